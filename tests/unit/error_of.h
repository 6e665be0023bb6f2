#pragma once
// The message of the lrd::Error a callable throws, for tests of one-line error messages.
#include <gtest/gtest.h>

#include <string>

#include "lrd/util/error.h"

namespace lrd::test {

// "" and a test failure when `f` throws no lrd::Error.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const lrd::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no lrd::Error thrown";
  return "";
}

}  // namespace lrd::test
