#pragma once
// What the snapshot reader's fuzzer (tests/fuzz/fuzz_snapshot.cpp) does with one input, shared
// with the normal build's tests (tests/test_snapshot.cpp replays the seed corpus through it and
// writes that corpus): World::restore into a World without terrain and into one with a small
// terrain; a snapshot either is refused with InvalidArgument or is restored, and then
// World::save gives back exactly its bytes (the format has one spelling of each state, so a
// reader that accepted something it misread shows here). Each input is tried as it is and with
// its checksum made right, so that the mutations reach the sections behind the checksum.

#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "hail/errors.h"
#include "hail/world.h"
#include "kernel/world/snapshot_format.h"

namespace hail::fuzz {

/// A 9 x 9-vertex terrain of 1 m cells around the origin, a gentle slope.
inline std::shared_ptr<const Terrain> snapshot_fuzz_terrain() {
  const HeightmapParams params{.origin_x = -4.0f, .origin_z = -4.0f};
  return std::make_shared<const Terrain>(
      Heightmap::from_function(9, 9, params, [](float x, float z) { return 0.1f * x + 0.05f * z; }));
}

/// The fuzzer's worlds: [0] without terrain, [1] with snapshot_fuzz_terrain(). One thread.
inline std::unique_ptr<World> snapshot_fuzz_world(bool terrain) {
  auto world = std::make_unique<World>(WorldSettings{.threads = 1});
  if (terrain) world->set_terrain(snapshot_fuzz_terrain());
  return world;
}

/// world.save() as a new vector.
inline std::vector<std::byte> saved(const World& world) {
  std::vector<std::byte> bytes;
  world.save(bytes);
  return bytes;
}

enum class SnapshotOutcome { Refused, Restored, Misread };

/// restore(bytes); Misread when it was accepted and save() does not give the same bytes back.
/// An older version's snapshot saves as this version: that one, restored, must save the same
/// bytes again.
inline SnapshotOutcome restore_and_compare(World& world, std::span<const std::byte> bytes) {
  try {
    world.restore(bytes);
  } catch (const InvalidArgument&) {
    return SnapshotOutcome::Refused;
  }
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + sizeof kSnapshotMagic, sizeof version);  // restore read it
  std::vector<std::byte> again, first_save;
  world.save(again);
  if (version != kSnapshotVersion) {
    first_save = std::move(again);
    world.restore(first_save);
    world.save(again);
    bytes = first_save;
  }
  const bool same = again.size() == bytes.size() && std::memcmp(again.data(), bytes.data(), bytes.size()) == 0;
  return same ? SnapshotOutcome::Restored : SnapshotOutcome::Misread;
}

/// The input, with the payload's checksum written into its header (when it has one).
inline std::vector<std::byte> with_right_checksum(std::span<const std::byte> bytes) {
  std::vector<std::byte> fixed(bytes.begin(), bytes.end());
  if (fixed.size() >= snapshot::kHeaderBytes) {
    const std::uint64_t sum = snapshot::fnv1a(std::span<const std::byte>(fixed).subspan(snapshot::kHeaderBytes));
    std::memcpy(fixed.data() + snapshot::kChecksumAt, &sum, sizeof sum);
  }
  return fixed;
}

}  // namespace hail::fuzz
