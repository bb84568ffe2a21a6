#pragma once
// Writing a file so that a failure never costs the old one: the bytes go to a temporary file
// beside the target, are flushed to the disk (fsync), and only then renamed over the target.
// A full disk, a crash or a killed process leaves either the old file or the new one whole,
// never a truncated mix (World::save_file).

#include <cstddef>
#include <span>
#include <string>

namespace hail::files {

/// Replaces `path` with `bytes` as above; the new file keeps an old one's permission bits. A
/// target that exists and is a device (/dev/null, /dev/full) is written in place, with every
/// write checked: renaming over it would replace the device. Throws FileError
/// "hail: <context><path>: <problem>" naming what failed (a folder or FIFO at `path`, no such
/// folder, a write, fsync or rename failing), the target unchanged.
void write_file_atomically(const std::string& path, std::span<const std::byte> bytes, const std::string& context = {});

}  // namespace hail::files
