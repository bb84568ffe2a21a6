#pragma once
// Collision filtering by category and mask bits, Box2D's rule: two things collide when each
// one's category shares a bit with the other's mask. Spheres carry one each (SphereDesc::filter,
// World::set_collision_filter); the default collides with everything.

#include <cstdint>

namespace hail {

/// Category bit of a sphere that was given none.
inline constexpr std::uint32_t kDefaultCategory = 0x1u;
/// A mask that accepts every category.
inline constexpr std::uint32_t kAllCategories = 0xFFFFFFFFu;

struct CollisionFilter {
  std::uint32_t category = kDefaultCategory;  ///< the bits this one is (usually one)
  std::uint32_t mask = kAllCategories;        ///< the categories it collides with
  friend bool operator==(CollisionFilter, CollisionFilter) = default;
};

/// Whether a and b collide: each one's category is in the other's mask. Symmetric.
[[nodiscard]] constexpr bool should_collide(CollisionFilter a, CollisionFilter b) noexcept {
  return (a.category & b.mask) != 0 && (b.category & a.mask) != 0;
}

}  // namespace hail
