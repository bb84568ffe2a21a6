// World queries (include/hail/world.h, "World queries"): rays, swept spheres and overlaps
// against the spheres, the terrain and the planes. Spheres are found through SphereQueryBvh,
// rebuilt lazily by SphereQueryCache (kernel/world/sphere_query_cache.h); the terrain through its
// own BVH; planes one by one (there are few). Every result is ordered by a rule of its own
// (hit_before, handle index), never by the order a walk happened to meet things, so it is the
// same on any thread count.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>

#include "hail/world.h"
#include "jobs/parallel_blocks.h"
#include "kernel/bvh/sphere_ray_walk.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/swept_sphere.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/terrain/terrain_parts.h"
#include "kernel/world/ray_batch_leaf_test.h"
#include "kernel/world/world_checks.h"
#include "kernel/world/world_services.h"

namespace hail {

using checks::number;
using checks::require;

namespace {

std::string vec_text(const Vec3& v) { return "(" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + ")"; }

bool finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

UnitRay check_ray(const Ray& ray, const char* call) {
  require(finite(ray.origin),
          [&] { return std::string(call) + ": ray origin " + vec_text(ray.origin) + " is not finite"; });
  Vec3 v = ray.direction;
  require(finite(v) && !(v.x() == 0.0f && v.y() == 0.0f && v.z() == 0.0f),
          [&] { return std::string(call) + ": ray direction " + vec_text(v) + " must be finite and not zero"; });
  float length = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
  // Any non-zero length works (include/hail/queries.h): one whose square leaves float range
  // (3e38) or underflows (1e-40) is scaled by its largest component first, as add_plane does.
  if (!(std::isfinite(length) && length > 1e-18f)) {
    v /= v.cwiseAbs().maxCoeff();
    length = v.norm();
  }
  require(ray.max_distance >= 0.0f, [&] {
    return std::string(call) + ": max_distance = " + number(ray.max_distance) + " must be >= 0 (infinity allowed)";
  });
  return {{ray.origin.x(), ray.origin.y(), ray.origin.z()},
          {v.x() / length, v.y() / length, v.z() / length},
          ray.max_distance};
}

void check_radius(float radius, const char* call) {
  require(std::isfinite(radius) && radius >= 0.0f,
          [&] { return std::string(call) + ": radius = " + number(radius) + " must be finite and >= 0"; });
}

Vec3 along(const UnitRay& r, float s) { return {r.o[0] + s * r.d[0], r.o[1] + s * r.d[1], r.o[2] + s * r.d[2]}; }

/// A sphere hit at distance s by a ball of `grow` swept along the ray (grow 0: the ray itself).
QueryHit sphere_hit(const SphereQueryBvh& s, std::uint32_t k, const UnitRay& r, float dist, float grow) {
  const Vec3 centre = along(r, dist);
  Vec3 normal = centre - Vec3(s.x[k], s.y[k], s.z[k]);
  const float n = normal.norm();
  normal = n > 0.0f && dist > 0.0f ? Vec3(normal / n) : Vec3(-r.d[0], -r.d[1], -r.d[2]);
  return {QueryHitKind::Sphere, s.handle[k], 0, centre - grow * normal, normal, dist};
}

/// Distance at which a ball of radius `grow` on the ray meets plane p's solid (0 from inside),
/// or kRayMiss; moving along or away from it misses.
float ray_plane(const UnitRay& r, const Plane& p, float grow) {
  const float gap = p.nx * r.o[0] + p.ny * r.o[1] + p.nz * r.o[2] - p.offset - grow;
  if (gap <= 0.0f) return 0.0f;
  const float closing = -(p.nx * r.d[0] + p.ny * r.d[1] + p.nz * r.d[2]);
  if (!(closing > 0.0f)) return kRayMiss;
  const float s = gap / closing;
  return std::isfinite(s) ? s : kRayMiss;
}

QueryHit plane_hit(const UnitRay& r, const Plane& p, std::uint32_t index, float dist, float grow) {
  const Vec3 n(p.nx, p.ny, p.nz);
  return {QueryHitKind::Plane, {}, index, along(r, dist) - grow * n, n, dist};
}

/// A terrain hit of the ray (the triangle's normal turned to face the ray's origin side).
QueryHit terrain_hit(const UnitRay& r, const TerrainTriangles& tri, std::uint32_t k, float dist) {
  Vec3 n(tri.nx[k], tri.ny[k], tri.nz[k]);
  if (n.x() * r.d[0] + n.y() * r.d[1] + n.z() * r.d[2] > 0.0f) n = -n;
  return {QueryHitKind::Terrain, {}, k, along(r, dist), n, dist};
}

/// A hit of the ray on mesh m's triangle k (BVH order), the normal turned to face the ray's origin side.
QueryHit mesh_hit(const UnitRay& r, const MeshCollider& mesh, std::uint32_t m, std::uint32_t k, float dist) {
  const TerrainTriangles& tri = mesh.triangles;
  Vec3 n(tri.nx[k], tri.ny[k], tri.nz[k]);
  if (n.x() * r.d[0] + n.y() * r.d[1] + n.z() * r.d[2] > 0.0f) n = -n;
  return {QueryHitKind::Mesh, {}, m, along(r, dist), n, dist, mesh.first_feature + k};
}

/// Mesh m's triangle k as float corners, for the ray and sweep tests.
struct Corners {
  float a[3], b[3], c[3];
};
Corners corners(const TerrainTriangles& tri, std::uint32_t k) {
  return {
      {tri.v0x[k], tri.v0y[k], tri.v0z[k]}, {tri.v1x[k], tri.v1y[k], tri.v1z[k]}, {tri.v2x[k], tri.v2y[k], tri.v2z[k]}};
}

/// Overlap results by handle index (unique among live spheres).
void sort_by_handle(std::vector<SphereId>& ids) {
  std::sort(ids.begin(), ids.end(), [](SphereId a, SphereId b) { return a.index < b.index; });
}

void keep_if_before(std::optional<QueryHit>& best, const QueryHit& hit) {
  if (!best || hit_before(hit, *best)) best = hit;
}

/// The closest hit of ray r on any mesh (both faces count, as on terrain).
void closest_mesh(const MeshSet* meshes, const UnitRay& r, std::optional<QueryHit>& best) {
  for (std::uint32_t m = 0; meshes && m < meshes->size(); ++m) {
    const MeshCollider& mesh = (*meshes)[m];
    const RayHit hit = query_ray(mesh.bvh, r.o, r.d, r.max, [&](std::uint32_t k) {
      const Corners t = corners(mesh.triangles, k);
      return ray_triangle(r.o, r.d, t.a, t.b, t.c);
    });
    if (hit.primitive != kNoPrimitive) keep_if_before(best, mesh_hit(r, mesh, m, hit.primitive, hit.t));
  }
}

/// Closest sphere hit of a ball of radius `grow` swept along r (grow 0: a ray): the scalar
/// reference walk (kernel/bvh/sphere_ray_walk.h).
std::optional<QueryHit> closest_sphere(const SphereQueryBvh& s, const UnitRay& r, float grow,
                                       const QueryFilter& filter) {
  const SphereRayHit best = closest_sphere_scalar(s, r, grow, filter);
  if (best.k == kNoPrimitive) return std::nullopt;
  return sphere_hit(s, best.k, r, best.t, grow);
}

std::optional<QueryHit> closest_plane(std::span<const Plane> planes, const UnitRay& r, float grow) {
  std::optional<QueryHit> best;
  for (std::uint32_t k = 0; k < planes.size(); ++k) {
    const float t = ray_plane(r, planes[k], grow);
    if (t >= 0.0f && t < r.max) keep_if_before(best, plane_hit(r, planes[k], k, t, grow));
  }
  return best;
}

/// The closest hit of ray r, given its closest sphere (closest_sphere_scalar or the SIMD kernel):
/// the terrain and the planes added.
std::optional<QueryHit> closest_hit(const SphereQueryBvh& s, const Terrain* terrain, const MeshSet* meshes,
                                    std::span<const Plane> planes, const UnitRay& r, const QueryFilter& filter,
                                    const SphereRayHit& sphere) {
  std::optional<QueryHit> best;
  if (sphere.k != kNoPrimitive) best = sphere_hit(s, sphere.k, r, sphere.t, 0.0f);
  if (terrain && filter.terrain) {
    // Terrain::raycast with the unit direction: its t is the distance in metres.
    const auto hit = terrain->raycast(Vec3(r.o[0], r.o[1], r.o[2]), Vec3(r.d[0], r.d[1], r.d[2]), r.max);
    if (hit) keep_if_before(best, terrain_hit(r, terrain->triangles(), hit->triangle, hit->t));
  }
  if (filter.meshes) closest_mesh(meshes, r, best);
  if (filter.planes)
    if (auto p = closest_plane(planes, r, 0.0f)) keep_if_before(best, *p);
  return best;
}

std::atomic<RayBatchLeafTest> batch_leaf_test{RayBatchLeafTest::Simd};

}  // namespace

void set_ray_batch_leaf_test(RayBatchLeafTest test) { batch_leaf_test.store(test, std::memory_order_relaxed); }
RayBatchLeafTest ray_batch_leaf_test() { return batch_leaf_test.load(std::memory_order_relaxed); }

std::uint64_t World::query_cache_builds() const { return services_->sphere_queries.builds(); }

std::optional<QueryHit> World::raycast(const Ray& ray, const QueryFilter& filter) const {
  const UnitRay r = check_ray(ray, "World::raycast");
  const SphereQueryBvh& s = services_->sphere_queries.get(spheres_);
  return closest_hit(s, terrain_.get(), has_meshes() ? meshes_.get() : nullptr, planes_, r, filter,
                     closest_sphere_scalar(s, r, 0.0f, filter));
}

void World::raycast_batch(std::span<const Ray> rays, std::span<std::optional<QueryHit>> hits,
                          const QueryFilter& filter) const {
  require(rays.size() == hits.size(), [&] {
    return "World::raycast_batch: " + std::to_string(rays.size()) + " rays but room for " +
           std::to_string(hits.size()) + " hits";
  });
  for (std::size_t k = 0; k < rays.size(); ++k) {
    try {
      (void)check_ray(rays[k], "World::raycast_batch");
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(std::string(e.what()) + " (ray " + std::to_string(k) + ")");
    }
  }
  const SphereQueryBvh& s = services_->sphere_queries.get(spheres_);
  const Terrain* terrain = terrain_.get();
  const MeshSet* meshes = has_meshes() ? meshes_.get() : nullptr;
  const bool simd = ray_batch_leaf_test() == RayBatchLeafTest::Simd;
  const SimdKernels& kernels = simd_kernels();
  // Each ray is answered alone, so any split of the rays gives the same bits; blocks of 64 rays
  // keep the task overhead small beside a few BVH walks, and the kernel table is called once a block.
  constexpr std::size_t kRaysPerBlock = 64;
  arena_->execute([&] {
    for_each_block(rays.size(), kRaysPerBlock, [&](std::size_t, std::size_t first, std::size_t last) {
      UnitRay unit[kRaysPerBlock];
      SphereRayHit sphere[kRaysPerBlock];
      const std::size_t count = last - first;
      for (std::size_t k = 0; k < count; ++k) unit[k] = check_ray(rays[first + k], "World::raycast_batch");
      if (simd) {
        kernels.closest_sphere_rays(s, unit, count, filter, sphere);
      } else {
        for (std::size_t k = 0; k < count; ++k) sphere[k] = closest_sphere_scalar(s, unit[k], 0.0f, filter);
      }
      for (std::size_t k = 0; k < count; ++k)
        hits[first + k] = closest_hit(s, terrain, meshes, planes_, unit[k], filter, sphere[k]);
    });
  });
}

std::vector<QueryHit> World::raycast_all(const Ray& ray, const QueryFilter& filter) const {
  const UnitRay r = check_ray(ray, "World::raycast_all");
  const SphereQueryBvh& s = services_->sphere_queries.get(spheres_);
  std::vector<QueryHit> hits;
  const float inv[3] = {1.0f / r.d[0], 1.0f / r.d[1], 1.0f / r.d[2]};
  walk_stackless(
      s.bvh.nodes, [&](const FlatNode& n) { return ray_overlaps(n, r.o, inv, r.max); },
      [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = first; k < first + count; ++k) {
          if (!sphere_passes(s, k, filter)) continue;
          const float t = ray_sphere(r.o, r.d, s.x[k], s.y[k], s.z[k], s.r[k]);
          if (t >= 0.0f && t < r.max) hits.push_back(sphere_hit(s, k, r, t, 0.0f));
        }
      });
  if (terrain_ && filter.terrain) {
    const TerrainTriangles& tri = terrain_->triangles();
    walk_stackless(
        terrain_->bvh().nodes, [&](const FlatNode& n) { return ray_overlaps(n, r.o, inv, r.max); },
        [&](std::uint32_t first, std::uint32_t count) {
          for (std::uint32_t k = first; k < first + count; ++k) {
            const float a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]};
            const float b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
            const float c[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]};
            const float t = ray_triangle(r.o, r.d, a, b, c);
            if (t >= 0.0f && t < r.max) hits.push_back(terrain_hit(r, tri, k, t));
          }
        });
  }
  for (std::uint32_t m = 0; filter.meshes && has_meshes() && m < meshes_->size(); ++m) {
    const MeshCollider& mesh = (*meshes_)[m];
    walk_stackless(
        mesh.bvh.nodes, [&](const FlatNode& n) { return ray_overlaps(n, r.o, inv, r.max); },
        [&](std::uint32_t first, std::uint32_t count) {
          for (std::uint32_t k = first; k < first + count; ++k) {
            const Corners t = corners(mesh.triangles, k);
            const float d = ray_triangle(r.o, r.d, t.a, t.b, t.c);
            if (d >= 0.0f && d < r.max) hits.push_back(mesh_hit(r, mesh, m, k, d));
          }
        });
  }
  if (filter.planes)
    for (std::uint32_t k = 0; k < planes_.size(); ++k) {
      const float t = ray_plane(r, planes_[k], 0.0f);
      if (t >= 0.0f && t < r.max) hits.push_back(plane_hit(r, planes_[k], k, t, 0.0f));
    }
  std::sort(hits.begin(), hits.end(), hit_before);
  return hits;
}

std::optional<QueryHit> World::sphere_cast(const Ray& ray, float radius, const QueryFilter& filter) const {
  const UnitRay r = check_ray(ray, "World::sphere_cast");
  check_radius(radius, "World::sphere_cast");
  std::optional<QueryHit> best = closest_sphere(services_->sphere_queries.get(spheres_), r, radius, filter);
  if (terrain_ && filter.terrain) {
    // kernel/geometry/swept_sphere.h in double, every edge a real edge (no internal-edge
    // smoothing: a query reports the geometry as it is).
    const TerrainTriangles& tri = terrain_->triangles();
    const double centre[3] = {r.o[0], r.o[1], r.o[2]}, v[3] = {r.d[0], r.d[1], r.d[2]};
    const double t_max = r.max;
    auto sweep = [&](std::uint32_t k, SweptHit& hit) {
      const double a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]}, b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
      const double c[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]}, n[3] = {tri.nx[k], tri.ny[k], tri.nz[k]};
      return swept_sphere_triangle(centre, v, radius, a, b, c, n, 0, t_max, hit);
    };
    const RayHit hit = query_swept_sphere(terrain_->bvh(), r.o, r.d, r.max, radius, [&](std::uint32_t k) {
      SweptHit h;
      return sweep(k, h) ? static_cast<float>(h.t) : kRayMiss;
    });
    if (hit.primitive != kNoPrimitive && hit.t < r.max) {
      SweptHit h;
      (void)sweep(hit.primitive, h);
      const Vec3 into(static_cast<float>(h.n[0]), static_cast<float>(h.n[1]), static_cast<float>(h.n[2]));
      keep_if_before(best, {QueryHitKind::Terrain, {}, hit.primitive, along(r, hit.t) + radius * into, -into, hit.t});
    }
  }
  for (std::uint32_t m = 0; filter.meshes && has_meshes() && m < meshes_->size(); ++m) {
    // As the terrain; a shell's triangle is met on the face the cast starts in front of (its
    // corners reversed and its normal turned for an origin behind it).
    const MeshCollider& mesh = (*meshes_)[m];
    const TerrainTriangles& tri = mesh.triangles;
    const double centre[3] = {r.o[0], r.o[1], r.o[2]}, v[3] = {r.d[0], r.d[1], r.d[2]};
    auto sweep = [&](std::uint32_t k, SweptHit& hit) {
      double a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]}, b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
      double c[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]}, n[3] = {tri.nx[k], tri.ny[k], tri.nz[k]};
      if (mesh.two_sided && n[0] * centre[0] + n[1] * centre[1] + n[2] * centre[2] < double{tri.d[k]})
        for (int d = 0; d < 3; ++d) std::swap(b[d], c[d]), n[d] = -n[d];
      return swept_sphere_triangle(centre, v, radius, a, b, c, n, 0, double{r.max}, hit);
    };
    const RayHit hit = query_swept_sphere(mesh.bvh, r.o, r.d, r.max, radius, [&](std::uint32_t k) {
      SweptHit h;
      return sweep(k, h) ? static_cast<float>(h.t) : kRayMiss;
    });
    if (hit.primitive != kNoPrimitive && hit.t < r.max) {
      SweptHit h;
      (void)sweep(hit.primitive, h);
      const Vec3 into(static_cast<float>(h.n[0]), static_cast<float>(h.n[1]), static_cast<float>(h.n[2]));
      keep_if_before(best, {QueryHitKind::Mesh,
                            {},
                            m,
                            along(r, hit.t) + radius * into,
                            -into,
                            hit.t,
                            mesh.first_feature + hit.primitive});
    }
  }
  if (filter.planes)
    if (auto p = closest_plane(planes_, r, radius)) keep_if_before(best, *p);
  return best;
}

std::vector<SphereId> World::overlap_sphere(const Vec3& centre, float radius, const QueryFilter& filter) const {
  require(finite(centre), [&] { return "World::overlap_sphere: centre " + vec_text(centre) + " is not finite"; });
  check_radius(radius, "World::overlap_sphere");
  const SphereQueryBvh& s = services_->sphere_queries.get(spheres_);
  std::vector<SphereId> found;
  query_sphere(s.bvh, centre.x(), centre.y(), centre.z(), radius, [&](std::uint32_t k) {
    if (!sphere_passes(s, k, filter)) return;
    const float dx = s.x[k] - centre.x(), dy = s.y[k] - centre.y(), dz = s.z[k] - centre.z();
    const float reach = s.r[k] + radius;
    if (dx * dx + dy * dy + dz * dz <= reach * reach) found.push_back(s.handle[k]);
  });
  sort_by_handle(found);
  return found;
}

std::vector<SphereId> World::overlap_box(const Vec3& min, const Vec3& max, const QueryFilter& filter) const {
  require(finite(min) && finite(max),
          [&] { return "World::overlap_box: box " + vec_text(min) + " .. " + vec_text(max) + " is not finite"; });
  require(min.x() <= max.x() && min.y() <= max.y() && min.z() <= max.z(),
          [&] { return "World::overlap_box: min " + vec_text(min) + " exceeds max " + vec_text(max); });
  const SphereQueryBvh& s = services_->sphere_queries.get(spheres_);
  const Aabb box{{min.x(), min.y(), min.z()}, {max.x(), max.y(), max.z()}};
  std::vector<SphereId> found;
  query_aabb(s.bvh, box, [&](std::uint32_t k) {
    if (!sphere_passes(s, k, filter)) return;
    // Squared distance from the centre to the box: the sphere touches it within its radius.
    const float c[3] = {s.x[k], s.y[k], s.z[k]};
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float out = c[a] < box.min[a] ? box.min[a] - c[a] : (c[a] > box.max[a] ? c[a] - box.max[a] : 0.0f);
      d2 += out * out;
    }
    if (d2 <= s.r[k] * s.r[k]) found.push_back(s.handle[k]);
  });
  sort_by_handle(found);
  return found;
}

}  // namespace hail
