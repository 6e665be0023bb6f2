#include "lrd/util/exception_message.h"

#include <fmt/format.h>

#include <new>
#include <opencv2/core.hpp>
#include <system_error>

namespace lrd::util {

namespace {

std::string describe(const std::exception_ptr& error) {
  try {
    if (error) std::rethrow_exception(error);
  } catch (const std::bad_alloc&) {
    return "out of memory";
  } catch (const cv::Exception& e) {
    if (e.code == cv::Error::StsNoMem) return "out of memory";
    return fmt::format("OpenCV: {}", e.err);
  } catch (const std::system_error& e) {
    // What std::thread throws when pthread_create finds no memory for the stack (or a thread limit).
    if (e.code() == std::errc::resource_unavailable_try_again)
      return fmt::format("cannot start a thread ({}): out of memory or too many threads", e.code().message());
    return e.what();
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
  return "unknown error";
}

}  // namespace

std::string exception_message(const std::exception_ptr& error) noexcept {
  try {
    return describe(error);
  } catch (...) {
    // No memory left even for the message; this one fits std::string's own buffer (no allocation).
    return "out of memory";
  }
}

}  // namespace lrd::util
