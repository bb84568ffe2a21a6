#pragma once
// The exceptions hail throws at its API boundary. Library code never terminates the host:
// bad input is reported with a message naming the value, and the object is left unchanged.

#include <stdexcept>
#include <string>

namespace hail {

/// A value passed to hail is out of its domain (NaN, negative radius, restitution > 1, ...).
class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A file could not be read or is malformed; the message names the file and the problem.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file's header asks for a bigger heightmap than the caller allows
/// (HeightmapParams::max_vertices): the file may be sound, the limit too low for it.
class SizeLimitError : public FileError {
 public:
  using FileError::FileError;
};

}  // namespace hail
