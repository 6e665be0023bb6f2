// ROS 1 messages' length prefixes checked against their bytes before ROS's deserializer sizes
// anything from them (bag/ros1_message_lengths.h).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "lrd/bag/ros1_message_lengths.h"

namespace lrd::bag {
namespace {

struct Bytes {
  std::vector<std::uint8_t> b;
  Bytes& u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    return *this;
  }
  Bytes& zeros(std::size_t n) {
    b.insert(b.end(), n, 0);
    return *this;
  }
  Bytes& str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    b.insert(b.end(), s.begin(), s.end());
    return *this;
  }
  Bytes& header() { return u32(7).zeros(8).str("rgb"); }
  [[nodiscard]] std::string problem(const std::string& type) const {
    return ros1_length_problem(type, b.data(), b.size());
  }
};

Bytes camera_info(std::uint32_t distortion_count, std::size_t doubles_present) {
  Bytes m;
  m.header().u32(480).u32(640).str("plumb_bob").u32(distortion_count).zeros(8 * doubles_present);
  return m.zeros((9 + 9 + 12) * 8 + 4 + 4 + 4 * 4 + 1);
}

TEST(Ros1MessageLengths, WellFormedMessagesPass) {
  EXPECT_EQ(camera_info(5, 5).problem("sensor_msgs/CameraInfo"), "");
  Bytes image;
  image.header().u32(2).u32(3).str("mono8").zeros(1).u32(3).u32(6).zeros(6);
  EXPECT_EQ(image.problem("sensor_msgs/Image"), "");
  Bytes tf;
  tf.u32(2);
  for (int i = 0; i < 2; ++i) tf.header().str("kinect").zeros(7 * 8);
  EXPECT_EQ(tf.problem("tf2_msgs/TFMessage"), "");
  EXPECT_EQ(Bytes{}.problem("std_msgs/String"), "");  // types the reader does not instantiate pass
}

TEST(Ros1MessageLengths, APrefixPastTheBytesIsNamed) {
  // 2^31 distortion coefficients: ROS's deserializer would allocate 16 GiB before reading them.
  EXPECT_EQ(camera_info(0x80000000u, 5).problem("sensor_msgs/CameraInfo"),
            "D: 2147483648 elements of 8 bytes where 305 bytes remain");
  Bytes image;
  image.header().u32(2).u32(3).str("mono8").zeros(1).u32(3).u32(0xffffffffu).zeros(6);
  EXPECT_EQ(image.problem("sensor_msgs/Image"), "data: 4294967295 elements of 1 bytes where 6 bytes remain");
  Bytes cut;
  cut.header().u32(2);
  EXPECT_EQ(cut.problem("sensor_msgs/Image"), "height/width: 8 bytes where 4 remain");
  // A count of transforms the bytes cannot hold: found at the first that does not fit.
  Bytes tf;
  tf.u32(1000000).header();
  EXPECT_EQ(tf.problem("tf2_msgs/TFMessage"), "child_frame_id: its length past the message's end");
}

}  // namespace
}  // namespace lrd::bag
