// The .msg texts of the messages in messages.h, as their packages define them (the fields; the
// packages' comments left out), for an MCAP schema's ros2msg definition laid out as rosbag2 lays
// it out: each used type after a blank line, 80 '=' and "MSG: package/Type" as the fields name it.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "lrd/rosbag2/messages.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2::msg {

namespace {

// Each type by the name its users' fields give it (package/Type), with its text and the types
// its fields use, sorted (as rosbag2 orders them).
struct Msg {
  const char* text;
  std::vector<std::string> uses;
};

const std::map<std::string, Msg>& msgs() {
  static const std::map<std::string, Msg> all = {
      {"builtin_interfaces/Time", {"int32 sec\nuint32 nanosec\n", {}}},
      {"std_msgs/Header", {"builtin_interfaces/Time stamp\nstring frame_id\n", {"builtin_interfaces/Time"}}},
      {"sensor_msgs/Image",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
        "uint32 step\nuint8[] data\n",
        {"std_msgs/Header"}}},
      {"sensor_msgs/RegionOfInterest",
       {"uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n", {}}},
      {"sensor_msgs/CameraInfo",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\n"
        "float64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\n"
        "RegionOfInterest roi\n",
        {"sensor_msgs/RegionOfInterest", "std_msgs/Header"}}},
      {"geometry_msgs/Vector3", {"float64 x\nfloat64 y\nfloat64 z\n", {}}},
      {"geometry_msgs/Quaternion", {"float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n", {}}},
      {"geometry_msgs/Transform",
       {"Vector3 translation\nQuaternion rotation\n", {"geometry_msgs/Quaternion", "geometry_msgs/Vector3"}}},
      {"geometry_msgs/TransformStamped",
       {"std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
        {"geometry_msgs/Transform", "std_msgs/Header"}}},
      {"tf2_msgs/TFMessage",
       {"geometry_msgs/TransformStamped[] transforms\n", {"geometry_msgs/TransformStamped"}}},
  };
  return all;
}

// The type's text, then each type it uses not yet written, depth first.
std::string full_text(const std::string& name, std::set<std::string>& written) {
  const Msg& m = msgs().at(name);
  std::string text = m.text;
  for (const std::string& use : m.uses)
    if (written.insert(use).second)
      text += "\n" + std::string(80, '=') + "\nMSG: " + use + "\n" + full_text(use, written);
  return text;
}

}  // namespace

std::string definition(const std::string& type) {
  if (type != kImageType && type != kCameraInfoType && type != kTfMessageType)
    throw lrd::Error("no message definition for " + type);
  const std::size_t slash = type.find("/msg/");
  std::set<std::string> written;
  return full_text(type.substr(0, slash) + "/" + type.substr(slash + 5), written);
}

}  // namespace lrd::rosbag2::msg
