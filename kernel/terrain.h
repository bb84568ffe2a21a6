#pragma once
// Static terrain: a heightmap's triangles with their per-triangle data computed once at load
// (kernel/terrain_triangles.h: vertices, edges, unit normal, plane offset, internal-edge
// mask), stored SoA in BVH order so that a
// leaf's triangles are contiguous, and the flat BVH over them.

#include <cstdint>
#include <vector>

#include "kernel/contact.h"
#include "kernel/flat_bvh.h"
#include "kernel/heightmap.h"
#include "kernel/terrain_triangles.h"
#include "soa/aligned_array.h"
#include "soa/sphere_soa.h"

namespace hail {

class Terrain {
 public:
  /// Builds triangles and BVH (leaf_size 1..8). Cost: see `hail-bench` set-up time.
  explicit Terrain(Heightmap heightmap, std::uint32_t leaf_size = 4);

  [[nodiscard]] const Heightmap& heightmap() const { return heightmap_; }
  [[nodiscard]] const TerrainTriangles& triangles() const { return triangles_; }
  [[nodiscard]] const FlatBvh& bvh() const { return bvh_; }

  /// Appends the contacts of spheres [first, last) with the terrain, in sphere order: every
  /// triangle whose gap is below the sphere's travel this step (|v| dt, speculative), reduced
  /// so that triangles giving the same normal (a flat area split into many triangles) yield one
  /// contact. Spheres walk the BVH in packets (kernel/bvh_packet_walk.h). No allocation beyond
  /// `out`'s growth.
  /// `restitution` and `friction` are the terrain's material, combined with each sphere's.
  /// Spheres that are fast (is_fast with `fast_fraction`, kernel/continuous_collision.h) reach
  /// no further than fast_fraction of their radius; with `sweep_fast` they get only the
  /// contacts they touch already, since what they meet later in the step is swept.
  void find_contacts(const SphereSoA& spheres, std::size_t first, std::size_t last, float dt, float restitution,
                     float friction, std::vector<Contact>& out, float fast_fraction = 0.0f,
                     bool sweep_fast = false) const;

  /// Deepest penetration (m, >= 0) of a sphere into the terrain: for error reports.
  [[nodiscard]] float penetration(float x, float y, float z, float r) const;

  /// Moves the centre of a sphere of radius r out of the terrain: the deepest overlapping
  /// triangle first, along its contact normal by its overlap, then again for what still
  /// overlaps, at most `rounds` times. Returns whether it moved. For spheres that travelled
  /// further in a step than their contacts reached (kernel/terrain_push_out.cpp).
  bool push_out(float& x, float& y, float& z, float r, int rounds = 4) const;

 private:
  Heightmap heightmap_;
  TerrainTriangles triangles_;
  FlatBvh bvh_;
  std::vector<Aabb> triangle_bounds_;  ///< per triangle, BVH order: the packet walk's leaf filter
};

}  // namespace hail
