#pragma once
// Snapshots: World::save writes everything that decides a world's future into bytes (or a
// file), World::restore puts it back, into this World or another, on any thread count and SIMD
// path; N steps later the two worlds have the same state, bitwise (rollback netcode, replays, a
// run checked on another machine). What is saved, the guarantees and the calls:
// docs/embedding.md, "Snapshots"; the byte layout: docs/snapshot_format.md.
//
// The terrain is not embedded (it may be hundreds of MB and is shared): a snapshot names it by
// a content hash (terrain_content_hash), and restore refuses a world whose terrain differs.

#include <cstdint>

namespace hail {

class Terrain;

/// The first 8 bytes of every snapshot.
inline constexpr char kSnapshotMagic[8] = {'H', 'A', 'I', 'L', 'S', 'N', 'A', 'P'};
/// The format this hail writes. restore reads this version and refuses a newer one (the
/// message names both). Raised whenever the layout changes, e.g. a sphere array is added
/// (SphereSoA::for_each_array).
/// Version 9 ends with a MESH section when the world has meshes (World::add_mesh): their count
/// and a content hash of each, and restore refuses a world whose meshes differ; a world without
/// meshes writes version 8's bytes.
/// Version 8 keeps each contact's rolling impulse in the warm-start cache when
/// rolling_resistance > 0 (otherwise its bytes are version 7's; a version 7 snapshot restores
/// with them zero). Version 7 adds rolling_resistance to the settings; version 6 (read with it 0) has no
/// warm_start byte among them (warm_start_factor 0 is warm starting off). Versions 5 and 4 are
/// still read: version 5 checksums with FNV-1a's published offset basis, version 4 with a
/// basis a digit short; both have the warm_start byte.
inline constexpr std::uint32_t kSnapshotVersion = 9;

/// FNV-1a 64 over everything that decides how spheres meet the terrain: the heightmap's size,
/// cell sizes, origin and heights, and the BVH (its nodes and triangle order, which number the
/// triangles that warm starting remembers). Equal hashes: the same terrain, to a step.
[[nodiscard]] std::uint64_t terrain_content_hash(const Terrain& terrain);

}  // namespace hail
