// integrate_positions without planes (kernel/solver/integrate.h): every sphere of every step
// moves here, a batch of spheres at a time. The scalar reference is integrate_free_scalar; the
// arithmetic is its own, operation for operation (IEEE adds, multiplies, divisions and square
// roots give the same bits in a lane as in a scalar register, and no path fuses a multiply
// and an add), with selects where it branches: the uniform integrator's acceleration
// (uniform_step_acceleration) is zero without a pull and shrunk only outside its ball. A
// batch holding a sphere that continuous collision moved already goes to the scalar code, as
// do the spheres past the last whole batch. Compiled once per SIMD path
// (kernel/dispatch/simd_arch.h).
//
// Why: GCC left the scalar loop scalar whatever its spelling (branch-free, restrict pointers:
// "control flow in loop"), and the uniform integrator cost twice semi-implicit Euler's
// instructions (docs/benchmarks.md, "Lean").

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "hail/sphere_soa.h"
#include "kernel/simd/kernels.h"
#include "kernel/solver/integrate.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

void integrate_free(SphereSoA& s, std::size_t first, std::size_t last, const IntegrationParams& p,
                    const std::uint8_t* skip) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::size_t W = batch::size;
  const bool uniform = p.modes.uniform_acceleration();
  const bool scaled = p.modes.gravity_scaled, forces = p.modes.forces;
  const batch zero(0.0f), one(1.0f), half(0.5f), dt(p.dt), inv_dt(1.0f / p.dt);
  const batch gx(p.gravity[0]), gy(p.gravity[1]), gz(p.gravity[2]);
  std::size_t i = first;
  for (; i + W <= last; i += W) {
    if (skip) {
      std::uint8_t any = 0;
      for (std::size_t l = 0; l < W; ++l) any |= skip[i + l];
      if (any) {
        integrate_free_scalar(s, i, i + W, p, skip);
        continue;
      }
    }
    const batch vx = batch::load_unaligned(s.vx.data() + i);
    const batch vy = batch::load_unaligned(s.vy.data() + i);
    const batch vz = batch::load_unaligned(s.vz.data() + i);
    batch ax = zero, ay = zero, az = zero;
    if (uniform) {
      const batch inv_mass = batch::load_unaligned(s.inv_mass.data() + i);
      const batch scale = scaled ? batch::load_unaligned(s.gravity_scale.data() + i) : one;
      const batch movable = xsimd::select(inv_mass > zero, scale, zero);
      batch f0 = gx * movable, f1 = gy * movable, f2 = gz * movable;
      if (forces) {
        f0 = f0 + batch::load_unaligned(s.force_x.data() + i) * inv_mass;
        f1 = f1 + batch::load_unaligned(s.force_y.data() + i) * inv_mass;
        f2 = f2 + batch::load_unaligned(s.force_z.data() + i) * inv_mass;
      }
      const batch ff = f0 * f0 + f1 * f1 + f2 * f2;
      const auto pulled = ff > zero;
      const batch m0 = (vx - batch::load_unaligned(p.start_vx + i)) * inv_dt;
      const batch m1 = (vy - batch::load_unaligned(p.start_vy + i)) * inv_dt;
      const batch m2 = (vz - batch::load_unaligned(p.start_vz + i)) * inv_dt;
      const batch share = (m0 * f0 + m1 * f1 + m2 * f2) / xsimd::select(pulled, ff, one);
      const batch along = xsimd::select(share < zero, zero, xsimd::select(share > one, one, share));
      batch c0 = m0 - share * f0, c1 = m1 - share * f1, c2 = m2 - share * f2;
      const batch across2 = c0 * c0 + c1 * c1 + c2 * c2;
      const batch bound2 = ff * along * (one - along);
      const auto outside = across2 > bound2;
      const batch shrink = xsimd::sqrt(bound2 / xsimd::select(outside, across2, one));
      c0 = xsimd::select(outside, c0 * shrink, c0);
      c1 = xsimd::select(outside, c1 * shrink, c1);
      c2 = xsimd::select(outside, c2 * shrink, c2);
      ax = xsimd::select(pulled, along * f0 + c0, zero);
      ay = xsimd::select(pulled, along * f1 + c1, zero);
      az = xsimd::select(pulled, along * f2 + c2, zero);
    }
    const batch ux = vx - ax * dt, uy = vy - ay * dt, uz = vz - az * dt;
    (batch::load_unaligned(s.px.data() + i) + (ux * dt + half * ax * dt * dt)).store_unaligned(s.px.data() + i);
    (batch::load_unaligned(s.py.data() + i) + (uy * dt + half * ay * dt * dt)).store_unaligned(s.py.data() + i);
    (batch::load_unaligned(s.pz.data() + i) + (uz * dt + half * az * dt * dt)).store_unaligned(s.pz.data() + i);
    (ux + ax * dt).store_unaligned(s.vx.data() + i);
    (uy + ay * dt).store_unaligned(s.vy.data() + i);
    (uz + az * dt).store_unaligned(s.vz.data() + i);
  }
  if (i < last) integrate_free_scalar(s, i, last, p, skip);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
