#include "lrd/util/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <streambuf>
#include <system_error>

#include "lrd/util/error.h"

namespace lrd::util {

namespace fs = std::filesystem;

namespace {

std::string reason(int error) {
  return std::generic_category().message(error);
}

// A rename is durable only once the folder's entry is on the disk too. Some file systems cannot
// sync a folder; the file's own bytes are synced by then, so that is no error.
void sync_folder(const fs::path& folder) noexcept {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  (void)::close(fd);
}

}  // namespace

// The stream's buffer over the file descriptor: unlike std::filebuf it keeps the errno of the
// first failed write, so the error can say why (a full disk, a file-size limit).
class AtomicFile::Buffer final : public std::streambuf {
 public:
  explicit Buffer(int fd) : fd_(fd) { setp(data_.data(), data_.data() + data_.size()); }
  ~Buffer() override {
    if (fd_ >= 0) (void)::close(fd_);
  }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  [[nodiscard]] int fd() const { return fd_; }
  [[nodiscard]] int error() const { return error_; }
  void fail(int error) {
    if (error_ == 0) error_ = error;
  }
  // Writes out what is buffered; false once any write failed.
  bool drain() {
    const auto n = static_cast<std::size_t>(pptr() - pbase());
    setp(data_.data(), data_.data() + data_.size());
    return write_all(data_.data(), n);
  }
  // Closes the descriptor, keeping close()'s error (NFS reports some write errors only there).
  void close() {
    if (fd_ < 0) return;
    if (::close(fd_) != 0) fail(errno);
    fd_ = -1;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (error_ != 0 || n <= 0) return 0;
    const auto size = static_cast<std::size_t>(n);
    if (size <= static_cast<std::size_t>(epptr() - pptr())) {
      std::memcpy(pptr(), s, size);
      pbump(static_cast<int>(size));
      return n;
    }
    if (!drain()) return 0;
    // A large block goes straight out rather than through the buffer.
    if (size >= data_.size()) return write_all(s, size) ? n : 0;
    std::memcpy(pptr(), s, size);
    pbump(static_cast<int>(size));
    return n;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool write_all(const char* p, std::size_t n) {
    if (error_ != 0) return false;
    if (fd_ < 0) fail(EBADF);
    while (n > 0 && error_ == 0) {
      const ssize_t written = ::write(fd_, p, n);
      if (written < 0) {
        if (errno != EINTR) fail(errno);
        continue;
      }
      if (written == 0) fail(EIO);
      p += written;
      n -= static_cast<std::size_t>(written);
    }
    return error_ == 0;
  }

  std::array<char, 64 * 1024> data_{};
  int fd_;
  int error_ = 0;
};

AtomicFile::AtomicFile(fs::path file, Sync sync) : file_(std::move(file)), target_(file_), sync_(sync) {
  std::error_code ec;
  // Through a symlink the file it points to is replaced, not the link.
  if (fs::is_symlink(fs::symlink_status(file_, ec))) {
    fs::path resolved = fs::canonical(file_, ec);
    if (!ec) target_ = std::move(resolved);
  }
  const fs::file_status status = fs::status(target_, ec);
  if (fs::is_directory(status))
    throw file_error(file_, fmt::format("cannot open for writing ({})", reason(EISDIR)));
  int fd = -1;
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device or pipe (/dev/null, /dev/stdout) cannot be replaced: it is written into.
    direct_ = true;
    temporary_ = target_;
    fd = ::open(target_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  } else {
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
      temporary_ = target_;
      temporary_ += fmt::format(".{}-{}.partial", ::getpid(), counter.fetch_add(1));
      fd = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0 || errno != EEXIST) break;  // else a stray one of an earlier process with our pid
    }
    // The replacement keeps the permissions of the file it replaces.
    struct stat old {};
    if (fd >= 0 && ::stat(target_.c_str(), &old) == 0) (void)::fchmod(fd, old.st_mode & 07777);
  }
  if (fd < 0) throw file_error(file_, fmt::format("cannot open for writing ({})", reason(errno)));
  buffer_ = std::make_unique<Buffer>(fd);
  stream_ = std::make_unique<std::ostream>(buffer_.get());
}

AtomicFile::~AtomicFile() {
  remove_temporary();
}

std::ostream& AtomicFile::stream() {
  return *stream_;
}

void AtomicFile::write(std::string_view bytes) {
  stream_->write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void AtomicFile::remove_temporary() noexcept {
  if (!pending_) return;
  pending_ = false;
  buffer_->close();
  if (!direct_) (void)::unlink(temporary_.c_str());
}

void AtomicFile::commit() {
  if (committed_) return;
  if (!pending_) throw file_error(file_, "cannot write");  // an earlier commit() failed
  const bool flushed = static_cast<bool>(stream_->flush());
  // fsync of a device is meaningless (and fails with EINVAL for some).
  if (sync_ == Sync::yes && !direct_ && buffer_->error() == 0 && ::fsync(buffer_->fd()) != 0 &&
      errno != EINVAL)
    buffer_->fail(errno);
  buffer_->close();
  if (buffer_->error() != 0 || !flushed || !stream_->good()) {
    const int error = buffer_->error();
    remove_temporary();
    throw file_error(file_, error != 0 ? fmt::format("cannot write ({})", reason(error)) : "cannot write");
  }
  if (!direct_) {
    if (::rename(temporary_.c_str(), target_.c_str()) != 0) {
      const int error = errno;
      remove_temporary();
      throw file_error(file_, fmt::format("cannot replace the file ({})", reason(error)));
    }
    if (sync_ == Sync::yes) sync_folder(target_.parent_path());
  }
  pending_ = false;
  committed_ = true;
}

void write_file_atomic(const fs::path& file, const std::function<void(std::ostream&)>& write, Sync sync) {
  AtomicFile out(file, sync);
  write(out.stream());
  out.commit();
}

}  // namespace lrd::util
