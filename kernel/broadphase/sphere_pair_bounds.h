#pragma once
// Conservative per-axis bounds for the pair predicate (spheres_within in kernel/broadphase/sphere_pairs.h),
// shared by the pair searches that prune with intervals or boxes before testing it
// (SortedAxisPairs, SphereBvhPairs). Pruning must never drop a pair the predicate accepts, or the
// searches would stop agreeing with brute force. Float rounding needs no widening here, because
// of a property of the predicate (round to nearest, no FMA; tests/test_broadphase.cpp checks it):
//
//   If spheres_within accepts with reach = fl(rj + ri_margin), then on every axis, in exact
//   arithmetic, |xj - xi| <= |rj + ri_margin| <= |ri_margin| + |rj|.
//
// Proof. fl(dx^2) <= d2 (adding non-negative squares never rounds below one of them) and
// d2 < fl(reach^2); fl(t^2) is monotone in |t|, so the float |dx| = |fl(xj - xi)| is below |reach|,
// at most the float before it. Rounding is monotone, so the exact |xj - xi| is at most the
// midpoint between that float and |reach| (beyond it, it would round to |reach| or up), and
// |rj + ri_margin|, which rounds to |reach|, is at least that midpoint. (When |reach| overflows,
// the "midpoint" is the overflow threshold, and an accepted dx is finite, hence below it.)
//
// So a box of half-extent |rj| around sphere j and one of |ri_margin| around sphere i overlap
// (closed boxes) for every accepted pair: xj - xi <= qi + ej exactly gives xj - ej <= xi + qi,
// and rounding both sides keeps that order. A window of half-width W = fl(|ri_margin| + R) for any
// float R >= |rj| holds xj as well: |xj - xi| <= |rj + ri_margin| <= W, and rounding xi +- W
// cannot pass the float xj. Overflow to infinity only widens.

#include <cmath>

namespace hail {

/// Half-width of a window on one axis around sphere i's centre that holds the centre of every
/// sphere j the predicate pairs it with, given ri_margin = ri + margin (brute force's float)
/// and any float rj_bound >= |rj| (a maximum of radii).
[[nodiscard]] inline float axis_reach_bound(float ri_margin, float rj_bound) { return std::fabs(ri_margin) + rj_bound; }

/// Half-extent of a box around a centre, exactly |v|: sphere j's box with v = rj and sphere i's
/// query box with v = ri + margin (brute force's float) overlap for every pair the predicate
/// accepts. Any rounding down here (a scale, a split margin) would break that.
[[nodiscard]] inline float box_half_extent(float v) { return std::fabs(v); }

/// False for a sphere the predicate rejects against everything (a non-finite centre, or a NaN
/// radius or ri + margin): the searches leave such spheres out rather than sort or box them.
[[nodiscard]] inline bool can_pair(float x, float y, float z, float radius) {
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && !std::isnan(radius);
}

}  // namespace hail
