#include "lrd/util/project_files.h"

#include <cstdlib>
#include <system_error>
#include <vector>

namespace lrd::util {

namespace fs = std::filesystem;

fs::path find_project_file(const fs::path& relative) {
  if (relative.is_absolute()) return relative;
  std::vector<fs::path> roots{fs::path{}};
  if (const char* env = std::getenv("LRD_MODEL_ROOT"); env != nullptr && *env != '\0')
    roots.emplace_back(env);
  fs::path source_root;
#ifdef LRD_SOURCE_DIR
  source_root = LRD_SOURCE_DIR;
  roots.push_back(source_root);
#endif
#ifdef LRD_INSTALLED_DATA_DIR
  roots.emplace_back(LRD_INSTALLED_DATA_DIR);
#endif
  std::error_code ec;
  for (const fs::path& root : roots)
    if (fs::is_regular_file(root / relative, ec)) return root / relative;
  return source_root / relative;
}

}  // namespace lrd::util
