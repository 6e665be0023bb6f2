// TUM list files: rgb.txt, depth.txt, associations.txt and groundtruth.txt (the input's parts
// between NUL bytes, in that order; an empty associations part leaves the file out).
#include "fuzz_input.h"
#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const auto parts = split_parts(data, size, 4);
  const auto dir = scratch() / "tum";
  std::filesystem::create_directories(dir);
  write_input("tum/rgb.txt", parts[0]);
  write_input("tum/depth.txt", parts[1]);
  if (parts[2].empty())
    std::filesystem::remove(dir / "associations.txt");
  else
    write_input("tum/associations.txt", parts[2]);
  const auto gt = write_input("tum/groundtruth.txt", parts[3]);
  guarded([&] { (void)lrd::io::TumSequence::open(dir); });
  return guarded([&] { (void)lrd::io::read_trajectory_tum(gt); });
}
