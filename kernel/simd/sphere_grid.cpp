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

struct RowState {
  std::uint32_t found[kBuffer];
  std::size_t count = 0;
};

template <bool kPairMargins>
void scan_run(const SphereGridView& v, std::uint32_t begin, std::uint32_t end, std::uint32_t i, float xi, float yi,
              float zi, float ri, float ri_margin, float travel_i, float margin, RowState& state,
              std::vector<std::uint32_t>& row) {
  using batch = xsimd::batch<float, simd_arch>;
  constexpr std::uint32_t W = batch::size;
  const batch bx(xi), by(yi), bz(zi);
  for (std::uint32_t k0 = begin; k0 < end; k0 += W) {
    const batch dx = batch::load_unaligned(v.x + k0) - bx;
    const batch dy = batch::load_unaligned(v.y + k0) - by;
    const batch dz = batch::load_unaligned(v.z + k0) - bz;
    const batch rj = batch::load_unaligned(v.radius + k0);
    batch reach;
    if constexpr (kPairMargins) {
      // std::min(margin, wanted) is wanted < margin ? wanted : margin (NaN: margin).
      const batch wanted = batch(v.travel_factor) * (batch(travel_i) + batch::load_unaligned(v.travel + k0));
      const batch pair_margin = xsimd::select(wanted < batch(margin), wanted, batch(margin));
      reach = rj + (batch(ri) + pair_margin);
    } else {
      reach = rj + batch(ri_margin);
    }
    const batch d2 = dx * dx + dy * dy + dz * dz;
    std::uint32_t lanes = lane_bits(d2 < reach * reach);
    if (end - k0 < W) lanes &= (1u << (end - k0)) - 1u;  // lanes past the run
    for (; lanes != 0; lanes &= lanes - 1) {
      const std::uint32_t j = v.index[k0 + lowest_lane(lanes)];
      if (j <= i) continue;
      if (state.count == kBuffer) append_slots(row, state.found, state.count), state.count = 0;
      state.found[state.count++] = j;
    }
  }
}

template <bool kPairMargins>
void find_rows(const SphereGridView& v, const SphereSoA& s, std::size_t first, std::size_t last, float margin,
               std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) {
  RowState state;
  constexpr std::size_t kPairBuffer = 256;
  SpherePair pairs[kPairBuffer];
  std::size_t pair_count = 0;
  const std::uint32_t buckets = v.mask + 1;
  for (std::size_t i = first; i < last; ++i) {
    const float xi = s.px[i], yi = s.py[i], zi = s.pz[i], ri = s.radius[i], ri_margin = ri + margin;  // brute force's order
    if (!can_pair(xi, yi, zi, ri_margin)) continue;
    const GridCell c = v.cell[i];
    const std::uint32_t i32 = static_cast<std::uint32_t>(i);
    state.count = 0;
    for (std::int32_t dz = -1; dz <= 1; ++dz)
      for (std::int32_t dy = -1; dy <= 1; ++dy) {
        // Cells x - 1, x, x + 1 of this row: buckets b0 .. b0 + 2, split if they wrap.
        const std::uint32_t b0 = (grid_row_hash(c.y + dy, c.z + dz) + static_cast<std::uint32_t>(c.x) - 1u) & v.mask;
        const std::uint32_t b3 = b0 + 3;
        if (b3 <= buckets) {
          scan_run<kPairMargins>(v, v.bucket_start[b0], v.bucket_start[b3], i32, xi, yi, zi, ri, ri_margin, c.travel,
                                 margin, state, row);
        } else {
          scan_run<kPairMargins>(v, v.bucket_start[b0], v.bucket_start[buckets], i32, xi, yi, zi, ri, ri_margin,
                                 c.travel, margin, state, row);
          scan_run<kPairMargins>(v, v.bucket_start[0], v.bucket_start[b3 - buckets], i32, xi, yi, zi, ri, ri_margin,
                                 c.travel, margin, state, row);
        }
      }
    if (state.count == 0 && row.empty()) continue;
    if (!row.empty()) {  // a long row: sorted in base code
      append_slots(row, state.found, state.count);
      if (pair_count > 0) append_pairs(out, pairs, pair_count), pair_count = 0;
      append_sorted_unique_row(i32, row, out);
      continue;
    }
    // Insertion sort without repeats (two runs may share buckets); rows are short.
    std::size_t kept = 0;
    for (std::size_t a = 0; a < state.count; ++a) {
      const std::uint32_t j = state.found[a];
      std::size_t at = kept;
      while (at > 0 && state.found[at - 1] > j) --at;
      if (at > 0 && state.found[at - 1] == j) continue;
      for (std::size_t b = kept; b > at; --b) state.found[b] = state.found[b - 1];
      state.found[at] = j;
      ++kept;
    }
    if (pair_count + kept > kPairBuffer) append_pairs(out, pairs, pair_count), pair_count = 0;
    for (std::size_t a = 0; a < kept; ++a) pairs[pair_count++] = {i32, state.found[a]};
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
