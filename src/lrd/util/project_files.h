#pragma once
// Files shipped with the project (the vocabulary, FNet-lite) or cached by its setup (converted
// segmentation models), named relative to the project root.
#include <filesystem>

namespace lrd::util {

// Looks for `relative` under the working directory, $LRD_MODEL_ROOT, the source tree the library
// was built from, then the installed data folder (PREFIX/share/lrdslam); returns the source-tree
// path when none has it (so errors name where it belongs). Absolute paths come back unchanged.
[[nodiscard]] std::filesystem::path find_project_file(const std::filesystem::path& relative);

}  // namespace lrd::util
