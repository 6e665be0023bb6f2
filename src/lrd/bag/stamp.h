#pragma once
// Message stamps (seconds + nanoseconds, as ROS 1 and ROS 2 headers carry them) to and from the
// double seconds lrd-slam works with.
#include <cstdint>

namespace lrd::bag {

struct Stamp {
  std::int64_t sec = 0;
  std::uint32_t nanosec = 0;  // a message may carry >= 1e9; to_seconds normalises
};

// A stamp as seconds, exactly as the TUM text files' "%.6f" stamps parse: the decimal digits of
// sec.nsec are read as one number (a sum sec + 1e-9 * nsec can round differently), so a frame
// read from a bag has the same double timestamp as from the folder made of the same bag.
[[nodiscard]] double to_seconds(const Stamp& stamp);
// Seconds (TUM layout: microseconds) as a stamp, through the same "%.6f" text; throws lrd::Error
// for a negative or implausible time.
[[nodiscard]] Stamp to_stamp(double seconds);
// Nanoseconds since the epoch (rosbag2's record times, exact comparisons of tf stamps).
[[nodiscard]] std::int64_t to_nanoseconds(const Stamp& stamp);

}  // namespace lrd::bag
