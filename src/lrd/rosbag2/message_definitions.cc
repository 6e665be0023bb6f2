// The .msg texts of the messages in messages.h, as their packages define them (the fields; the
// packages' comments left out), for an MCAP schema's ros2msg definition.
#include <map>
#include <string>
#include <vector>

#include "lrd/rosbag2/messages.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2::msg {

namespace {

const std::map<std::string, std::string>& msg_texts() {
  static const std::map<std::string, std::string> texts = {
      {"builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/msg/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
       "uint32 step\nuint8[] data\n"},
      {"sensor_msgs/msg/RegionOfInterest",
       "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\n"
       "float64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\n"
       "RegionOfInterest roi\n"},
      {"geometry_msgs/msg/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/msg/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/msg/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/msg/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"tf2_msgs/msg/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
  };
  return texts;
}

// Each type after the first in the order a depth-first walk of the fields meets it.
const std::map<std::string, std::vector<std::string>>& dependencies() {
  static const std::map<std::string, std::vector<std::string>> deps = {
      {kImageType, {"std_msgs/msg/Header", "builtin_interfaces/msg/Time"}},
      {kCameraInfoType,
       {"std_msgs/msg/Header", "builtin_interfaces/msg/Time", "sensor_msgs/msg/RegionOfInterest"}},
      {kTfMessageType,
       {"geometry_msgs/msg/TransformStamped", "std_msgs/msg/Header", "builtin_interfaces/msg/Time",
        "geometry_msgs/msg/Transform", "geometry_msgs/msg/Vector3", "geometry_msgs/msg/Quaternion"}},
  };
  return deps;
}

}  // namespace

std::string definition(const std::string& type) {
  const auto deps = dependencies().find(type);
  if (deps == dependencies().end()) throw lrd::Error("no message definition for " + type);
  std::string text = msg_texts().at(type);
  for (const std::string& dep : deps->second)
    text += std::string(80, '=') + "\nMSG: " + dep + "\n" + msg_texts().at(dep);
  return text;
}

}  // namespace lrd::rosbag2::msg
