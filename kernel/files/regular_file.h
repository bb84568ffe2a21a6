#pragma once
// Opening files that hail reads whole (snapshots, recordings, heightmaps): the one rule for
// what may be opened. Only a regular file is, after symbolic links: opening a FIFO blocks until
// a writer comes, which may be never, and a device or a folder has no length to check what it
// holds against (/dev/zero is endless). A file is read up to the size the file system gave
// for it, never further, so a file that grows while it is read cannot make hail read on.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hail::files {

/// Throws FileError "hail: <context><path>: <problem>" unless `path` (after symbolic links) is
/// a regular file; `kind` names what it should have been in the message for a folder ("is a
/// directory, not <kind>").
void require_regular_file(const std::string& path, const std::string& context = {},
                          const std::string& kind = "a regular file");

/// The size the file system gives for a regular file, as require_regular_file checks it.
[[nodiscard]] std::uint64_t regular_file_size(const std::string& path, const std::string& context = {},
                                              const std::string& kind = "a regular file");

/// The bytes of a regular file (require_regular_file), at most its size when opened; FileError
/// (same message form) when it cannot be opened or read, or changed size while it was read.
[[nodiscard]] std::vector<std::byte> read_regular_file(const std::string& path, const std::string& context = {},
                                                       const std::string& kind = "a regular file");

}  // namespace hail::files
