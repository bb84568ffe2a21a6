// World::save: the snapshot layout of kernel/world/snapshot_format.h, written.
//
// What carries from one step to the next, and so is saved (the rest of StepScratch is scratch
// that every step rebuilds before reading it: pair and contact blocks, colourings, solver
// bodies and batches, the sweep, the terrain guard's start positions, the re-sort's keys):
//   World      settings (but threads), planes, terrain material and (by hash) the terrain,
//              steps_taken_ (the Morton re-sort's phase), unchecked_from_ (spheres not yet
//              checked against the terrain), forces_pending_, ground_filter_
//   SphereSoA  every array of for_each_array, the handles, generations and free list
//   StepScratch    the warm-start cache (ContactImpulseCache::entries, ranges, rolling)
//   WorldServices  the touch-event state (ContactEventTracker::settings, touching_pairs,
//                  touching_ground)
// Not saved: the last step's outputs (contacts, impacts, events, stats, phase times) and the
// trace; restore empties them.

#include "hail/world.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/files/atomic_write.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/world/snapshot_format.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_services.h"

namespace hail {

std::uint64_t terrain_content_hash(const Terrain& terrain) { return snapshot::terrain_hash(terrain, kFnvOffsetBasis); }

std::uint64_t snapshot::terrain_hash(const Terrain& terrain, std::uint64_t basis) {
  const Heightmap& h = terrain.heightmap();
  const HeightmapParams& p = h.params();
  std::vector<std::byte> head;
  snapshot::Writer w(head);
  w.value(h.cols()), w.value(h.rows());
  w.value(p.cell_x), w.value(p.cell_z), w.value(p.origin_x), w.value(p.origin_z);
  const FlatBvh& bvh = terrain.bvh();
  w.value(std::uint64_t{bvh.nodes.size()}), w.value(std::uint64_t{bvh.primitive_order.size()});
  std::uint64_t hash = snapshot::fnv1a(head, basis);
  hash = snapshot::fnv1a(std::as_bytes(h.heights()), hash);
  hash = snapshot::fnv1a(std::as_bytes(std::span<const FlatNode>(bvh.nodes)), hash);
  return snapshot::fnv1a(std::as_bytes(std::span<const std::uint32_t>(bvh.primitive_order)), hash);
}

std::uint64_t snapshot::mesh_hash(const MeshCollider& mesh) {
  std::vector<std::byte> head;
  snapshot::Writer w(head);
  w.value(std::uint64_t{mesh.triangles.size()}), w.value(std::uint64_t{mesh.bvh.nodes.size()});
  w.value(std::uint8_t{mesh.two_sided}), w.value(mesh.restitution), w.value(mesh.friction);
  w.value(mesh.first_feature);
  std::uint64_t hash = snapshot::fnv1a(head);
  const TerrainTriangles& t = mesh.triangles;
  for (const AlignedArray<float>* a :
       {&t.v0x, &t.v0y, &t.v0z, &t.v1x, &t.v1y, &t.v1z, &t.v2x, &t.v2y, &t.v2z, &t.nx, &t.ny, &t.nz, &t.d})
    hash = snapshot::fnv1a(std::as_bytes(std::span<const float>(a->data(), a->size())), hash);
  hash = snapshot::fnv1a(std::as_bytes(std::span<const std::uint8_t>(t.internal_edges.data(), t.size())), hash);
  hash = snapshot::fnv1a(std::as_bytes(std::span<const FlatNode>(mesh.bvh.nodes)), hash);
  return snapshot::fnv1a(std::as_bytes(std::span<const std::uint32_t>(mesh.bvh.primitive_order)), hash);
}

void World::save(std::vector<std::byte>& out) const {
  out.clear();
  snapshot::Writer w(out);
  w.bytes(kSnapshotMagic, sizeof kSnapshotMagic);
  w.value(kSnapshotVersion), w.value(std::uint32_t{0});
  w.value(std::uint64_t{0}), w.value(std::uint64_t{0});  // payload length and checksum, below

  w.begin_section(snapshot::kWorldTag);
  snapshot::for_each_setting(settings_, [&](const auto& field, const SettingSpec&) {
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>)
      w.value(std::uint8_t{field});
    else if constexpr (std::is_enum_v<T>)
      w.value(static_cast<std::uint32_t>(field));
    else if constexpr (std::is_same_v<T, std::size_t>)
      w.value(std::uint64_t{field});
    else if constexpr (std::is_same_v<T, Vec3>)
      w.value(field.x()), w.value(field.y()), w.value(field.z());
    else
      w.value(field);  // float, int
  });
  w.value(std::uint64_t{steps_taken_}), w.value(std::uint64_t{unchecked_from_});
  w.value(std::uint8_t{forces_pending_});
  w.value(ground_filter_.category), w.value(ground_filter_.mask);
  w.value(std::uint8_t{terrain_ != nullptr});
  w.value(terrain_ ? terrain_content_hash(*terrain_) : std::uint64_t{0});
  w.value(terrain_restitution_), w.value(terrain_friction_);
  w.end_section();

  w.begin_section(snapshot::kPlanesTag);
  w.value(std::uint64_t{planes_.size()});
  for (const Plane& p : planes_)
    w.value(p.nx), w.value(p.ny), w.value(p.nz), w.value(p.offset), w.value(p.restitution), w.value(p.friction);
  w.end_section();

  w.begin_section(snapshot::kSpheresTag);
  const SphereSoA& s = spheres_;
  const std::size_t n = s.size();
  w.value(std::uint64_t{n}), w.value(std::uint64_t{s.generations().size()});
  w.value(std::uint64_t{s.free_indices().size()});
  for (SphereId id : s.handles()) w.value(id.index), w.value(id.generation);
  w.bytes(s.generations().data(), s.generations().size_bytes());
  w.bytes(s.free_indices().data(), s.free_indices().size_bytes());
  w.value(std::uint32_t{SphereSoA::kArrayCount});
  s.for_each_array([&](const char* name, const auto& array) {
    const std::size_t length = std::strlen(name);
    w.value(static_cast<std::uint8_t>(length));
    w.bytes(name, length);
    w.value(static_cast<std::uint8_t>(sizeof array[0]));
    w.bytes(array.data(), n * sizeof array[0]);
  });
  w.end_section();

  w.begin_section(snapshot::kCacheTag);
  const ContactImpulseCache& cache = scratch_->contact_cache;
  w.value(std::uint64_t{cache.entries().size()});
  for (const ContactImpulseCache::Entry& e : cache.entries())
    w.value(e.partner), w.value(e.normal_impulse), w.value(e.tx), w.value(e.ty), w.value(e.tz);
  w.value(std::uint64_t{cache.ranges().size()});
  for (const ContactImpulseCache::Range& r : cache.ranges())
    w.value(r.id), w.value(r.static_begin), w.value(r.static_end), w.value(r.pair_begin), w.value(r.pair_end);
  if (settings_.rolling_resistance > 0.0f) {  // a world without rolling resistance keeps version 7's bytes
    w.value(std::uint64_t{cache.rolling().size()});
    w.bytes(cache.rolling().data(), cache.rolling().size_bytes());
  }
  w.end_section();

  w.begin_section(snapshot::kEventsTag);
  const ContactEventTracker& events = services_->events;
  w.value(std::uint8_t{events.settings().touch}), w.value(std::uint8_t{events.settings().hits});
  w.value(events.settings().hit_speed);
  for (std::span<const TouchKey> keys : {events.touching_pairs(), events.touching_ground()}) {
    w.value(std::uint64_t{keys.size()});
    for (const TouchKey& k : keys) w.value(k.key), w.value(k.generations);
  }
  w.end_section();

  if (has_meshes()) {  // a world without meshes writes version 8's bytes
    w.begin_section(snapshot::kMeshesTag);
    w.value(std::uint64_t{meshes_->size()});
    for (std::size_t m = 0; m < meshes_->size(); ++m) w.value(snapshot::mesh_hash((*meshes_)[m]));
    w.end_section();
  }

  const std::span<const std::byte> payload(out.data() + snapshot::kHeaderBytes, out.size() - snapshot::kHeaderBytes);
  const std::uint64_t length = payload.size(), checksum = snapshot::fnv1a(payload);
  std::memcpy(out.data() + snapshot::kPayloadBytesAt, &length, sizeof length);
  std::memcpy(out.data() + snapshot::kChecksumAt, &checksum, sizeof checksum);
}

void World::save_file(const std::string& path) const {
  std::vector<std::byte> bytes;
  save(bytes);
  // Beside the target, fsync'd, then renamed over it: a full disk leaves the old snapshot whole.
  files::write_file_atomically(path, bytes, "World::save_file: ");
}

}  // namespace hail
