#pragma once
// A static plane as the World stores it (World::planes()); PlaneDesc (hail/world.h) adds one.

#include <cmath>

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

/// The sphere whose plane_gap is `gap` touches the plane: the gap is at most about eight float
/// roundings of its terms above zero. A sphere resting on a plane is held on it only to within
/// rounding; one left a hair above it had no contact for a step, met the plane as an impact
/// instead, and for the rest of that step nothing resisted its pull along the plane (a sphere
/// rolling down a slope against rolling resistance gained one step of free acceleration).
inline bool plane_touching(const Plane& p, float x, float y, float z, float r, float gap) {
  const float scale =
      std::fabs(p.nx * x) + std::fabs(p.ny * y) + std::fabs(p.nz * z) + std::fabs(p.offset) + r;
  return gap <= 0x1p-20f * scale;
}

}  // namespace hail
