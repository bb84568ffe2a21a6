#pragma once
// Helpers shared by the heightmap file loaders (heightmap_pgm/png/raw.cpp); not public API.
// Every loader opens its file through require_regular_file (open_heightmap_file for streams),
// so the file-type rule lives in one place.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <istream>
#include <string>
#include <system_error>

#include "hail/errors.h"
#include "hail/heightmap.h"
#include "kernel/files/regular_file.h"

namespace hail::detail {

/// Throws FileError "hail: <path>: <problem>".
[[noreturn]] inline void throw_file_error(const std::string& path, const std::string& problem) {
  throw FileError("hail: " + path + ": " + problem);
}

/// Throws FileError unless `path` (after symbolic links) is a regular file (kernel/files/).
inline void require_regular_file(const std::string& path) { files::require_regular_file(path, {}, "a heightmap file"); }

/// The file opened for binary reading, once require_regular_file has passed.
inline std::ifstream open_heightmap_file(const std::string& path) {
  require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_file_error(path, "cannot open file");
  return in;
}

/// check_heightmap_size for sizes read from a file: the file is at fault, so FileError; a size
/// within the hard limits but over `max_vertices` is SizeLimitError (the caller's limit).
inline void check_file_heightmap_size(const std::string& path, std::uint64_t cols, std::uint64_t rows,
                                      std::uint64_t max_vertices) {
  if (cols == 0 || rows == 0) throw_file_error(path, "zero width or height");
  try {
    check_heightmap_size(cols, rows, path);
  } catch (const InvalidArgument& e) {
    throw FileError(e.what());
  }
  try {
    check_heightmap_size(cols, rows, path, max_vertices);
  } catch (const InvalidArgument& e) {
    throw SizeLimitError(e.what());
  }
}

/// Bytes from the stream's position to its end (the stream is left where it was). Lets a
/// loader refuse a truncated file before allocating what its header promised.
inline std::uint64_t bytes_remaining(std::istream& in) {
  const std::istream::pos_type here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  in.seekg(here);
  return here < 0 || end < here ? 0 : static_cast<std::uint64_t>(end - here);
}

}  // namespace hail::detail
