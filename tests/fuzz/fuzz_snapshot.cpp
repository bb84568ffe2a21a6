// libFuzzer target: the snapshot reader (World::restore, kernel/world/snapshot_reader.cpp) on
// arbitrary bytes, as they come and with their checksum made right (tests/fuzz/snapshot_harness.h).
// A bad snapshot must end in InvalidArgument, never a crash, a hang or a sanitizer report; one the
// reader accepts must save back to the same bytes. Seeds: tests/fuzz/corpus/snapshot/, small
// valid snapshots written by tests/test_snapshot.cpp ("[.write-snapshot-corpus]").

#include <cstdint>
#include <cstdlib>

#include "snapshot_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hail::fuzz;
  static std::unique_ptr<hail::World> worlds[2] = {snapshot_fuzz_world(false), snapshot_fuzz_world(true)};
  const std::span<const std::byte> raw(reinterpret_cast<const std::byte*>(data), size);
  const std::vector<std::byte> fixed = with_right_checksum(raw);
  for (auto& world : worlds)
    for (std::span<const std::byte> bytes : {raw, std::span<const std::byte>(fixed)})
      if (restore_and_compare(*world, bytes) == SnapshotOutcome::Misread) std::abort();
  return 0;
}
