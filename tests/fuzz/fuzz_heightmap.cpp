// libFuzzer target: the heightmap loaders (PGM, PNG, raw float32 / uint16) on arbitrary bytes.
// The first byte picks the loader (and for raw files the size), the rest is the file. A bad
// file must end in hail::FileError or hail::InvalidArgument, never a crash, a hang, a huge
// allocation or a sanitizer report. Run through scripts/fuzz.sh. Each input meets a clean state:
// the loaders keep nothing between calls, and the PNG loader clears stb_image's (thread-local)
// failure reason before each decode, which an earlier input could otherwise leave set.

#include <sys/mman.h>
#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "hail/errors.h"
#include "hail/heightmap.h"

namespace {

/// The file each input is written to: an in-memory file (memfd) on a fixed descriptor, named
/// /proc/self/fd/900. Not a file on disk, which made the run I/O-bound (about 350 inputs/s
/// instead of 25,000), and nothing in the name that changes from run to run (the process id did):
/// the loaders' string compares feed libFuzzer's mutation dictionary, so two runs with the same
/// -seed differed.
const std::string& input_path() {
  static const std::string path = [] {
    constexpr int kFd = 900;
    const int fd = memfd_create("hail_fuzz_heightmap", 0);
    if (fd < 0 || dup2(fd, kFd) != kFd) {
      std::perror("fuzz-heightmap: memfd_create / dup2");
      std::abort();
    }
    close(fd);
    return "/proc/self/fd/" + std::to_string(kFd);
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string& path = input_path();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  const std::uint8_t pick = data[0];
  const std::uint32_t cols = 2 + (pick >> 4), rows = 2 + ((pick >> 2) & 3);
  try {
    switch (pick & 3) {
      case 0:
        (void)hail::Heightmap::load_pgm(path, {});
        break;
      case 1:
        (void)hail::Heightmap::load_png(path, {});
        break;
      case 2:
        (void)hail::Heightmap::load_raw_f32(path, cols, rows, {});
        break;
      default:
        (void)hail::Heightmap::load_raw_u16(path, cols, rows, {}, (pick & 0x80) != 0);
        break;
    }
  } catch (const hail::FileError&) {
  } catch (const hail::InvalidArgument&) {
  }
  return 0;
}
