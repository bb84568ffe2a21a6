#include "kernel/solver/integrate.h"

#include <cmath>

#include "kernel/broadphase/sphere_filters.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/fast_motion.h"
#include "kernel/solver/contact_impulse.h"

namespace hail {

namespace {
/// predict_velocities' first pass; `Scaled` false is the loop without the multiply by the
/// gravity scale (every scale is 1 then, so the result is the same), kept separate so that
/// scenes without scales run exactly the instructions they ran before scales existed.
template <bool Scaled>
float add_gravity(SphereSoA& s, std::size_t first, std::size_t last, const IntegrationParams& p, float fast_fraction,
                  float& fastest) {
  const float gx = p.gravity[0] * p.dt, gy = p.gravity[1] * p.dt, gz = p.gravity[2] * p.dt;
  const float dt2 = p.dt * p.dt;
  float max_speed2 = 0.0f;
  // Branch-free (selects), so that the compiler vectorises it: this runs for every sphere.
  for (std::size_t i = first; i < last; ++i) {
    const bool movable = s.inv_mass[i] > 0.0f;
    // (g dt) scale: at the default scale 1 bitwise the g dt of a world without scales.
    const float scale = Scaled ? s.gravity_scale[i] : 1.0f;
    const float vx = movable ? s.vx[i] + (Scaled ? gx * scale : gx) : s.vx[i];
    const float vy = movable ? s.vy[i] + (Scaled ? gy * scale : gy) : s.vy[i];
    const float vz = movable ? s.vz[i] + (Scaled ? gz * scale : gz) : s.vz[i];
    s.vx[i] = vx, s.vy[i] = vy, s.vz[i] = vz;
    const float v2 = vx * vx + vy * vy + vz * vz;
    const float reach = fast_fraction * s.radius[i];
    const float excess = v2 * dt2 - reach * reach;
    max_speed2 = v2 > max_speed2 ? v2 : max_speed2;
    // Any sphere may be fast, immovable ones included: a static sphere's velocity is zero, and
    // a kinematic one moving far in a step is swept like a dynamic one.
    fastest = excess > fastest ? excess : fastest;
  }
  return max_speed2;
}
}  // namespace

float predict_velocities(SphereSoA& s, std::size_t first, std::size_t last, const IntegrationParams& p,
                         float fast_fraction, std::vector<std::uint32_t>* fast) {
  float fastest = -1.0f;  // fastest > 0: some sphere may be fast
  float max_speed2 = p.modes.gravity_scaled ? add_gravity<true>(s, first, last, p, fast_fraction, fastest)
                                            : add_gravity<false>(s, first, last, p, fast_fraction, fastest);
  if (!fast || !(fastest > 0.0f)) return std::sqrt(max_speed2);
  // Some sphere is fast: list the fast ones and take the largest speed of the others.
  max_speed2 = 0.0f;
  for (std::size_t i = first; i < last; ++i) {
    // The same expression as the terrain's per-sphere margin, so both agree on who is fast.
    const float v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
    if (is_fast(v2, p.dt, s.radius[i], fast_fraction))
      fast->push_back(static_cast<std::uint32_t>(i));
    else
      max_speed2 = v2 > max_speed2 ? v2 : max_speed2;
  }
  return std::sqrt(max_speed2);
}

void apply_forces(SphereSoA& s, std::size_t first, std::size_t last, float dt, bool rotation) {
  for (std::size_t i = first; i < last; ++i) {
    const float linear = s.inv_mass[i] * dt;  // 0 for a static sphere: forces do not move it
    s.vx[i] += s.force_x[i] * linear;
    s.vy[i] += s.force_y[i] * linear;
    s.vz[i] += s.force_z[i] * linear;
  }
  if (!rotation) return;
  for (std::size_t i = first; i < last; ++i) {
    const float angular = s.inv_inertia[i] * dt;
    s.wx[i] += s.torque_x[i] * angular;
    s.wy[i] += s.torque_y[i] * angular;
    s.wz[i] += s.torque_z[i] * angular;
  }
}

double earliest_root(double d0, double vn, double an, double limit) {
  double best = -1.0;
  auto consider = [&](double t) {
    if (t > 0.0 && t <= limit && (best < 0.0 || t < best)) best = t;
  };
  if (std::fabs(an) < 1e-12) {
    if (vn < 0.0) consider(-d0 / vn);
    return best;
  }
  const double a = 0.5 * an, disc = vn * vn - 4.0 * a * d0;
  if (disc < 0.0) return best;
  const double q = -0.5 * (vn + std::copysign(std::sqrt(disc), vn));
  if (q != 0.0) {
    consider(q / a);
    consider(d0 / q);
  }
  return best;
}

namespace {

/// The part of a sphere's step in which it meets planes: up to four impacts, each at its exact
/// time, the motion x, u advanced to it and `remaining` shortened. Out of the loop that runs for
/// every sphere, so that a scene without planes does not carry it there: inlined, it cost
/// every sphere instructions in every step (callgrind: docs/benchmarks.md, "Figures behind the
/// code's choices").
///
/// `a` (the uniform integrator's acceleration; zero under semi-implicit Euler) loses its part into
/// a plane that the sphere comes to rest on: after an impact that leaves the sphere not fast
/// enough to stay off the plane for the rest of the step, the plane carries the pull. Without
/// that the sphere fell into the plane by |a| remaining^2 / 2 after its last impact (1.2 mm at
/// 60 Hz) and stayed there, since the solver owns a contact from the moment it touches.
[[gnu::noinline]] void bounce_off_planes(SphereSoA& s, std::size_t i, std::span<const Plane> planes,
                                         const IntegrationParams& p, float a[3], float x[3], float u[3],
                                         float& remaining, std::vector<Impact>* impacts) {
  for (int impact = 0; impact < 4; ++impact) {
    double hit_t = -1.0;
    std::size_t hit_plane = 0;
    for (std::size_t k = 0; k < planes.size(); ++k) {
      const Plane& pl = planes[k];
      const float d0 = plane_gap(pl, x[0], x[1], x[2], s.radius[i]);
      // Touching: the solver owns this contact. At the step's start by detection's own rule
      // (find_plane_contacts), after an impact only where the sphere reached the plane.
      const bool owned = impact == 0 ? plane_touching(pl, x[0], x[1], x[2], s.radius[i], d0) : d0 <= 0.0f;
      if (owned) continue;
      const float vn = pl.nx * u[0] + pl.ny * u[1] + pl.nz * u[2];
      const float an = pl.nx * a[0] + pl.ny * a[1] + pl.nz * a[2];
      const double t = earliest_root(d0, vn, an, remaining);
      if (t > 0.0 && (hit_t < 0.0 || t < hit_t)) {
        hit_t = t;
        hit_plane = k;
      }
    }
    if (hit_t < 0.0) break;
    const float t = static_cast<float>(hit_t);
    for (int d = 0; d < 3; ++d) {
      x[d] += u[d] * t + 0.5f * a[d] * t * t;
      u[d] += a[d] * t;
    }
    remaining -= t;
    const Plane& pl = planes[hit_plane];
    Contact contact;
    contact.a = static_cast<std::uint32_t>(i);
    contact.nx = -pl.nx;
    contact.ny = -pl.ny;
    contact.nz = -pl.nz;
    contact.restitution = combine_restitution(s.restitution[i], pl.restitution);
    contact.friction = combine_friction(s.friction[i], pl.friction);
    // Without rotation the impulse acts on the linear velocity alone and w is not touched.
    const bool spin = p.modes.rotation;
    ContactBodies bodies = spin ? gather_bodies<kWithFriction>(s, contact) : gather_bodies<kLinearFriction>(s, contact);
    for (int d = 0; d < 3; ++d) bodies.va[d] = u[d];
    const float j = spin ? solve_impact<kWithFriction>(contact, bodies, p.restitution_threshold)
                         : solve_impact<kLinearFriction>(contact, bodies, p.restitution_threshold);
    if (impacts && j > 0.0f) {
      const float r = s.radius[i];
      impacts->push_back({.a = contact.a,
                          .b = kStaticBody,
                          .feature = kPlaneFeature | static_cast<std::uint32_t>(hit_plane),
                          .time = p.dt - remaining,
                          .px = x[0] + contact.nx * r,
                          .py = x[1] + contact.ny * r,
                          .pz = x[2] + contact.nz * r,
                          .nx = contact.nx,
                          .ny = contact.ny,
                          .nz = contact.nz,
                          .impulse = j});
    }
    for (int d = 0; d < 3; ++d) u[d] = bodies.va[d];
    if (spin) s.wx[i] = bodies.wa[0], s.wy[i] = bodies.wa[1], s.wz[i] = bodies.wa[2];
    // Pulled into the plane (an < 0, the uniform integrator only) and back on it before the
    // step ends (u_n < -an remaining / 2): it rests there for the rest of the step.
    const float an = pl.nx * a[0] + pl.ny * a[1] + pl.nz * a[2];
    if (an < 0.0f) {
      const float un = pl.nx * u[0] + pl.ny * u[1] + pl.nz * u[2];
      if (2.0f * un < -an * remaining) {
        const float n[3] = {pl.nx, pl.ny, pl.nz};
        for (int d = 0; d < 3; ++d) a[d] -= an * n[d], u[d] -= un * n[d];
      }
    }
  }
}

}  // namespace

namespace {
/// integrate_positions' loop; `Filtered`: spheres whose filter rejects p.modes.ground skip the planes.
template <bool Filtered>
void integrate_range(SphereSoA& s, std::size_t first, std::size_t last, std::span<const Plane> planes,
                     const IntegrationParams& p, std::span<const std::uint8_t> skip, std::vector<Impact>* impacts) {
  const bool uniform = p.modes.uniform_acceleration();
  for (std::size_t i = first; i < last; ++i) {
    if (!skip.empty() && skip[i]) continue;
    float a[3] = {0.0f, 0.0f, 0.0f};
    if (uniform) {
      const float v_end[3] = {s.vx[i], s.vy[i], s.vz[i]};
      uniform_step_acceleration(s, i, p, v_end, a);
    }
    float x[3] = {s.px[i], s.py[i], s.pz[i]};
    // Velocity at the start of the (sub)step that reaches the solved end velocity under a
    // (semi-implicit Euler: a = 0, the end velocity itself).
    float u[3] = {s.vx[i] - a[0] * p.dt, s.vy[i] - a[1] * p.dt, s.vz[i] - a[2] * p.dt};
    float remaining = p.dt;
    if (!planes.empty() && (!Filtered || meets_ground(s, i, p.modes.ground)))
      bounce_off_planes(s, i, planes, p, a, x, u, remaining, impacts);
    for (int d = 0; d < 3; ++d) x[d] += u[d] * remaining + 0.5f * a[d] * remaining * remaining;
    s.px[i] = x[0];
    s.py[i] = x[1];
    s.pz[i] = x[2];
    s.vx[i] = u[0] + a[0] * remaining;
    s.vy[i] = u[1] + a[1] * remaining;
    s.vz[i] = u[2] + a[2] * remaining;
  }
}
}  // namespace

void integrate_free_scalar(SphereSoA& s, std::size_t first, std::size_t last, const IntegrationParams& p,
                           const std::uint8_t* skip) {
  const std::span<const std::uint8_t> held = skip ? std::span<const std::uint8_t>(skip, last) : std::span<const std::uint8_t>();
  integrate_range<false>(s, first, last, {}, p, held, nullptr);
}

void integrate_positions(SphereSoA& s, std::size_t first, std::size_t last, std::span<const Plane> planes,
                         const IntegrationParams& p, std::span<const std::uint8_t> skip, std::vector<Impact>* impacts) {
  if (planes.empty()) {  // nothing cuts a sphere's step short: the SIMD kernel
    simd_kernels().integrate_free(s, first, last, p, skip.empty() ? nullptr : skip.data());
    return;
  }
  p.modes.filtering ? integrate_range<true>(s, first, last, planes, p, skip, impacts)
                    : integrate_range<false>(s, first, last, planes, p, skip, impacts);
}

}  // namespace hail
