#pragma once
// The one exception type lrd-slam throws for bad input. Its message is a single line that names
// the file (and line, where there is one) and the problem, so the CLI can print it verbatim.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace lrd {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// "FILE: problem"
[[nodiscard]] inline Error file_error(const std::filesystem::path& file, const std::string& problem) {
  return Error(file.string() + ": " + problem);
}

// "FILE:LINE: problem"
[[nodiscard]] inline Error line_error(const std::filesystem::path& file, std::size_t line,
                                      const std::string& problem) {
  return Error(file.string() + ":" + std::to_string(line) + ": " + problem);
}

}  // namespace lrd
