#pragma once
// Inputs shared by the microbenchmarks: the terrain-rain terrain, query spheres on it, and the
// sphere clouds the pair searches run on. Every input comes from a literal seed and is made once
// per benchmark, outside the timed loop, so two runs time the same work.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/sphere_soa.h"
#include "kernel/geometry/aabb.h"
#include "kernel/terrain/terrain_parts.h"

namespace hail::micro {

/// terrain-rain's terrain (256 x 256 vertices, h = 8 sin(0.05x) cos(0.07z) + 3 sin(0.21x + 0.13z),
/// leaf size 4), built on first use and kept.
const Terrain& rain_terrain();
/// Its triangles' boxes in BVH order (what Terrain keeps privately for the packet walk's leaf filter).
std::span<const Aabb> rain_triangle_bounds();
/// The box of the whole terrain (the Morton grid's bounds).
Aabb rain_terrain_box();

/// A query sphere (or a path's start, with its velocity).
struct Query {
  float x, y, z, r;
  float vx = 0, vy = 0, vz = 0;
};

/// Query order: as drawn (random over the terrain) or sorted by Morton code.
enum class Order { Random, Morton };
const char* name_of(Order order);

/// `count` spheres of r 0.5 on or just above the terrain (-0.05..0.3 m above resting), at
/// random (x, z), falling at 0..3 m/s (`hail-bench query`'s set plus a velocity).
std::vector<Query> resting_queries(std::size_t count, Order order, std::uint32_t seed);
/// `count` spheres of r 0.5 falling fast from 1..3 m above the terrain at 30..300 m/s, slightly
/// off vertical: the paths continuous collision sweeps (up to 5 m in a 1/60 s step).
std::vector<Query> falling_queries(std::size_t count, Order order, std::uint32_t seed);
/// The queries sorted by the Morton code of their centres over the terrain's box.
void sort_by_morton(std::vector<Query>& queries);

/// Appends a sphere of mass 1 with restitution and friction 0.5.
void add_sphere(SphereSoA& s, float x, float y, float z, float r, float vx = 0, float vy = 0, float vz = 0);

/// Cloud shapes for the pair searches.
enum class Cloud {
  Rain,   ///< terrain-rain's layout: r 0.5 on a square lattice 1.5 m apart in layers 1.5 m apart
          ///< (side min(160, ceil(sqrt n))), each centre jittered by up to 0.3 m so that neighbours pair
  Mixed,  ///< `hail-bench pairs`' mixed pile: r 0.25..2.5, 1% r 5, random in a cube at volume fraction 0.3
};
const char* name_of(Cloud cloud);
/// n spheres of the given cloud, in generation order; velocities 0..1 m/s random.
SphereSoA make_cloud(Cloud cloud, std::size_t n, std::uint32_t seed);

}  // namespace hail::micro
