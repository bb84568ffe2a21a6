#pragma once
// Helpers shared by the heightmap file loaders (heightmap_pgm/png/raw.cpp); not public API.

#include <cstdint>
#include <istream>
#include <string>

#include "kernel/errors.h"
#include "kernel/heightmap.h"

namespace hail::detail {

/// Throws FileError "hail: <path>: <problem>".
[[noreturn]] inline void throw_file_error(const std::string& path, const std::string& problem) {
  throw FileError("hail: " + path + ": " + problem);
}

/// check_heightmap_size for sizes read from a file: the file is at fault, so FileError.
inline void check_file_heightmap_size(const std::string& path, std::uint64_t cols, std::uint64_t rows) {
  if (cols == 0 || rows == 0) throw_file_error(path, "zero width or height");
  try {
    check_heightmap_size(cols, rows, path);
  } catch (const InvalidArgument& e) {
    throw FileError(e.what());
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
