// SphereGrid::find_pairs (kernel/broadphase/sphere_grid.h): per sphere, the contiguous runs of sorted
// spheres in the cells its reach window overlaps (one run per row of cells along x), tested a
// batch at a time with the brute-force predicate in its float operations (or, with pair
// margins, keep_pairs_within_their_margin's). Compiled once per SIMD path (kernel/dispatch/simd_arch.h);
// the scalar reference is SphereGrid::find_pairs_scalar.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pair_bounds.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/simd/compress_lanes.h"
#include "kernel/simd/kernels.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

// Partners of one row, collected before they are sorted; a row that could overflow it is
// searched again by long_row, into the caller's `row` vector (base code, kernel/dispatch/kernel_table.h).
constexpr std::size_t kBuffer = 128;

using batch = xsimd::batch<float, simd_arch>;
// Slots compared as int32: a World's slots are far below 2^31 (SpherePair holds uint32).
using ibatch = xsimd::batch<std::int32_t, simd_arch>;
constexpr std::uint32_t W = batch::size;
static_assert(ibatch::size == W);

/// Sphere i's pair predicate against W sorted slots at a time: the brute-force predicate in its
/// float operations (or, with pair margins, keep_pairs_within_their_margin's), partners j > i.
template <bool kPairMargins>
struct RowTest {
  batch bx, by, bz, b_ri, b_ri_margin, travel_i, factor, b_margin;
  ibatch bi;

  RowTest(const SphereGridView& v, const SphereSoA& s, std::size_t i, float margin)
      : bx(s.px[i]),
        by(s.py[i]),
        bz(s.pz[i]),
        b_ri(s.radius[i]),
        b_ri_margin(s.radius[i] + margin),  // brute force's order
        travel_i(kPairMargins ? v.sphere_travel[i] : 0.0f),
        factor(v.travel_factor),
        b_margin(margin),
        bi(static_cast<std::int32_t>(i)) {}

  /// Lanes of slots [k0, k0 + W) within reach, masked to the run [.., end).
  [[gnu::always_inline]] std::uint32_t operator()(const SphereGridView& v, std::uint32_t k0, std::uint32_t end) const {
    const batch dx = batch::load_unaligned(v.x + k0) - bx;
    const batch dy = batch::load_unaligned(v.y + k0) - by;
    const batch dz = batch::load_unaligned(v.z + k0) - bz;
    const batch rj = batch::load_unaligned(v.radius + k0);
    batch reach;
    if constexpr (kPairMargins) {
      // keep_pairs_within_their_margin's reach; std::min(margin, wanted) is
      // wanted < margin ? wanted : margin (NaN: margin).
      const batch wanted = factor * (travel_i + batch::load_unaligned(v.travel + k0));
      reach = rj + (b_ri + xsimd::select(wanted < b_margin, wanted, b_margin));
    } else {
      reach = rj + b_ri_margin;
    }
    const batch d2 = dx * dx + dy * dy + dz * dz;
    // Partners j > i only: about half the lanes within reach are j < i (and i itself).
    const ibatch j = ibatch::load_unaligned(reinterpret_cast<const std::int32_t*>(v.index + k0));
    std::uint32_t lanes = lane_bits((d2 < reach * reach) && xsimd::bool_cast(j > bi));
    if (end - k0 < W) lanes &= (1u << (end - k0)) - 1u;  // lanes past the run
    return lanes;
  }
};

/// Sphere i's partners when they might not fit find_rows' buffer: into `row`, then sorted into
/// `out`. Out of line, so that find_rows' loop holds no call (its registers stay in registers).
template <bool kPairMargins>
[[gnu::noinline]] void long_row(const SphereGridView& v, const SphereSoA& s, std::size_t i, float margin,
                                std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  const RowTest<kPairMargins> test(v, s, i, margin);
  for_each_window_run(v, grid_window(v, s.px[i], s.py[i], s.pz[i], s.radius[i], s.radius[i] + margin),
                      [&](std::uint32_t begin, std::uint32_t end) {
                        for (std::uint32_t k0 = begin; k0 < end; k0 += W)
                          for (std::uint32_t lanes = test(v, k0, end); lanes != 0; lanes &= lanes - 1)
                            row.push_back(v.index[k0 + lowest_lane(lanes)]);
                      });
  append_sorted_unique_row(static_cast<std::uint32_t>(i), row, out);
}

template <bool kPairMargins>
void find_rows(const SphereGridView& v, const SphereSoA& s, std::size_t first, std::size_t last, float margin,
               std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  std::uint32_t found[kBuffer];
  constexpr std::size_t kPairBuffer = 256;
  SpherePair pairs[kPairBuffer];
  std::size_t pair_count = 0;
  for (std::size_t i = first; i < last; ++i) {
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri = s.radius[i],
                ri_margin = ri + margin;  // brute force's order
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    const std::uint32_t i32 = static_cast<std::uint32_t>(i);
    const RowTest<kPairMargins> test(v, s, i, margin);
    std::size_t count = 0;
    bool overflow = false;
    auto scan = [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t k0 = begin; k0 < end && !overflow; k0 += W) {
        if (count + W > kBuffer) {  // this batch might not fit: the whole row again, in long_row
          overflow = true;
          break;
        }
        // The hits stored at once (kernel/simd/compress_lanes.h), not one branch per hit.
        count += compress_lanes(found + count, v.index + k0, test(v, k0, end));
      }
    };
    const GridWindow g = grid_window(v, xi, yi, zi, ri, ri_margin);
    for_each_window_run(v, g, scan);
    if (overflow) {
      if (pair_count > 0) append_pairs(out, pairs, pair_count), pair_count = 0;
      long_row<kPairMargins>(v, s, i, margin, out, row);
      continue;
    }
    if (count == 0) continue;
    // Insertion sort without repeats (two runs may share buckets); rows are short.
    std::size_t kept = 0;
    for (std::size_t a = 0; a < count; ++a) {
      const std::uint32_t j = found[a];
      std::size_t at = kept;
      while (at > 0 && found[at - 1] > j) --at;
      if (at > 0 && found[at - 1] == j) continue;
      for (std::size_t b = kept; b > at; --b) found[b] = found[b - 1];
      found[at] = j;
      ++kept;
    }
    if (pair_count + kept > kPairBuffer) append_pairs(out, pairs, pair_count), pair_count = 0;
    for (std::size_t a = 0; a < kept; ++a) pairs[pair_count++] = {i32, found[a]};
  }
  if (pair_count > 0) append_pairs(out, pairs, pair_count);
}

}  // namespace

void grid_find_pairs(const SphereGridView& v, const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                     std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  static_assert(kSimdPadding >= xsimd::batch<float, simd_arch>::size, "the grid's padding must cover the widest batch");
  if (v.travel)
    find_rows<true>(v, s, first, last, margin, out, row);
  else
    find_rows<false>(v, s, first, last, margin, out, row);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
