// Publishes what a misbehaving ROS 2 camera driver might, on the node's default input topics, for
// the node's bad-input test (tests/python/test_ros2_node.py): a 64x48 camera_info, then pairs
// (colour rgb8, depth 32FC1) broken one way each, then a publisher of the wrong type on the colour
// topic. Waits for the node's readers first; exits when everything is sent.
//   lrdslam_ros2_test_publisher   (ROS_DOMAIN_ID and ROS_LOCALHOST_ONLY as the node's)
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "endpoints.h"
#include "messages.h"
#include "participant.h"
#include "sensor_msgs.h"
#include "std_msgs.h"

namespace {

using namespace lrd_ros2;
constexpr std::uint32_t kWidth = 64, kHeight = 48;

struct Pair {
  std::string colour_encoding = "rgb8";
  std::uint32_t width = kWidth, height = kHeight;
  std::size_t colour_bytes = 0;  // 0: what the size needs
};

void send_pair(Writer<sensor_msgs_msg_dds__Image_>& rgb, Writer<sensor_msgs_msg_dds__Image_>& depth,
               const Pair& p, double stamp) {
  lrd::bag::ImagePixels c{
      p.width, p.height, p.colour_encoding, p.width * 3,
      std::vector<std::uint8_t>(p.colour_bytes > 0 ? p.colour_bytes : p.width * p.height * 3, 128)};
  lrd::bag::ImagePixels d{p.width, p.height, "32FC1", p.width * 4,
                          std::vector<std::uint8_t>(p.width * p.height * 4)};
  const float one = 1.0f;
  for (std::size_t i = 0; i < d.data.size(); i += 4) std::memcpy(&d.data[i], &one, 4);
  const std::string frame = "camera";
  depth.write(image_message(d, stamp, frame));
  rgb.write(image_message(c, stamp, frame));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
}

}  // namespace

int main() {
  try {
    Participant participant(domain_from_environment());
    Writer<sensor_msgs_msg_dds__Image_> rgb(participant, dds_topic_name("/camera/rgb/image_color"),
                                            &sensor_msgs_msg_dds__Image__desc, default_qos(10));
    Writer<sensor_msgs_msg_dds__Image_> depth(participant, dds_topic_name("/camera/depth/image"),
                                              &sensor_msgs_msg_dds__Image__desc, default_qos(10));
    Writer<sensor_msgs_msg_dds__CameraInfo_> info(participant, dds_topic_name("/camera/rgb/camera_info"),
                                                  &sensor_msgs_msg_dds__CameraInfo__desc, default_qos(10));
    if (!rgb.wait_for_reader(30) || !depth.wait_for_reader(5) || !info.wait_for_reader(5)) {
      std::fprintf(stderr, "test_publisher: no subscriber\n");
      return 1;
    }
    sensor_msgs_msg_dds__CameraInfo_ ci{};
    const std::string frame = "camera", model = "plumb_bob";
    ci.header = header(1.0, frame);
    ci.width = kWidth;
    ci.height = kHeight;
    ci.distortion_model = text(model);
    const double k[9] = {50, 0, 32, 0, 50, 24, 0, 0, 1};
    std::copy(k, k + 9, ci.k);
    info.write(ci);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));

    double stamp = 10.0;
    Pair yuv;
    yuv.colour_encoding = "yuv422";
    Pair truncated;
    truncated.colour_bytes = kWidth * kHeight * 3 - 100;
    Pair bigger;
    bigger.width = 80;
    bigger.height = 60;
    for (const Pair* p : {&yuv, &yuv, &truncated, &truncated, &bigger, &bigger})
      send_pair(rgb, depth, *p, stamp += 1.0);

    // A driver publishing compressed frames' text on the raw topic: another type, never matched.
    // (A participant of its own: one participant has one type per topic name.)
    Participant other(domain_from_environment());
    Writer<std_msgs_msg_dds__String_> wrong(other, dds_topic_name("/camera/rgb/image_color"),
                                            &std_msgs_msg_dds__String__desc, default_qos(10));
    const std::string hello = "not an image";
    std_msgs_msg_dds__String_ s{text(hello)};
    wrong.write(s);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    std::printf("test_publisher: sent\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "test_publisher: %s\n", e.what());
    return 1;
  }
  return 0;
}
