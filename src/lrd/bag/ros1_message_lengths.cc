#include "lrd/bag/ros1_message_lengths.h"

#include <fmt/format.h>

#include "lrd/util/binary_io.h"

namespace lrd::bag {

namespace {

// Walks the message's fields; the first that does not fit is the problem.
class Lengths {
 public:
  Lengths(const std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}
  [[nodiscard]] const std::string& problem() const { return problem_; }

  // `n` fixed bytes.
  bool skip(std::uint64_t n, const char* field) {
    if (!problem_.empty()) return false;
    if (n > left()) {
      problem_ = fmt::format("{}: {} bytes where {} remain", field, n, left());
      return false;
    }
    at_ += n;
    return true;
  }
  // A uint32 count, then that many elements of `element` bytes (a string: 1); returns the count.
  std::uint64_t array(std::uint64_t element, const char* field) {
    if (!problem_.empty()) return 0;
    if (left() < 4) {
      problem_ = fmt::format("{}: its length past the message's end", field);
      return 0;
    }
    const std::uint64_t n = util::get_u32(bytes_ + at_);
    at_ += 4;
    if (n * element > left()) {
      problem_ = fmt::format("{}: {} elements of {} bytes where {} bytes remain", field, n, element, left());
      return 0;
    }
    at_ += n * element;
    return n;
  }
  void header() {
    skip(4 + 8, "header.seq/stamp");
    array(1, "header.frame_id");
  }

 private:
  [[nodiscard]] std::uint64_t left() const { return size_ - at_; }
  const std::uint8_t* bytes_;
  std::size_t size_;
  std::uint64_t at_ = 0;
  std::string problem_;
};

}  // namespace

std::string ros1_length_problem(const std::string& datatype, const std::uint8_t* bytes, std::size_t size) {
  Lengths m(bytes, size);
  if (datatype == "sensor_msgs/Image") {
    m.header();
    m.skip(8, "height/width");
    m.array(1, "encoding");
    m.skip(1 + 4, "is_bigendian/step");
    m.array(1, "data");
  } else if (datatype == "sensor_msgs/CameraInfo") {
    m.header();
    m.skip(8, "height/width");
    m.array(1, "distortion_model");
    m.array(8, "D");
    m.skip((9 + 9 + 12) * 8 + 4 + 4 + 4 * 4 + 1, "K/R/P/binning/roi");
  } else if (datatype == "tf2_msgs/TFMessage") {
    const std::uint64_t n = m.array(0, "transforms");  // counted below, element by element
    for (std::uint64_t i = 0; i < n && m.problem().empty(); ++i) {
      m.header();
      m.array(1, "child_frame_id");
      m.skip(7 * 8, "transform");
    }
  }
  return m.problem();
}

}  // namespace lrd::bag
