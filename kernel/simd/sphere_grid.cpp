// SphereGrid::find_pairs (kernel/sphere_grid.h): per sphere, the 9 contiguous runs of sorted
// spheres in the cells around it, tested a batch at a time with the brute-force predicate in
// its float operations (or, with pair margins, keep_pairs_within_their_margin's). Compiled
// once per SIMD path (kernel/simd_arch.h); the scalar reference is SphereGrid::find_pairs_scalar.

#include "kernel/simd_arch.h"  // first: the path's namespace

#include "kernel/simd/kernels.h"
#include "kernel/sphere_grid.h"
#include "kernel/sphere_pair_bounds.h"
#include "kernel/sphere_pairs.h"

namespace hail {
inline namespace HAIL_SIMD_NS {
namespace {

// Partners of one row, collected before they are sorted; a row that overflows it goes through
// the caller's `row` vector (base code, kernel/simd_kernels.h).
constexpr std::size_t kBuffer = 128;

template <bool kPairMargins>
void find_rows(const SphereGridView& v, const SphereSoA& s, std::size_t first, std::size_t last, float margin,
               std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::uint32_t W = batch::size;
  std::uint32_t found[kBuffer];
  constexpr std::size_t kPairBuffer = 256;
  SpherePair pairs[kPairBuffer];
  std::size_t pair_count = 0;
  const std::uint32_t buckets = v.mask + 1;
  const batch factor(v.travel_factor), b_margin(margin);
  for (std::size_t i = first; i < last; ++i) {
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri = s.radius[i], ri_margin = ri + margin;  // brute force's order
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    const GridCell c = v.cell[i];
    const std::uint32_t i32 = static_cast<std::uint32_t>(i);
    // The 9 runs (cells x - 1 .. x + 1 of each row: buckets b0 .. b0 + 2), a wrapping one split.
    std::uint32_t run_begin[10], run_end[10], runs = 0;
    for (std::int32_t dz = -1; dz <= 1; ++dz)
      for (std::int32_t dy = -1; dy <= 1; ++dy) {
        const std::uint32_t b0 = grid_key(c.x - 1, c.y + dy, c.z + dz, v.stride_y, v.stride_z) & v.mask;
        const std::uint32_t b3 = b0 + 3;
        run_begin[runs] = v.bucket_start[b0];
        if (b3 <= buckets) {
          run_end[runs++] = v.bucket_start[b3];
        } else {
          run_end[runs++] = v.bucket_start[buckets];
          run_begin[runs] = v.bucket_start[0];
          run_end[runs++] = v.bucket_start[b3 - buckets];
        }
      }
    const batch bx(xi), by(yi), bz(zi), b_ri(ri), b_ri_margin(ri_margin), travel_i(c.travel);
    std::size_t count = 0;
    for (std::uint32_t r = 0; r < runs; ++r) {
      const std::uint32_t end = run_end[r];
      for (std::uint32_t k0 = run_begin[r]; k0 < end; k0 += W) {
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
        std::uint32_t lanes = lane_bits(d2 < reach * reach);
        if (end - k0 < W) lanes &= (1u << (end - k0)) - 1u;  // lanes past the run
        for (; lanes != 0; lanes &= lanes - 1) {
          const std::uint32_t j = v.index[k0 + lowest_lane(lanes)];
          if (j <= i32) continue;
          if (count == kBuffer) append_slots(row, found, count), count = 0;
          found[count++] = j;
        }
      }
    }
    if (count == 0 && row.empty()) continue;
    if (!row.empty()) {  // a long row: sorted in base code
      append_slots(row, found, count);
      if (pair_count > 0) append_pairs(out, pairs, pair_count), pair_count = 0;
      append_sorted_unique_row(i32, row, out);
      continue;
    }
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
