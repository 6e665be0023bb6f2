#pragma once
// One line for whatever a worker or a library threw, so that an error reaches the user as one
// line wherever it was raised: std::bad_alloc (and OpenCV's own out-of-memory error) is "out of
// memory", so a memory limit reads the same wherever it is hit; a thread that cannot be started
// says so; OpenCV's errors are "OpenCV: <message>" without their multi-line header.
#include <exception>
#include <string>

namespace lrd::util {

// Never throws: with no memory left even for the message, "out of memory".
[[nodiscard]] std::string exception_message(const std::exception_ptr& error) noexcept;

}  // namespace lrd::util
