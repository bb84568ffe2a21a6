// The depenetration pass (push_apart, kernel/solver/depenetrate.h) over the staged contact batches
// (kernel/solver/contact_solve_simd.h), a batch of contacts per instruction. Compiled once per SIMD
// path (kernel/dispatch/simd_arch.h). Each lane performs push_apart's float operations in its order, so
// every path moves the spheres exactly as the scalar loop over the same contacts does; the
// contacts of a batch belong to one colour and share no sphere, so their order does not matter.
//
// Why: most contacts of a pile sit within the slop and move nothing, and the scalar loop spent
// its time reading 60-byte contacts and branching on each (docs/benchmarks.md, "Figures behind
// the code's choices"). Here a batch reads its slots, normals and offsets from the staged arrays, gathers
// positions only when the skip rule keeps one of its lanes, and stores only for lanes that push.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/simd/gather.h"
#include "kernel/simd/kernels.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/depenetrate.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

using batch = xsimd::batch<float, simd_arch>;
using ibatch = xsimd::batch<std::int32_t, simd_arch>;
constexpr std::size_t W = batch::size;

}  // namespace

bool contact_depenetrate(const ContactBatchArrays& c, std::size_t first, std::size_t last, const DepenetrationArrays& s,
                         std::uint32_t now, std::uint32_t previous) {
  bool deep = false;  // push_apart's deep flag, over every lane that pushes
  const std::int32_t static_slot = s.static_slot;
  const ibatch b_static_slot(static_slot), b_previous(static_cast<std::int32_t>(previous));
  const batch zero(0.0f), slop(s.params.slop_fraction), fraction(s.params.fraction), deep_radius(s.deep_radius);
  const auto* moved = reinterpret_cast<const std::int32_t*>(s.moved);
  alignas(64) float out[6][W];
  alignas(64) std::int32_t slot_a[W], slot_b[W];
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t o = k * W;
    const ibatch a = ibatch::load_aligned(c.a + o), b = ibatch::load_aligned(c.b + o);
    // The skip rule of StepPipeline::depenetrate: neither sphere moved since this contact's
    // previous evaluation (previous 0 in the first pass: nothing skipped). The static slot's
    // entry is 0, and padding lanes have a = b = the static slot, so they always skip from
    // pass 1 on; in pass 0 they are left out below (no inverse mass).
    auto kept = a == a;  // the first pass evaluates every contact: no stamps to gather
    if (previous > 0) {
      kept = (gather_ints(moved, a) >= b_previous) | (gather_ints(moved, b) >= b_previous);
      if (!xsimd::any(kept)) continue;
    }
    const auto has_a = a != b_static_slot, dynamic_b = b != b_static_slot;
    // Indices that exist for the lanes whose values go unused (padding, a static b): this
    // batch's own spheres (lane 0 is never padding, and its a is a sphere), never another's.
    // Slot 0 (as it was) could be a sphere that another batch of the same colour moves on
    // another thread at that moment: a data race (ThreadSanitizer), if a harmless-looking one.
    const ibatch own(static_cast<std::int32_t>(c.a[o]));
    const ibatch ia = xsimd::select(has_a, a, own), ib = xsimd::select(dynamic_b, b, ia);
    const batch pxa = gather_floats(s.px, ia), pya = gather_floats(s.py, ia), pza = gather_floats(s.pz, ia);
    const batch pxb = gather_floats(s.px, ib), pyb = gather_floats(s.py, ib), pzb = gather_floats(s.pz, ib);
    const auto dyn = xsimd::bool_cast(dynamic_b);
    const batch nx = batch::load_aligned(c.nx + o), ny = batch::load_aligned(c.ny + o),
                nz = batch::load_aligned(c.nz + o);
    const batch ra = batch::load_aligned(c.ra + o), rb = batch::load_aligned(c.rb + o);
    // current_gap, both forms, in its operation order.
    const batch gap_static = (batch::load_aligned(c.surface_d + o) - (nx * pxa + ny * pya + nz * pza)) - ra;
    const batch gap_pair = ((nx * (pxb - pxa) + ny * (pyb - pya)) + nz * (pzb - pza)) - ra - rb;
    const batch gap = xsimd::select(dyn, gap_pair, gap_static);
    const batch rmin = xsimd::select(dyn & (rb < ra), rb, ra);
    const batch excess = -gap - slop * rmin;
    const batch ima = gather_floats(s.inv_mass, ia);
    const batch imb = xsimd::select(dyn, gather_floats(s.inv_mass, ib), zero);
    const batch w = ima + imb;
    const auto pushes = xsimd::bool_cast(kept & has_a) & !(excess <= zero) & !(w <= zero);
    std::uint32_t lanes = lane_bits(pushes);
    if (lanes == 0) continue;
    if (!deep) deep = lane_bits(pushes & (excess > slop * rmin) & (rmin < deep_radius)) != 0;
    const batch move = fraction * excess / w;
    const batch mx = nx * move, my = ny * move, mz = nz * move;
    (pxa - mx * ima).store_aligned(out[0]);
    (pya - my * ima).store_aligned(out[1]);
    (pza - mz * ima).store_aligned(out[2]);
    (pxb + mx * imb).store_aligned(out[3]);
    (pyb + my * imb).store_aligned(out[4]);
    (pzb + mz * imb).store_aligned(out[5]);
    a.store_aligned(slot_a);
    b.store_aligned(slot_b);
    for (; lanes != 0; lanes &= lanes - 1) {
      const std::uint32_t l = lowest_lane(lanes);
      const auto sa = static_cast<std::uint32_t>(slot_a[l]);
      s.px[sa] = out[0][l], s.py[sa] = out[1][l], s.pz[sa] = out[2][l];
      s.moved[sa] = now;
      if (slot_b[l] != static_slot) {
        const auto sb = static_cast<std::uint32_t>(slot_b[l]);
        s.px[sb] = out[3][l], s.py[sb] = out[4][l], s.pz[sb] = out[5][l];
        s.moved[sb] = now;
      }
    }
  }
  return deep;
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
