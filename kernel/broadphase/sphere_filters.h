#pragma once
// Collision filters in the step (include/hail/collision_filter.h): a sphere's filter read from
// the SoA, and the pass that drops filtered sphere pairs right after the pair search, before
// any contact is made of them. The step calls these only when some filter is not the default or
// some sphere is kinematic (World keeps that flag), so a scene without either runs none of it.

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

inline bool is_kinematic(const SphereSoA& s, std::size_t i) { return (s.flags[i] & kSphereFlagKinematic) != 0; }

/// Whether sphere i collides with the static world (terrain and planes), whose filter is
/// `ground`. A kinematic sphere never does: the game moves it, and no ground could push it.
inline bool meets_ground(const SphereSoA& s, std::size_t i, CollisionFilter ground) {
  return should_collide(sphere_filter(s, i), ground) && !is_kinematic(s, i);
}

/// Whether spheres a and b may collide: their filters accept each other, and not both are
/// immovable with one of them kinematic (a paddle sliding past a static post or another paddle:
/// no impulse could move either, so their contact would only cost time and raise touch events).
inline bool pair_collides(const SphereSoA& s, std::size_t a, std::size_t b) {
  if (!should_collide(sphere_filter(s, a), sphere_filter(s, b))) return false;
  const bool immovable = !(s.inv_mass[a] > 0.0f) && !(s.inv_mass[b] > 0.0f);
  return !(immovable && (is_kinematic(s, a) || is_kinematic(s, b)));
}

/// Drops the pairs from `from` on that pair_collides rejects. Every pair search (brute force,
/// grid, sweep and prune, BVH) lists the same pairs in the same order, so they keep the same
/// ones after this too.
inline void drop_filtered_pairs(const SphereSoA& s, std::vector<SpherePair>& pairs, std::size_t from) {
  const auto kept = std::remove_if(pairs.begin() + static_cast<std::ptrdiff_t>(from), pairs.end(),
                                   [&](SpherePair p) { return !pair_collides(s, p.a, p.b); });
  pairs.erase(kept, pairs.end());
}

}  // namespace hail
