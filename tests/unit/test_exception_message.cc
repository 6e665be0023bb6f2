// util::exception_message: whatever a worker or a library throws becomes one line, and running out
// of memory reads the same wherever it is hit.
#include <gtest/gtest.h>

#include <new>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <system_error>

#include "lrd/util/exception_message.h"
#include "lrd/util/thread_errors.h"

namespace {

using lrd::util::exception_message;

template <class E>
std::string message_of(const E& e) {
  return exception_message(std::make_exception_ptr(e));
}

TEST(ExceptionMessage, OutOfMemoryIsOneWordingWhereverItComesFrom) {
  EXPECT_EQ(message_of(std::bad_alloc()), "out of memory");
  EXPECT_EQ(message_of(std::bad_array_new_length()), "out of memory");
  EXPECT_EQ(message_of(
                cv::Exception(cv::Error::StsNoMem, "Failed to allocate 1228800 bytes", "f", "alloc.cpp", 73)),
            "out of memory");
  EXPECT_EQ(message_of(std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again))),
            "cannot start a thread (Resource temporarily unavailable): out of memory or too many threads");
}

TEST(ExceptionMessage, OtherErrorsKeepTheirMessageOnOneLine) {
  EXPECT_EQ(message_of(std::runtime_error("disk full")), "disk full");
  const std::string opencv = message_of(cv::Exception(cv::Error::StsBadArg, "bad size", "f", "file.cpp", 1));
  EXPECT_EQ(opencv, "OpenCV: bad size");
  EXPECT_EQ(exception_message(std::make_exception_ptr(42)), "unknown error");
  EXPECT_EQ(exception_message(nullptr), "unknown error");
}

TEST(ExceptionMessage, AThreadThatRunsOutOfMemoryIsNamedWithIt) {
  lrd::util::ThreadErrors errors;
  try {
    throw std::bad_alloc();
  } catch (...) {
    errors.capture("local mapping");
  }
  EXPECT_EQ(errors.message(), "local mapping thread: out of memory");
}

}  // namespace
