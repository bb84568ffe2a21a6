#pragma once
// A static plane as the World stores it (World::planes()); PlaneDesc (hail/world.h) adds one.

namespace hail {

/// The solid half-space {x : n.x < offset}.
struct Plane {
  float nx, ny, nz;  ///< unit normal pointing out of the solid
  float offset;      ///< n.x = offset on the surface, m
  float restitution;
  float friction;
};

/// Signed distance from the sphere's surface to the plane (negative when overlapping).
inline float plane_gap(const Plane& p, float x, float y, float z, float r) {
  return p.nx * x + p.ny * y + p.nz * z - p.offset - r;
}

}  // namespace hail
