#pragma once
// Brute-force sphere-sphere pair detection over the SoA: every pair (i, j), i < j, whose
// surfaces are closer than `margin` (speculative contacts). A SIMD kernel tests one sphere i
// against a batch of j at a time (4, 8 or 16: SSE4.2, AVX2, AVX-512); the scalar reference evaluates the same predicate in the same
// float operations, so both return exactly the same pairs (tests compare them).

#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"

namespace hail {

struct SpherePair {
  std::uint32_t a, b;  ///< dense slots, a < b
  friend bool operator==(SpherePair, SpherePair) = default;
};

/// The predicate every pair search evaluates: |pb - pa|^2 < reach^2 with
/// reach = rb + (ra + margin), in exactly this order of float operations, so that brute force
/// (scalar or SIMD) and the grid agree to the last bit on which pairs exist.
inline bool spheres_within(float dx, float dy, float dz, float reach) {
  const float d2 = dx * dx + dy * dy + dz * dz;
  return d2 < reach * reach;
}

/// Appends the pairs (i, j) with i in [first, last), i < j < spheres.size(). Scalar reference.
void find_sphere_pairs_scalar(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                              std::vector<SpherePair>& out);

/// Same result as find_sphere_pairs_scalar, testing a batch of j per instruction on the active
/// SIMD path (kernel/dispatch/simd_dispatch.h; the kernel is kernel/simd/sphere_pairs.cpp).
void find_sphere_pairs_simd(const SphereSoA& spheres, std::size_t first, std::size_t last, float margin,
                            std::vector<SpherePair>& out);

/// Turns a pair into a contact: normal from a to b, gap = distance - ra - rb (computed before
/// the normal is normalised), material combined. Coincident centres (centres_coincide) get the
/// pair's own direction from the two spheres' ids (kernel/geometry/coincident_normal.h).
Contact make_sphere_contact(const SphereSoA& spheres, SpherePair pair);

/// Effective friction of two materials: the geometric mean, so equal values combine to themselves.
float combine_friction(float a, float b);
/// Effective restitution: the smaller coefficient (the original design's rule).
inline float combine_restitution(float a, float b) { return a < b ? a : b; }

}  // namespace hail
