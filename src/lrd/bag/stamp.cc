#include "lrd/bag/stamp.h"

#include <fmt/format.h>

#include <cstdlib>
#include <string>

#include "lrd/util/error.h"

namespace lrd::bag {

double to_seconds(const Stamp& stamp) {
  const std::int64_t sec = stamp.sec + stamp.nanosec / 1000000000u;
  const std::string text = fmt::format("{}.{:09d}", sec, stamp.nanosec % 1000000000u);
  return std::strtod(text.c_str(), nullptr);
}

Stamp to_stamp(double seconds) {
  if (!(seconds >= 0.0) || seconds > 2.1e9)
    throw lrd::Error(fmt::format("timestamp {} is not a ROS time", seconds));
  const std::string text = fmt::format("{:.6f}", seconds);
  const std::size_t dot = text.find('.');
  Stamp t;
  t.sec = std::strtoll(text.substr(0, dot).c_str(), nullptr, 10);
  t.nanosec = static_cast<std::uint32_t>(std::strtoul(text.substr(dot + 1).c_str(), nullptr, 10) * 1000);
  return t;
}

std::int64_t to_nanoseconds(const Stamp& stamp) {
  return stamp.sec * 1000000000 + static_cast<std::int64_t>(stamp.nanosec);
}

}  // namespace lrd::bag
