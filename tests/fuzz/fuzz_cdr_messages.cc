// ROS 2 messages' CDR (what bags and DDS samples carry): the first byte picks the type.
#include "fuzz_input.h"
#include "lrd/rosbag2/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lrd::fuzz;
  namespace msg = lrd::rosbag2::msg;
  if (size == 0) return 0;
  const std::uint8_t* body = data + 1;
  const std::size_t n = size - 1;
  return guarded([&] {
    switch (data[0] % 4) {
      case 0:
        (void)msg::decode_image(body, n);
        break;
      case 1:
        (void)msg::decode_camera_info(body, n);
        break;
      case 2:
        (void)msg::decode_tf_message(body, n);
        break;
      default:
        (void)msg::decode_header(body, n);
    }
  });
}
