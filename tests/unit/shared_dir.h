#pragma once
// Where the tests find ../shared (real models and photos): $LRD_SHARED_DIR, else beside the
// source tree. Tests that need it skip when it is absent.
#include <cstdlib>
#include <filesystem>

namespace lrd::test {

inline std::filesystem::path shared_dir() {
  const char* env = std::getenv("LRD_SHARED_DIR");
  return (env != nullptr && *env != '\0') ? std::filesystem::path(env)
                                          : std::filesystem::path(LRD_SOURCE_DIR) / ".." / "shared";
}

}  // namespace lrd::test
