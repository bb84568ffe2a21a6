#include "kernel/files/atomic_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "hail/errors.h"

namespace hail::files {
namespace {

[[noreturn]] void refuse(const std::string& context, const std::string& path, const std::string& problem) {
  throw FileError("hail: " + context + path + ": " + problem);
}

std::string system_reason() { return std::strerror(errno); }

/// Writes all of `bytes` to `fd`; false (errno set) when a write fails or makes no progress.
bool write_all(int fd, std::span<const std::byte> bytes) {
  while (!bytes.empty()) {
    const ssize_t wrote = ::write(fd, bytes.data(), bytes.size());
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) {
      if (wrote == 0) errno = EIO;
      return false;
    }
    bytes = bytes.subspan(static_cast<std::size_t>(wrote));
  }
  return true;
}

/// A temporary file beside the target, removed unless committed.
class Temporary {
 public:
  explicit Temporary(std::string name) : name_(std::move(name)) {}
  ~Temporary() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(name_.c_str());
  }
  std::string name_;
  int fd_ = -1;
  bool committed_ = false;
};

}  // namespace

void write_file_atomically(const std::string& path, std::span<const std::byte> bytes, const std::string& context) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path target(path);
  if (fs::is_symlink(fs::symlink_status(target, error))) {  // replace the file it points to, not the link
    fs::path resolved = fs::weakly_canonical(target, error);
    if (!error) target = std::move(resolved);
  }
  struct stat old {};
  const bool exists = ::stat(target.c_str(), &old) == 0;
  if (exists && S_ISDIR(old.st_mode)) refuse(context, path, "is a directory");
  if (exists && (S_ISCHR(old.st_mode) || S_ISBLK(old.st_mode))) {
    const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) refuse(context, path, "cannot open the device (" + system_reason() + ")");
    const bool ok = write_all(fd, bytes);
    const std::string why = ok ? std::string() : system_reason();
    if (::close(fd) != 0 && ok) refuse(context, path, "closing it failed (" + system_reason() + ")");
    if (!ok) refuse(context, path, "a write failed (" + why + ")");
    return;
  }
  if (exists && !S_ISREG(old.st_mode)) refuse(context, path, "is not a regular file (a FIFO or socket)");
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  static std::atomic<unsigned> serial{0};
  // Hidden, named after the target; appended piece by piece (GCC 12 warns, wrongly, on the
  // chain of operator+ with -Wrestrict).
  std::string name = ".";
  name.append(target.filename().string())
      .append(".tmp-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(serial++));
  Temporary temporary((folder / name).string());
  temporary.fd_ = ::open(temporary.name_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (temporary.fd_ < 0) refuse(context, path, "cannot create " + temporary.name_ + " (" + system_reason() + ")");
  if (exists) (void)::fchmod(temporary.fd_, old.st_mode & 07777);
  if (!write_all(temporary.fd_, bytes)) refuse(context, path, "a write failed (" + system_reason() + ")");
  if (::fsync(temporary.fd_) != 0) refuse(context, path, "fsync failed (" + system_reason() + ")");
  const int fd = temporary.fd_;
  temporary.fd_ = -1;
  if (::close(fd) != 0) refuse(context, path, "closing it failed (" + system_reason() + ")");
  if (std::rename(temporary.name_.c_str(), target.c_str()) != 0)
    refuse(context, path, "cannot rename " + temporary.name_ + " over it (" + system_reason() + ")");
  temporary.committed_ = true;
  // The rename itself reaches the disk with the folder's entry; a failure here loses nothing.
  const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

}  // namespace hail::files
