#pragma once
// Collision filters in the step (include/hail/collision_filter.h): a sphere's filter read from
// the SoA, and the pass that drops filtered sphere pairs right after the pair search, before
// any contact is made of them. The step calls these only when some filter is not the default
// (World keeps that flag), so a scene without filters runs none of it.

#include <algorithm>
#include <cstddef>
#include <vector>

#include "hail/collision_filter.h"
#include "hail/sphere_soa.h"
#include "kernel/broadphase/sphere_pairs.h"

namespace hail {

inline CollisionFilter sphere_filter(const SphereSoA& s, std::size_t i) {
  return {s.collision_category[i], s.collision_mask[i]};
}

/// Whether sphere i collides with the static world (terrain and planes), whose filter is `ground`.
inline bool meets_ground(const SphereSoA& s, std::size_t i, CollisionFilter ground) {
  return should_collide(sphere_filter(s, i), ground);
}

/// Drops the pairs from `from` on whose spheres' filters reject each other. Every pair search
/// (brute force, grid, sweep and prune, BVH) lists the same pairs in the same order, so they
/// keep the same ones after this too.
inline void drop_filtered_pairs(const SphereSoA& s, std::vector<SpherePair>& pairs, std::size_t from) {
  const auto kept = std::remove_if(pairs.begin() + static_cast<std::ptrdiff_t>(from), pairs.end(), [&](SpherePair p) {
    return !should_collide(sphere_filter(s, p.a), sphere_filter(s, p.b));
  });
  pairs.erase(kept, pairs.end());
}

}  // namespace hail
