#include "scenes/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace hail::bench {
namespace {

namespace fs = std::filesystem;

fs::path folder_of(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

/// ": <the system's reason>" for the last failed call, or nothing where errno says nothing.
std::string system_reason() { return errno != 0 ? std::string(": ") + std::strerror(errno) : ""; }

/// Creates and removes a file in `folder`: empty if that worked, else the system's reason.
std::string probe_folder(const fs::path& folder) {
  std::string name = (folder / ".hail-bench-probe-XXXXXX").string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(name.c_str());
  return "";
}

bool is_special_file(const fs::path& p) {  // a device, pipe or socket: written in place
  std::error_code ec;
  const fs::file_status st = fs::status(p, ec);
  return fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st);
}

/// Why `path` cannot be written, or empty if it can.
std::string why_unwritable(const std::string& path) {
  const fs::path p(path);
  if (path.empty() || !p.has_filename()) return "it names a folder, not a file";
  std::error_code ec;
  const fs::file_status st = fs::status(p, ec);
  if (fs::is_directory(st)) return "it is a folder";
  if (is_special_file(p)) return ::access(path.c_str(), W_OK) == 0 ? "" : std::strerror(errno);
  const fs::path folder = folder_of(p);
  const fs::file_status folder_status = fs::status(folder, ec);
  if (!fs::exists(folder_status)) return "the folder " + folder.string() + " does not exist";
  if (!fs::is_directory(folder_status)) return folder.string() + " is not a folder";
  if (fs::exists(st) && ::access(path.c_str(), W_OK) != 0) return std::strerror(errno);
  const std::string probe = probe_folder(folder);
  return probe.empty() ? "" : "no file can be created in " + folder.string() + " (" + probe + ")";
}

fs::path canonical_or_absolute(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(path, ec);
  return ec ? fs::absolute(path, ec).lexically_normal() : p;
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool same = fs::equivalent(a, b, ec);
    if (!ec) return same;
  }
  return canonical_or_absolute(a) == canonical_or_absolute(b);
}

void check_output_paths(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::string& out = outputs[k];
    if (out.empty()) continue;
    // /dev/null or /dev/stdout may well be named twice; only files can be clobbered.
    if (!is_special_file(out)) {
      for (const std::string& in : inputs)
        if (!in.empty() && same_file(out, in))
          throw std::invalid_argument("refusing to write " + out + ": it is the input " + in +
                                      ", which it would overwrite");
      for (std::size_t j = 0; j < k; ++j)
        if (!outputs[j].empty() && same_file(out, outputs[j]))
          throw std::invalid_argument("two outputs name the same file: " + outputs[j] + " and " + out);
    }
    const std::string why = why_unwritable(out);
    if (!why.empty()) throw std::invalid_argument("cannot write " + out + ": " + why);
  }
}

void prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::invalid_argument("cannot create the output folder " + dir + ": " + ec.message());
  if (!fs::is_directory(dir, ec)) throw std::invalid_argument("cannot write into " + dir + ": it is not a folder");
  const std::string probe = probe_folder(dir);
  if (!probe.empty()) throw std::invalid_argument("cannot write into " + dir + ": " + probe);
}

AtomicOutputFile::AtomicOutputFile(std::string path) : path_(std::move(path)), target_(path_) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {  // replace the file it points to, not the link
    const fs::path resolved = fs::weakly_canonical(target_, ec);
    if (!ec) target_ = resolved.string();
  }
  if (fs::is_directory(target_, ec)) fail("it is a folder");
  if (is_special_file(target_)) {
    temporary_ = target_;
  } else {
    static std::atomic<unsigned> serial{0};
    const fs::path t(target_);
    std::string name = ".";  // hidden, and named after the target; appended piece by piece (GCC 12's -Wrestrict)
    name.append(t.filename().string())
        .append(".tmp-")
        .append(std::to_string(::getpid()))
        .append("-")
        .append(std::to_string(serial++));
    temporary_ = (folder_of(t) / name).string();
  }
  errno = 0;
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) fail("cannot create " + temporary_ + system_reason());
  if (temporary_ != target_ && fs::exists(target_, ec))  // the new file keeps the old one's permissions
    fs::permissions(temporary_, fs::status(target_, ec).permissions(), ec);
}

AtomicOutputFile::~AtomicOutputFile() {
  if (done_) return;
  out_.close();
  if (temporary_ != target_) ::unlink(temporary_.c_str());
}

void AtomicOutputFile::fail(const std::string& what) {
  const std::string message = "cannot write " + path_ + ": " + what;
  out_.close();
  if (!temporary_.empty() && temporary_ != target_) ::unlink(temporary_.c_str());
  done_ = true;
  throw std::runtime_error(message);
}

void AtomicOutputFile::flush() {
  if (!out_) fail("a write failed" + system_reason());  // errno still the failed write's
  errno = 0;
  if (!out_.flush()) fail("a write failed" + system_reason());
}

void AtomicOutputFile::commit() {
  flush();
  errno = 0;
  out_.close();
  if (out_.fail()) fail("closing it failed" + system_reason());
  // To the disk before the rename, so that a crash after it cannot leave an empty new file in
  // the old one's place (a descriptor opened for reading may fsync the file's data).
  if (temporary_ != target_) {
    errno = 0;
    const int fd = ::open(temporary_.c_str(), O_RDONLY | O_CLOEXEC);
    const bool synced = fd >= 0 && ::fsync(fd) == 0;
    const std::string why = system_reason();
    if (fd >= 0) ::close(fd);
    if (!synced) fail("fsync failed" + why);
  }
  errno = 0;
  if (temporary_ != target_ && std::rename(temporary_.c_str(), target_.c_str()) != 0)
    fail("cannot rename " + temporary_ + " over it" + system_reason());
  done_ = true;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  AtomicOutputFile file(path);
  write(file.stream());
  file.commit();
}

}  // namespace hail::bench
