#pragma once
// Every file lrd-slam writes is written whole or not at all: the bytes go into a temporary beside
// the file (same folder, so the rename cannot cross file systems), every write is checked, and
// only a complete temporary is renamed over the file. A failed write (a full disk, a file-size
// limit, a read-only folder) throws one lrd::Error "FILE: cannot write (No space left on device)",
// removes the temporary and leaves a file that was already there as it was; a crash leaves at
// most a stray "FILE.<pid>-<n>.partial", never half a file.
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string_view>

namespace lrd::util {

// Whether commit() waits for the bytes to reach the disk (fsync of the file and its folder) before
// the rename. Yes keeps a power cut from leaving an empty file under the name; no (each fsync
// costs milliseconds) for the per-frame images, thousands of files that a rerun makes again.
enum class Sync : bool { no, yes };

class AtomicFile {
 public:
  // Creates the temporary (or, for an existing device such as /dev/null, opens it: it is written
  // straight through). Throws lrd::Error "FILE: cannot open for writing (reason)".
  explicit AtomicFile(std::filesystem::path file, Sync sync = Sync::yes);
  // Uncommitted: removes the temporary; the file is left as it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered; a failed write sets the stream's badbit and is reported by commit().
  [[nodiscard]] std::ostream& stream();
  void write(std::string_view bytes);
  // Flushes, syncs, closes and renames the temporary over the file; throws lrd::Error naming the
  // file when any of it fails (the temporary is then removed). Nothing may be written after it.
  void commit();

  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  // Where the bytes go until commit(): for a library that writes by name (sqlite3), which then
  // owns the contents; commit() still syncs and renames it.
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_; }

 private:
  class Buffer;
  void remove_temporary() noexcept;

  std::filesystem::path file_;       // as the caller named it (the errors name it)
  std::filesystem::path target_;     // what is replaced: the file, or where its symlink points
  std::filesystem::path temporary_;  // == target_ when writing straight into a device
  Sync sync_;
  bool direct_ = false;
  bool pending_ = true;  // the temporary is there, neither renamed nor removed
  bool committed_ = false;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
};

// The file as `write` streams it, written atomically as above.
void write_file_atomic(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write,
                       Sync sync = Sync::yes);

}  // namespace lrd::util
