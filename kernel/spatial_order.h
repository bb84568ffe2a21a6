#pragma once
// Keeps spheres that are near each other in space near each other in memory: the dense slots
// are sorted by the Morton code of the sphere centres (kernel/morton.h). Terrain queries then go
// down the BVH in coherent packets (kernel/bvh_packet_walk.h), and the pair search and the
// solver touch fewer cache lines. The order is a pure function of the positions (ties broken by
// the current slot), so it is the same for any thread count.

#include <cstdint>
#include <vector>

#include "soa/sphere_soa.h"

namespace hail {

/// Fills `order` with the slots of `spheres` sorted by Morton code (then slot), ready for
/// SphereSoA::permute. `keys` is scratch; neither allocates once large enough.
void morton_slot_order(const SphereSoA& spheres, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order);

}  // namespace hail
