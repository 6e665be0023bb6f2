// ORB-SLAM2/3 settings files (OpenCV FileStorage YAML, both versions' keys).
#include "fuzz_input.h"
#include "lrd/config/orbslam_settings.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  const auto file = write_input("settings.yaml", {reinterpret_cast<const char*>(data), size});
  return guarded([&] { (void)lrd::config::read_orbslam_settings(file); });
}
