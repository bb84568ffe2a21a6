#pragma once
// Axis-aligned bounding boxes: the one thing the BVH knows about its primitives. The tests are
// templates over anything with `min[3]` and `max[3]`, so the same code reads an Aabb and a
// FlatNode (whose bounds are interleaved with its links and cannot be an Aabb member).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>

namespace hail {

/// Closed box [min, max] per axis. An empty box has min = +inf, max = -inf (see empty_aabb()).
struct Aabb {
  float min[3], max[3];
};

/// Anything with float min[3] and max[3]: Aabb, FlatNode.
template <class Box>
concept BoxBounds = requires(const Box& b) {
  { b.min[0] } -> std::convertible_to<float>;
  { b.max[0] } -> std::convertible_to<float>;
};

/// The box that contains nothing: growing it by any box gives that box.
[[nodiscard]] constexpr Aabb empty_aabb() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

/// Enlarges `a` to contain `b`.
template <BoxBounds Box>
constexpr void grow(Aabb& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    a.min[k] = std::min(a.min[k], b.min[k]);
    a.max[k] = std::max(a.max[k], b.max[k]);
  }
}

/// Enlarges `a` to contain point p.
constexpr void grow(Aabb& a, const float p[3]) {
  for (int k = 0; k < 3; ++k) {
    a.min[k] = std::min(a.min[k], p[k]);
    a.max[k] = std::max(a.max[k], p[k]);
  }
}

/// True when the closed boxes share a point (touching faces count).
template <BoxBounds A, BoxBounds B>
[[nodiscard]] constexpr bool overlaps(const A& a, const B& b) {
  return a.min[0] <= b.max[0] && b.min[0] <= a.max[0] && a.min[1] <= b.max[1] && b.min[1] <= a.max[1] &&
         a.min[2] <= b.max[2] && b.min[2] <= a.max[2];
}

/// x > y ? x : y: x86's max instruction exactly (y when either is NaN), and xsimd::max's.
/// The empty asm makes the result a value the compiler must produce in a register, so that it
/// cannot fold what follows into a branch on the comparison (sphere_overlaps).
[[nodiscard]] inline float max_in_register(float x, float y) {
  float m = x > y ? x : y;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm("" : "+x"(m));
#endif
  return m;
}

/// True when the sphere touches the box: squared distance from the centre to the box <= r^2.
/// Exact for boxes of any size (no centre-box inflation, whose corners would over-accept).
template <BoxBounds Box>
[[nodiscard]] inline bool sphere_overlaps(const Box& b, float cx, float cy, float cz, float r) {
  // max(lo - c, c - hi, 0) is the distance outside [lo, hi] (the larger term is the only
  // positive one), computed as the SIMD packet test computes it (xsimd::max in the same operand
  // order, kernel/bvh/bvh_packet_walk.h), so both decide alike. A NaN centre keeps a NaN excess (0
  // comes first in the outer max), so it touches no box. Written with std::max, GCC 12 folded
  // the squaring below into a branch on the sign of the excess: three branches per node that
  // the predictor cannot learn, where Terrain::push_out's scalar walk spent most of its time.
  auto excess = [](float c, float lo, float hi) { return max_in_register(0.0f, max_in_register(lo - c, c - hi)); };
  const float dx = excess(cx, b.min[0], b.max[0]);
  const float dy = excess(cy, b.min[1], b.max[1]);
  const float dz = excess(cz, b.min[2], b.max[2]);
  return dx * dx + dy * dy + dz * dz <= r * r;
}

/// Surface area of the box; 0 for an empty box (SAH weighs an empty side by nothing).
[[nodiscard]] constexpr float surface_area(const Aabb& b) {
  const float x = b.max[0] - b.min[0], y = b.max[1] - b.min[1], z = b.max[2] - b.min[2];
  if (!(x >= 0.0f && y >= 0.0f && z >= 0.0f)) return 0.0f;
  return 2.0f * (x * y + y * z + z * x);
}

/// Axis (0, 1, 2) of the largest extent; the lowest axis wins ties, so the choice is repeatable.
[[nodiscard]] constexpr int longest_axis(const Aabb& b) {
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (b.max[k] - b.min[k] > b.max[axis] - b.min[axis]) axis = k;
  return axis;
}

/// Centre of the box along one axis.
[[nodiscard]] constexpr float centroid(const Aabb& b, int axis) { return 0.5f * (b.min[axis] + b.max[axis]); }

/// True for a box with finite bounds and min <= max on every axis (a point is valid).
[[nodiscard]] inline bool is_valid(const Aabb& b) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k]) || !(b.min[k] <= b.max[k])) return false;
  return true;
}

/// Slab test of the ray o + t d, t in [0, t_max], against the box, given inv_dir = 1 / d
/// per axis (+-inf for a zero component). Conservative: the exit distance is widened by
/// 2 gamma(3) of itself (Pharr et al., PBRT 3.9.2) so rounding never drops a box the ray touches, and
/// a 0 * inf = NaN slab (ray in a face's plane) is ignored rather than rejecting the box.
/// With grow > 0 the box is first grown by that much on every side: a sphere of radius `grow`
/// moving along the ray can touch the box only if this passes (the grown box holds the box's
/// Minkowski sum with the sphere), which continuous collision uses to walk the terrain's BVH.
template <BoxBounds Box>
[[nodiscard]] inline bool ray_overlaps(const Box& b, const float origin[3], const float inv_dir[3], float t_max,
                                       float grow = 0.0f) {
  constexpr float kTwoGamma3 = 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);
  float t0 = 0.0f, t1 = t_max;
  for (int k = 0; k < 3; ++k) {
    float near = (b.min[k] - grow - origin[k]) * inv_dir[k];
    float far = (b.max[k] + grow - origin[k]) * inv_dir[k];
    if (near > far) std::swap(near, far);
    far += std::fabs(far) * kTwoGamma3;
    // Written so that a NaN slab leaves the interval unchanged.
    t0 = near > t0 ? near : t0;
    t1 = far < t1 ? far : t1;
  }
  return t0 <= t1;
}

}  // namespace hail
