// The image and camera_info checks both ROS nodes and all bag readers use (lrd/bag): an image's
// fields (size, step, encoding, byte order) against its data, and a camera_info's calibration.
#include <cstring>

#include "fuzz_input.h"
#include "lrd/bag/camera_info.h"
#include "lrd/bag/image_pixels.h"

namespace {

template <typename T>
T take(const std::uint8_t*& p, std::size_t& n) {
  T v{};
  const std::size_t k = std::min(sizeof(T), n);
  std::memcpy(&v, p, k);
  p += k;
  n -= k;
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  static const char* encodings[] = {"rgb8",  "bgr8",  "rgba8",  "bgra8", "mono8",
                                    "32FC1", "16UC1", "yuv422", ""};
  const std::uint8_t* p = data;
  std::size_t n = size;
  lrd::bag::ImageView v;
  // Sizes kept small so a header cannot ask for gigabytes of pixels the input does not hold.
  v.width = take<std::uint16_t>(p, n) % 4096;
  v.height = take<std::uint16_t>(p, n) % 4096;
  v.step = take<std::uint32_t>(p, n);
  v.is_bigendian = take<std::uint8_t>(p, n);
  v.encoding = encodings[take<std::uint8_t>(p, n) % std::size(encodings)];
  lrd::bag::CameraCalibration c;
  c.width = take<std::uint16_t>(p, n);
  c.height = take<std::uint16_t>(p, n);
  c.distortion_model = take<std::uint8_t>(p, n) % 2 == 0 ? "plumb_bob" : "rational_polynomial";
  c.d.resize(take<std::uint8_t>(p, n) % 10);
  for (double& d : c.d) d = take<double>(p, n);
  for (double& k : c.k) k = take<double>(p, n);
  v.data = p;
  v.size = n;
  guarded([&] { (void)lrd::bag::colour_from_image(v); });
  guarded([&] { (void)lrd::bag::depth_from_image(v); });
  return guarded([&] { (void)lrd::bag::camera_from_calibration(c); });
}
