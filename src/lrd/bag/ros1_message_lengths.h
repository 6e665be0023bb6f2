#pragma once
// The length prefixes of a ROS 1 serialized message, checked against its bytes before ROS's own
// deserializer reads it: that one sizes each string and array from its prefix before it reads the
// elements, so a prefix of 2^31 in a damaged bag allocates gigabytes (found by fuzzing
// `lrdslam run --bag`). Only what the bag reader instantiates: sensor_msgs/Image,
// sensor_msgs/CameraInfo, tf2_msgs/TFMessage (ROS 1's serialization: little-endian, no padding,
// uint32 lengths before strings and arrays). C++17: the ROS 1 code that calls it is.
#include <cstddef>
#include <cstdint>
#include <string>

namespace lrd::bag {

// Whether the message's strings and arrays fit in its bytes; else what does not ("D: 2147483648
// elements of 8 bytes where 12 bytes remain"). `datatype` is the ROS type name; other types pass.
[[nodiscard]] std::string ros1_length_problem(const std::string& datatype, const std::uint8_t* bytes,
                                              std::size_t size);

}  // namespace lrd::bag
