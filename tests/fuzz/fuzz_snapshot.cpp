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
  // Each input starts from the worlds as they were made (restore replaces all a snapshot holds
  // and empties the rest): an input restored by the one before must not change what the next
  // one meets, so a find replays alone.
  static std::unique_ptr<hail::World> worlds[2] = {snapshot_fuzz_world(false), snapshot_fuzz_world(true)};
  static const std::vector<std::byte> pristine[2] = {saved(*worlds[0]), saved(*worlds[1])};
  const std::span<const std::byte> raw(reinterpret_cast<const std::byte*>(data), size);
  const std::vector<std::byte> fixed = with_right_checksum(raw);
  for (int k = 0; k < 2; ++k)
    for (std::span<const std::byte> bytes : {raw, std::span<const std::byte>(fixed)}) {
      worlds[k]->restore(pristine[k]);
      if (restore_and_compare(*worlds[k], bytes) == SnapshotOutcome::Misread) std::abort();
    }
  return 0;
}
