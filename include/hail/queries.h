#pragma once
// World queries (World::raycast and friends, kernel/world/world_queries.cpp): what a ray, a
// swept sphere or an overlap test finds among a World's spheres, terrain, meshes and planes, between
// steps. The types here are plain values; the queries never change the world.

#include <cstdint>
#include <limits>

#include "hail/collision_filter.h"
#include "hail/sphere_soa.h"
#include "hail/vec3.h"

namespace hail {

/// What a query reports. A sphere is reported when its category (SphereDesc::filter.category,
/// SphereSoA::collision_category) shares a bit with `mask` and it is not `ignore`; the terrain,
/// the planes and the meshes when their flag is set. The default reports everything.
struct QueryFilter {
  std::uint32_t mask = kAllCategories;
  bool terrain = true;
  bool planes = true;
  SphereId ignore{};  ///< a handle to leave out (e.g. the caster itself); the default names none
  bool meshes = true;
};

/// What a hit touched.
enum class QueryHitKind : std::uint8_t {
  Sphere = 0,   ///< QueryHit::sphere names it
  Terrain = 1,  ///< QueryHit::index is the triangle (Terrain::triangle, BVH order)
  Plane = 2,    ///< QueryHit::index is the plane (World::planes)
  Mesh = 3,     ///< QueryHit::index is the mesh (World::add_mesh's index), QueryHit::triangle its triangle
};

/// One hit of a ray or a swept sphere.
struct QueryHit {
  QueryHitKind kind = QueryHitKind::Sphere;
  SphereId sphere{};              ///< the sphere hit (kind Sphere), else the default handle
  std::uint32_t index = 0;        ///< terrain triangle, plane or mesh index (kind Terrain, Plane, Mesh), else 0
  Vec3 point{0.0f, 0.0f, 0.0f};   ///< where the surface was met, m (a swept sphere: its contact point)
  Vec3 normal{0.0f, 0.0f, 0.0f};  ///< unit, out of what was hit, towards the ray's origin side
  float distance = 0.0f;          ///< along the (normalised) direction from the origin, m
  /// kind Mesh: the triangle hit, as a mesh Contact::feature numbers it without kMeshFeature
  /// (the world's mesh triangles one after another); else 0.
  std::uint32_t triangle = 0;
};

/// A ray origin + s * direction / |direction|, s in [0, max_distance): distances are metres
/// whatever the length of `direction` (not zero). max_distance may be infinite.
struct Ray {
  Vec3 origin{0.0f, 0.0f, 0.0f};
  Vec3 direction{0.0f, -1.0f, 0.0f};
  float max_distance = std::numeric_limits<float>::infinity();
};

/// The order of hits along a ray (World::raycast_all) and of equal-distance candidates for the
/// closest hit: by distance, then kind (spheres, the terrain, planes, meshes), then the sphere's
/// handle index, triangle, plane or mesh index and triangle. The same on any thread count and
/// SIMD path.
[[nodiscard]] inline bool hit_before(const QueryHit& a, const QueryHit& b) {
  if (a.distance != b.distance) return a.distance < b.distance;
  if (a.kind != b.kind) return a.kind < b.kind;
  if (a.kind == QueryHitKind::Sphere) return a.sphere.index < b.sphere.index;
  if (a.index != b.index) return a.index < b.index;
  return a.triangle < b.triangle;
}

}  // namespace hail
