#pragma once
// Keeps spheres that are near each other in space near each other in memory: the dense slots
// are sorted by the Morton code of the sphere centres (kernel/geometry/morton.h). Terrain queries then go
// down the BVH in coherent packets (kernel/bvh/bvh_packet_walk.h), and the pair search and the
// solver touch fewer cache lines. The order is a pure function of the positions (ties broken by
// the current slot), so it is the same for any thread count.

#include <cstdint>
#include <vector>

#include "hail/sphere_soa.h"
#include "kernel/geometry/aabb.h"

namespace hail {

/// Fills `order` with the slots of `spheres` sorted by Morton code (then slot), ready for
/// SphereSoA::permute. `keys` is scratch; neither allocates once large enough. Serial; the
/// World's re-sort runs the same three parts below over blocks in parallel (jobs/), with the
/// same result: min and max are exact in any order, and the keys are unique (the slot is in
/// their low bits), so every correct sort puts them in the same order.
void morton_slot_order(const SphereSoA& spheres, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order);

/// The box of the finite centres of spheres [first, last) (empty_aabb() when there is none): a
/// non-finite centre would stretch it to infinity and put everyone in one Morton cell. The box
/// of all spheres is the union of the boxes of any split of them.
[[nodiscard]] Aabb finite_centre_bounds(const SphereSoA& spheres, std::size_t first, std::size_t last);

/// keys[i] = Morton code of sphere i in `bounds` (the box of all centres) << 32 | i, for i in
/// [first, last).
void morton_keys(const SphereSoA& spheres, const Aabb& bounds, std::size_t first, std::size_t last,
                 std::uint64_t* keys);

}  // namespace hail
