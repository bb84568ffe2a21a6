#pragma once
// The stackless walk for a packet of spheres at once: one node load and one SIMD box test
// serve a whole batch of queries (4 lanes under SSE4.2, 8 under AVX2, 16 under AVX-512). A node is entered when any lane touches
// it; a leaf is handed to each lane that touches it. Because a child's box lies inside its
// parent's, a lane that missed a node misses everything below it, so no per-lane mask has to
// be carried down: each lane sees exactly the leaves, in exactly the order, that its own
// single-sphere walk (query_sphere in kernel/bvh/flat_bvh.h, the scalar reference) would see.
//
// It pays when the packet's spheres are near each other (sorted by Morton code, say): their
// walks then share most nodes, and the tree's top is tested once per packet instead of once per
// sphere. `hail-bench query` measures it against the single walks and the grid lookup.
//
// Everything here is compiled for the including translation unit's SIMD path, in its own
// namespace (kernel/dispatch/simd_arch.h): the terrain's contact search runs the copies of
// kernel/simd/terrain_contacts.cpp, chosen at start-up (kernel/dispatch/simd_dispatch.h).

#include <cstdint>
#include <span>

#include "kernel/bvh/flat_bvh.h"
#include "kernel/dispatch/simd_arch.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

/// Lanes in a sphere packet: one xsimd float batch of this translation unit's SIMD path.
inline constexpr std::uint32_t kSpherePacketWidth = static_cast<std::uint32_t>(xsimd::batch<float, simd_arch>::size);

/// Up to kSpherePacketWidth query spheres, SoA. Unused lanes hold radius_sq = -1, which no
/// squared distance (>= 0) can be below, so they never enter a node.
struct SpherePacket {
  alignas(64) float cx[kSpherePacketWidth];
  alignas(64) float cy[kSpherePacketWidth];
  alignas(64) float cz[kSpherePacketWidth];
  alignas(64) float radius_sq[kSpherePacketWidth];
  std::uint32_t count = 0;

  /// Empties the packet (every lane inert).
  void clear() {
    for (std::uint32_t l = 0; l < kSpherePacketWidth; ++l) {
      cx[l] = cy[l] = cz[l] = 0.0f;
      radius_sq[l] = -1.0f;
    }
    count = 0;
  }
  /// Puts a sphere in the next free lane (requires count < kSpherePacketWidth); returns the lane.
  std::uint32_t add(float x, float y, float z, float r) {
    cx[count] = x;
    cy[count] = y;
    cz[count] = z;
    radius_sq[count] = r * r;  // r * r as sphere_overlaps computes it: the same float decisions
    return count++;
  }
};

namespace detail {

/// The packet's spheres against one box, all lanes at once. Per axis the excess
/// max(lo - c, c - hi, 0) and the sum's order are those of sphere_overlaps (kernel/geometry/aabb.h), so
/// every lane decides exactly as the scalar test would.
struct PacketBoxTest {
  using batch = xsimd::batch<float, simd_arch>;
  batch cx, cy, cz, radius_sq;
  explicit PacketBoxTest(const SpherePacket& p)
      : cx(batch::load_aligned(p.cx)),
        cy(batch::load_aligned(p.cy)),
        cz(batch::load_aligned(p.cz)),
        radius_sq(batch::load_aligned(p.radius_sq)) {}
  template <BoxBounds Box>
  [[nodiscard]] std::uint32_t operator()(const Box& b) const {
    // Zero first in the outer max: a NaN lane keeps a NaN excess and touches nothing, as in
    // sphere_overlaps (xsimd::max(x, y) is x > y ? x : y, y when either is NaN).
    const batch zero(0.0f);
    const batch ex = xsimd::max(zero, xsimd::max(batch(b.min[0]) - cx, cx - batch(b.max[0])));
    const batch ey = xsimd::max(zero, xsimd::max(batch(b.min[1]) - cy, cy - batch(b.max[1])));
    const batch ez = xsimd::max(zero, xsimd::max(batch(b.min[2]) - cz, cz - batch(b.max[2])));
    return lane_bits(ex * ex + ey * ey + ez * ez <= radius_sq);
  }
};

/// The packet walk; `visit_leaf(lane_bits, first, count)` gets each entered leaf with the
/// lanes that touch it.
template <class VisitLeaf, class Count>
void walk_packet(const FlatBvh& bvh, const PacketBoxTest& touches, VisitLeaf&& visit_leaf, Count&& count) {
  const FlatNode* node = bvh.nodes.data();
  std::uint32_t i = 0;
  while (i != kFlatBvhEnd) {
    const FlatNode& n = node[i];
    count(i);
    if (const std::uint32_t lanes = touches(n)) {
      if (!is_leaf(n)) {
        i = i + 1;
        continue;
      }
      visit_leaf(lanes, leaf_first(n), leaf_count(n));
    }
    i = n.skip;
  }
}

}  // namespace detail

/// Stackless packet walk: visit(lane, k) for every primitive k (BVH order) of every leaf whose
/// box lane's sphere touches; per lane, the same k in the same order as query_sphere.
/// count(i) is called once per node tested (once per packet, not per lane).
template <class Visit, class Count = NoNodeCount>
void query_sphere_packet(const FlatBvh& bvh, const SpherePacket& packet, Visit&& visit, Count&& count = {}) {
  if (bvh.nodes.empty() || packet.count == 0) return;
  const detail::PacketBoxTest touches(packet);
  detail::walk_packet(
      bvh, touches,
      [&](std::uint32_t lanes, std::uint32_t first, std::uint32_t n) {
        for (; lanes != 0; lanes &= lanes - 1) {
          const std::uint32_t lane = lowest_lane(lanes);
          for (std::uint32_t k = first; k < first + n; ++k) visit(lane, k);
        }
      },
      count);
}

/// query_sphere_packet_exact below with each primitive's lanes at once: visit_lanes(lanes, k)
/// for every primitive k of every entered leaf, `lanes` the bit mask of the lanes whose sphere
/// touches its box (maybe none). For visitors that take a primitive's lanes without a branch
/// per lane (PacketWalkExact::run_masks says why).
template <class VisitLanes, class Count = NoNodeCount>
void query_sphere_packet_exact_masks(const FlatBvh& bvh, std::span<const Aabb> bounds, const SpherePacket& packet,
                                     VisitLanes&& visit_lanes, Count&& count = {}) {
  if (bvh.nodes.empty() || packet.count == 0) return;
  const detail::PacketBoxTest touches(packet);
  detail::walk_packet(
      bvh, touches,
      [&](std::uint32_t leaf_lanes, std::uint32_t first, std::uint32_t n) {
        // A primitive's box lies inside its leaf's, so only the leaf's lanes can touch it.
        for (std::uint32_t k = first; k < first + n; ++k) visit_lanes(touches(bounds[k]) & leaf_lanes, k);
      },
      count);
}

/// The packet walk with each leaf's primitives filtered by their own boxes, one SIMD test per
/// primitive for all lanes: visit(lane, k) exactly for the primitives k whose box
/// (`bounds[k]`, BVH order) lane's sphere touches. Per lane: the k of query_sphere that pass
/// sphere_overlaps(bounds[k], ...), in the same order; the same pairs (lane, k) but grouped by
/// primitive rather than by lane.
template <class Visit, class Count = NoNodeCount>
void query_sphere_packet_exact(const FlatBvh& bvh, std::span<const Aabb> bounds, const SpherePacket& packet,
                               Visit&& visit, Count&& count = {}) {
  query_sphere_packet_exact_masks(
      bvh, bounds, packet,
      [&](std::uint32_t lanes, std::uint32_t k) {
        for (; lanes != 0; lanes &= lanes - 1) visit(lowest_lane(lanes), k);
      },
      count);
}

/// query_sphere_packet_exact in stretches, for a visitor that fills a bounded buffer and
/// empties it between stretches: run() walks on from where the last one stopped and stops
/// before a leaf whose primitives could need more than free_slots() (a primitive takes at most
/// one slot per lane). Over all stretches, visit(lane, k) gets exactly the pairs, in exactly the
/// order, of query_sphere_packet_exact. Emptying the buffer outside the walk keeps any call out
/// of its loop, so the packet's registers stay in registers (a call inside the loop makes the
/// compiler keep them on the stack). An empty buffer must hold a whole leaf's worth,
/// kMaxLeafSize * kSpherePacketWidth slots, or run() cannot get past that leaf.
class PacketWalkExact {
 public:
  PacketWalkExact(const FlatBvh& bvh, std::span<const Aabb> bounds, const SpherePacket& packet)
      : bvh_(bvh), bounds_(bounds), touches_(packet), next_(bvh.nodes.empty() || packet.count == 0 ? kFlatBvhEnd : 0) {}

  [[nodiscard]] bool done() const { return next_ == kFlatBvhEnd; }

  template <class Visit, class FreeSlots>
  void run(Visit&& visit, FreeSlots&& free_slots) {
    run_masks(
        [&](std::uint32_t lanes, std::uint32_t k) {
          for (; lanes != 0; lanes &= lanes - 1) visit(lowest_lane(lanes), k);
        },
        free_slots);
  }

  /// run() with each primitive's touching lanes at once: visit_lanes(lanes, k) for every
  /// primitive k of every entered leaf, `lanes` the bit mask of the lanes that touch it (maybe
  /// none): the pairs (lane, k) of run(), in the same order when taken lowest lane first. For
  /// visitors that store a primitive's lanes without a branch per lane or per primitive
  /// (kernel/simd/terrain_contacts.cpp): whether a lane touches a leaf's triangle is about a
  /// coin toss, which no predictor learns.
  template <class VisitLanes, class FreeSlots>
  void run_masks(VisitLanes&& visit_lanes, FreeSlots&& free_slots) {
    const FlatNode* node = bvh_.nodes.data();
    std::uint32_t i = next_;
    while (i != kFlatBvhEnd) {
      const FlatNode& n = node[i];
      if (const std::uint32_t leaf_lanes = touches_(n)) {
        if (!is_leaf(n)) {
          i = i + 1;
          continue;
        }
        const std::uint32_t first = leaf_first(n), count = leaf_count(n);
        if (count * kSpherePacketWidth > free_slots()) break;  // resume at this leaf
        for (std::uint32_t k = first; k < first + count; ++k) visit_lanes(touches_(bounds_[k]) & leaf_lanes, k);
      }
      i = n.skip;
    }
    next_ = i;
  }

 private:
  const FlatBvh& bvh_;
  std::span<const Aabb> bounds_;
  detail::PacketBoxTest touches_;
  std::uint32_t next_;
};

}  // namespace HAIL_SIMD_NS
}  // namespace hail
