#include "kernel/files/regular_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

#include "hail/errors.h"

namespace hail::files {
namespace {

[[noreturn]] void refuse(const std::string& context, const std::string& path, const std::string& problem) {
  throw FileError("hail: " + context + path + ": " + problem);
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

void require_regular_file(const std::string& path, const std::string& context, const std::string& kind) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) refuse(context, path, "cannot open file (no such file)");
  if (error) refuse(context, path, "cannot open file (" + error.message() + ")");
  switch (status.type()) {
    case fs::file_type::regular:
      return;
    case fs::file_type::directory:
      refuse(context, path, "is a directory, not " + kind);
    case fs::file_type::fifo:
      refuse(context, path, "is a FIFO (named pipe), not a regular file: it would block");
    case fs::file_type::character:
    case fs::file_type::block:
      refuse(context, path, "is a device, not a regular file");
    case fs::file_type::socket:
      refuse(context, path, "is a socket, not a regular file");
    default:
      refuse(context, path, "is not a regular file");
  }
}

std::uint64_t regular_file_size(const std::string& path, const std::string& context, const std::string& kind) {
  require_regular_file(path, context, kind);
  std::error_code error;
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error) refuse(context, path, "cannot read the file's size (" + error.message() + ")");
  return size;
}

std::vector<std::byte> read_regular_file(const std::string& path, const std::string& context, const std::string& kind) {
  const std::uint64_t size = regular_file_size(path, context, kind);
  errno = 0;
  const std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) refuse(context, path, std::string("cannot open file (") + std::strerror(errno) + ")");
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  const std::size_t got = bytes.empty() ? 0 : std::fread(bytes.data(), 1, bytes.size(), file.get());
  if (std::ferror(file.get())) refuse(context, path, std::string("cannot read file (") + std::strerror(errno) + ")");
  if (got != bytes.size() || std::fgetc(file.get()) != EOF)
    refuse(context, path, "changed size while it was read (" + std::to_string(size) + " bytes when opened)");
  return bytes;
}

}  // namespace hail::files
