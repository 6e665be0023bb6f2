#pragma once
// What every fuzz harness shares: the fuzzer's bytes as the file a reader opens (a scratch folder
// of this process), and the rule that a reader may refuse input only with lrd::Error — any other
// exception escaping it, like a crash or a sanitizer report, is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "lrd/util/error.h"

namespace lrd::fuzz {

// A folder of this process for the harness's files (removed at exit by the OS's tmp cleanup; the
// files are overwritten at each input).
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    auto d = std::filesystem::path(tmp != nullptr ? tmp : "/tmp") / ("lrd-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::filesystem::path write_input(const std::string& name, std::string_view bytes) {
  const std::filesystem::path file = scratch() / name;
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return file;
}

// The input cut at NUL bytes into at most n parts (the rest empty): one input, several files.
inline std::vector<std::string_view> split_parts(const std::uint8_t* data, std::size_t size, std::size_t n) {
  std::vector<std::string_view> parts(n);
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t at = i + 1 < n ? rest.find('\0') : std::string_view::npos;
    parts[i] = rest.substr(0, at);
    if (at == std::string_view::npos) break;
    rest.remove_prefix(at + 1);
  }
  return parts;
}

// Runs `read`; lrd::Error is a clean refusal, anything else aborts (the fuzzer reports it).
template <typename F>
int guarded(F&& read) {
  try {
    read();
  } catch (const lrd::Error&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: an exception other than lrd::Error escaped: %s\n", e.what());
    std::abort();
  }
  return 0;
}

}  // namespace lrd::fuzz
