#include "lrd/util/binary_io.h"

#include <fstream>
#include <system_error>

namespace lrd::util {

namespace fs = std::filesystem;

std::string read_file_bytes(const fs::path& file, const std::string& kind) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw file_error(file, "no such " + kind + " file");
  if (!fs::is_regular_file(file, ec)) throw file_error(file, "not a regular file");
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw file_error(file, "cannot open the " + kind + " file");
  const std::streamoff size = in.tellg();
  if (size < 0) throw file_error(file, "cannot read the " + kind + " file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (size > 0) in.read(bytes.data(), size);
  if (size > 0 && in.gcount() != size) throw file_error(file, "cannot read the " + kind + " file");
  return bytes;
}

void write_file_bytes(const fs::path& file, std::string_view bytes, Sync sync) {
  AtomicFile out(file, sync);
  out.write(bytes);
  out.commit();
}

}  // namespace lrd::util
