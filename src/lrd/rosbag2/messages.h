#pragma once
// The ROS 2 messages an RGB-D bag carries, laid out field for field as rosidl generates them, with
// their CDR encoding and decoding (a bag's records, a DDS sample) and their type names and .msg
// definitions (an MCAP schema). Decoding throws lrd::Error naming the field for a message shorter
// than its fields.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lrd::rosbag2::msg {

struct Time {  // builtin_interfaces/msg/Time
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};

struct Header {  // std_msgs/msg/Header
  Time stamp;
  std::string frame_id;
};

struct Image {  // sensor_msgs/msg/Image
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string encoding;
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;
  std::vector<std::uint8_t> data;
};

struct RegionOfInterest {  // sensor_msgs/msg/RegionOfInterest
  std::uint32_t x_offset = 0, y_offset = 0, height = 0, width = 0;
  bool do_rectify = false;
};

struct CameraInfo {  // sensor_msgs/msg/CameraInfo
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string distortion_model;
  std::vector<double> d;
  std::array<double, 9> k{}, r{};
  std::array<double, 12> p{};
  std::uint32_t binning_x = 0, binning_y = 0;
  RegionOfInterest roi;
};

struct Vector3 {  // geometry_msgs/msg/Vector3
  double x = 0.0, y = 0.0, z = 0.0;
};

struct Quaternion {  // geometry_msgs/msg/Quaternion
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
};

struct Transform {  // geometry_msgs/msg/Transform
  Vector3 translation;
  Quaternion rotation;
};

struct TransformStamped {  // geometry_msgs/msg/TransformStamped
  Header header;
  std::string child_frame_id;
  Transform transform;
};

struct TFMessage {  // tf2_msgs/msg/TFMessage
  std::vector<TransformStamped> transforms;
};

inline constexpr const char* kImageType = "sensor_msgs/msg/Image";
inline constexpr const char* kCameraInfoType = "sensor_msgs/msg/CameraInfo";
inline constexpr const char* kTfMessageType = "tf2_msgs/msg/TFMessage";

[[nodiscard]] std::vector<std::uint8_t> encode(const Image& m);
[[nodiscard]] std::vector<std::uint8_t> encode(const CameraInfo& m);
[[nodiscard]] std::vector<std::uint8_t> encode(const TFMessage& m);

[[nodiscard]] Image decode_image(const std::uint8_t* data, std::size_t size);
[[nodiscard]] CameraInfo decode_camera_info(const std::uint8_t* data, std::size_t size);
[[nodiscard]] TFMessage decode_tf_message(const std::uint8_t* data, std::size_t size);
// The header alone of any message that starts with one (an image's stamp without its pixels).
[[nodiscard]] Header decode_header(const std::uint8_t* data, std::size_t size);

// The type's definition as rosbag2 stores it in an MCAP schema (encoding "ros2msg"): its .msg
// text, then each type it uses after a line of 80 '=' and "MSG: package/Type". Throws lrd::Error
// for a type other than the three above.
[[nodiscard]] std::string definition(const std::string& type);

}  // namespace lrd::rosbag2::msg
