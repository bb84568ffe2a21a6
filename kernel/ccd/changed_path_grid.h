#pragma once
// The paths that changed during one step's continuous collision, in a hashed grid of their
// boxes, so that a sphere searching for its next impact tries only the changed paths near its
// own instead of all of them. Trying every changed path made the resolve quadratic in the
// impacts of a step: a million spheres in 40 layers stalled for minutes in one step when the top
// layers, falling fast, hit the pile and each impact set off chains through it.
//
// Conservative: a path is found by every query box that overlaps its box (both are closed
// float boxes; cells come from one monotone function, so overlapping boxes share a cell). Stale
// entries (the motion's path changed again) are skipped by version; a path listed under several
// cells is reported once per query. Which order candidates come in does not matter to the
// caller (ties are broken by index), so the result is exactly that of trying them all.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>
#include "soa/heap_bytes.h"

namespace hail {

class ChangedPathGrid {
 public:
  /// Empties the grid for a step whose boxes are about `cell` wide (> 0), for up to
  /// `motions` motion indices.
  void reset(float cell, std::size_t motions) {
    for (std::uint32_t b : used_) head_[b] = -1;
    used_.clear();
    entries_.clear();
    wide_.clear();
    if (head_.empty()) head_.assign(kBuckets, -1);
    inv_cell_ = 1.0f / cell;
    if (seen_.size() < motions) seen_.resize(motions, 0);
    std::fill(seen_.begin(), seen_.end(), 0u);
    query_ = 0;
  }

  /// Lists motion `m`, at `version`, under every cell of the box [lo, hi].
  void insert(std::uint32_t m, std::uint32_t version, const float lo[3], const float hi[3]) {
    if (seen_.size() <= m) seen_.resize(m + 1, 0);
    std::int32_t c0[3], c1[3];
    if (!cells_of(lo, hi, c0, c1)) {
      wide_.push_back({m, version, -1});
      return;
    }
    for (std::int32_t x = c0[0]; x <= c1[0]; ++x)
      for (std::int32_t y = c0[1]; y <= c1[1]; ++y)
        for (std::int32_t z = c0[2]; z <= c1[2]; ++z) {
          const std::uint32_t b = bucket(x, y, z);
          if (head_[b] < 0) used_.push_back(b);
          entries_.push_back({m, version, head_[b]});
          head_[b] = static_cast<std::int32_t>(entries_.size() - 1);
        }
  }

  /// Calls f(m) once for every motion listed at its current version (current(m)) whose box may
  /// overlap [lo, hi]. A query box over too many cells visits every entry.
  template <class Current, class F>
  void query(const float lo[3], const float hi[3], Current&& current, F&& f) {
    ++query_;
    auto visit = [&](const Entry& e) {
      if (e.version != current(e.motion) || seen_[e.motion] == query_) return;
      seen_[e.motion] = query_;
      f(e.motion);
    };
    for (const Entry& e : wide_) visit(e);
    std::int32_t c0[3], c1[3];
    if (!cells_of(lo, hi, c0, c1)) {
      for (const Entry& e : entries_) visit(e);
      return;
    }
    for (std::int32_t x = c0[0]; x <= c1[0]; ++x)
      for (std::int32_t y = c0[1]; y <= c1[1]; ++y)
        for (std::int32_t z = c0[2]; z <= c1[2]; ++z)
          for (std::int32_t k = head_[bucket(x, y, z)]; k >= 0; k = entries_[static_cast<std::size_t>(k)].next)
            visit(entries_[static_cast<std::size_t>(k)]);
  }

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(head_, used_, entries_, wide_, seen_);
  }

 private:
  static constexpr std::uint32_t kBuckets = 1u << 14;
  static constexpr std::int64_t kMaxCells = 64;  // per box; beyond, a box is "wide"

  struct Entry {
    std::uint32_t motion, version;
    std::int32_t next;  // next entry of the bucket, -1 at the end
  };

  /// The cell ranges of a box; false when they are not finite or cover more than kMaxCells.
  bool cells_of(const float lo[3], const float hi[3], std::int32_t c0[3], std::int32_t c1[3]) const {
    std::int64_t count = 1;
    for (int d = 0; d < 3; ++d) {
      const float a = std::floor(lo[d] * inv_cell_), b = std::floor(hi[d] * inv_cell_);
      if (!(a >= -1.0e9f && b <= 1.0e9f && a <= b)) return false;
      c0[d] = static_cast<std::int32_t>(a), c1[d] = static_cast<std::int32_t>(b);
      count *= static_cast<std::int64_t>(c1[d]) - c0[d] + 1;
      if (count > kMaxCells) return false;
    }
    return true;
  }

  static std::uint32_t bucket(std::int32_t x, std::int32_t y, std::int32_t z) {
    const std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^
                            static_cast<std::uint32_t>(z) * 83492791u;
    return (h ^ (h >> 15)) & (kBuckets - 1);
  }

  float inv_cell_ = 1.0f;
  std::vector<std::int32_t> head_;
  std::vector<std::uint32_t> used_;  // buckets with entries, to empty them cheaply
  std::vector<Entry> entries_;
  std::vector<Entry> wide_;
  std::vector<std::uint32_t> seen_;  // per motion: the last query that reported it
  std::uint32_t query_ = 0;
};

}  // namespace hail
