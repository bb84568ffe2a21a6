#pragma once
// Every file hail-bench writes goes through here, so that a run never reports success over a
// missing or cut-short file and never destroys what it cannot replace:
// - before the run, check_output_paths refuses a path that cannot be written (no such folder,
//   a folder in its place, a folder where no file can be created) or that is the same file as
//   an input (the scene file) or as another output, so minutes of simulation are not lost and
//   the scene is never overwritten by its own dump;
// - the content goes to a temporary file beside the target, is flushed and checked, and only
//   written to the disk (fsync), then renamed over the target, so a failed write (full disk)
//   or a crash leaves the old file intact.
//   A target that exists and is not a regular file (/dev/stdout, /dev/full, a pipe) is written
//   in place, with the same checks: renaming over a device would replace the device.
// Failures are std::invalid_argument (a path refused before the run) or std::runtime_error (a
// write that failed), each naming the path.

#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace hail::bench {

/// Whether `a` and `b` name the same file: by filesystem identity (device and inode) when both
/// exist, else by their weakly canonical paths.
[[nodiscard]] bool same_file(const std::string& a, const std::string& b);

/// Refuses, with std::invalid_argument naming the flag's path, any non-empty `outputs` entry
/// that cannot be written or that is the same file as a non-empty `inputs` entry or another
/// output. Creates and removes a probe file beside each, which proves writability even where
/// permission bits cannot (as root, on a read-only mount).
void check_output_paths(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs = {});

/// The folder for several output files (--out DIR): created if missing; std::invalid_argument
/// if that fails or no file can be created in it.
void prepare_output_dir(const std::string& dir);

/// A file being written: a temporary beside `path` until commit() renames it over `path`.
/// Destroyed without commit() (an exception on the way), it removes the temporary and leaves
/// `path` as it was.
class AtomicOutputFile {
 public:
  /// Opens the temporary (std::runtime_error naming `path` if it cannot be created).
  explicit AtomicOutputFile(std::string path);
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;
  ~AtomicOutputFile();

  [[nodiscard]] std::ostream& stream() { return out_; }
  /// Flushes what was written so far; std::runtime_error naming the path if a write failed
  /// (for a file written over a long run, so that a full disk stops it early).
  void flush();
  /// Flushes, closes and checks the file, then renames it over the target; std::runtime_error
  /// naming the path (and the system's reason) if any of that failed, the target unchanged.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& what);

  std::string path_;       // the target, as given (named in messages)
  std::string target_;     // the file replaced: path_, or the file a symbolic link there points to
  std::string temporary_;  // where the content goes; target_ itself when written in place
  std::ofstream out_;
  bool done_ = false;
};

/// AtomicOutputFile in one call: `write` fills the stream, then commit().
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace hail::bench
