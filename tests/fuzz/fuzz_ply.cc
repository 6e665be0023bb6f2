// PLY point clouds (the dense map; `lrdslam eval-map` reads the reference scene's).
#include "fuzz_input.h"
#include "lrd/dense/ply_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const auto file = write_input("cloud.ply", {reinterpret_cast<const char*>(data), size});
  return guarded([&] { (void)lrd::dense::read_ply(file); });
}
