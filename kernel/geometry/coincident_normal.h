#pragma once
// The contact normal of two spheres whose centres coincide (or nearly): the centres give no
// direction, so the pair gets one of its own, derived from the two spheres' stable ids.
//
// A fixed fallback (+y, as before) sent every pair of a heap of spheres created at one point the
// same way: they parted along one line and ended as a vertical column, many still overlapping
// thousands of steps later. Here each pair gets its own direction, spread over the whole sphere
// (a hash of the two ids mapped to a unit vector), so a heap parts in all directions at once.
// The rule:
//  * from ids, not dense slots: slots move (removal, the Morton re-sort) and the direction of
//    a pair must not change with where its spheres happen to be stored;
//  * antisymmetric: the pair seen from b (b, a) gets exactly the negated normal, so the spheres
//    part the same way whichever one the pair search lists first;
//  * integer hashing, then only +, *, / and sqrt on floats (correctly rounded, no libm), so the
//    same bits on every SIMD path, thread count and compiler: one scalar function, called by
//    make_sphere_contact for every path.

#include <cmath>
#include <cstdint>

namespace hail {

/// Centres closer than this fraction of ra + rb have no usable direction: their difference is
/// position rounding, or exactly 0. It covers a few float spacings of positions near the origin
/// (at 256 to 512 m the spacing is 31 um, 6e-5 of two 0.25 m radii); pairs that deep inside
/// each other are made only by creating them there.
inline constexpr float kCoincidentCentreFraction = 1e-4f;

/// Whether two centres `distance` apart are taken as coincident (coincident_normal applies).
[[nodiscard]] inline bool centres_coincide(float distance, float ra, float rb) {
  return !(distance > kCoincidentCentreFraction * (ra + rb));  // NaN distance too: never a NaN normal
}

/// The splitmix64 finaliser: every input bit moves about half of the output bits.
[[nodiscard]] constexpr std::uint64_t mix_bits(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Unit normal from sphere `id_a` towards sphere `id_b` (distinct stable ids, SphereId::index)
/// for coincident centres; coincident_normal(b, a) is exactly -coincident_normal(a, b).
/// The height y is uniform in (-1, 1) (so the directions are uniform over the sphere's area,
/// Archimedes), the azimuth a point of the unit circle from a rational parametrisation
/// ((1 - t^2, 2t) / (1 + t^2), t uniform in (-1, 1), either half by one more bit): its density
/// varies by 2 : 1 around the circle, well enough spread, and needs no sin or cos.
inline void coincident_normal(std::uint32_t id_a, std::uint32_t id_b, float n[3]) {
  const bool a_first = id_a < id_b;
  const std::uint32_t low = a_first ? id_a : id_b, high = a_first ? id_b : id_a;
  const std::uint64_t bits = mix_bits(std::uint64_t{low} << 32 | high);
  constexpr float kStep = 1.0f / 8388608.0f;  // 2^-23: (2k + 1) 2^-23 - 1 is exact in float for k < 2^23
  const float y = static_cast<float>(2 * (bits & 0x7FFFFF) + 1) * kStep - 1.0f;
  const float t = static_cast<float>(2 * ((bits >> 23) & 0x7FFFFF) + 1) * kStep - 1.0f;
  const float across = std::sqrt(1.0f - y * y);  // |y| <= 1 - 2^-23: positive
  const float q = 1.0f + t * t;
  const float c = (1.0f - t * t) / q, s = 2.0f * t / q;
  const float half = (bits >> 46) & 1 ? -1.0f : 1.0f;
  const float sign = a_first ? 1.0f : -1.0f;  // the same vector for (a, b) and (b, a), negated
  n[0] = sign * (half * c * across);
  n[1] = sign * y;
  n[2] = sign * (s * across);
}

}  // namespace hail
