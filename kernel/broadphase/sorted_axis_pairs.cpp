#include "kernel/broadphase/sorted_axis_pairs.h"

#include <algorithm>
#include <cmath>

#include "kernel/broadphase/sphere_pair_bounds.h"
#include "kernel/dispatch/kernel_table.h"
#include "soa/grow.h"

namespace hail {
namespace {

// Padding after the sorted arrays: the widest batch of any SIMD path.
constexpr std::size_t kLanes = kSimdPadding;
constexpr std::uint8_t kExcluded = 0xFF;

// Axis of the largest variance of the centres that can pair (lowest axis on ties). Double
// sums in index order: the same spheres always give the same axis.
int widest_axis(const SphereSoA& s, const std::vector<std::uint8_t>& class_of) {
  const float* p[3] = {s.px.data(), s.py.data(), s.pz.data()};
  double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
  std::size_t count = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (class_of[i] == kExcluded) continue;
    ++count;
    for (int a = 0; a < 3; ++a) sum[a] += p[a][i];
  }
  if (count == 0) return 0;
  double mean[3];
  for (int a = 0; a < 3; ++a) mean[a] = sum[a] / double(count);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (class_of[i] == kExcluded) continue;
    for (int a = 0; a < 3; ++a) sum_sq[a] += (p[a][i] - mean[a]) * (p[a][i] - mean[a]);
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (sum_sq[a] > sum_sq[axis]) axis = a;
  return axis;
}

}  // namespace

void SortedAxisPairs::build(const SphereSoA& s, float /*margin: the sort does not depend on it*/) {
  const std::size_t n = s.size();
  resize_geometric(class_of_, n);

  // Radius classes, a factor 4 apart from the smallest positive |radius|. Zero radii join
  // class 0. Powers of two scale exactly, so the class of a radius is repeatable.
  float smallest = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    const float r = std::fabs(s.radius[i]);
    if (can_pair(s.px[i], s.py[i], s.pz[i], r) && r > 0.0f && (smallest == 0.0f || r < smallest)) smallest = r;
  }
  std::uint32_t count[kMaxRadiusClasses] = {};
  float max_radius[kMaxRadiusClasses] = {};
  for (std::size_t i = 0; i < n; ++i) {
    const float r = std::fabs(s.radius[i]);
    if (!can_pair(s.px[i], s.py[i], s.pz[i], r)) {
      class_of_[i] = kExcluded;
      continue;
    }
    int c = 0;
    for (float bound = 4.0f * smallest; c < kMaxRadiusClasses - 1 && r > bound; bound *= 4.0f) ++c;
    class_of_[i] = static_cast<std::uint8_t>(c);
    ++count[c];
    max_radius[c] = std::max(max_radius[c], r);
  }
  axis_ = widest_axis(s, class_of_);

  // Non-empty classes only, so that find_pairs searches no empty run.
  int slot_of_class[kMaxRadiusClasses];
  class_begin_.assign(1, 0);
  class_max_radius_.clear();
  for (int c = 0; c < kMaxRadiusClasses; ++c) {
    slot_of_class[c] = static_cast<int>(class_max_radius_.size());
    if (count[c] == 0) continue;
    class_begin_.push_back(class_begin_.back() + count[c]);
    class_max_radius_.push_back(max_radius[c]);
  }

  // Counting sort by class (index order kept), then each class by (centre, index): the keys
  // are unique, so the order does not depend on the sort algorithm.
  const std::size_t sorted = class_begin_.back();
  resize_geometric(keys_, sorted);
  const float* centre = axis_ == 0 ? s.px.data() : axis_ == 1 ? s.py.data() : s.pz.data();
  std::uint32_t cursor[kMaxRadiusClasses];
  for (int c = 0; c < kMaxRadiusClasses; ++c) cursor[c] = count[c] ? class_begin_[slot_of_class[c]] : 0;
  for (std::size_t i = 0; i < n; ++i)
    if (class_of_[i] != kExcluded) keys_[cursor[class_of_[i]]++] = {centre[i], static_cast<std::uint32_t>(i)};
  for (std::size_t c = 0; c + 1 < class_begin_.size(); ++c)
    std::sort(keys_.begin() + class_begin_[c], keys_.begin() + class_begin_[c + 1],
              [](const SortKey& a, const SortKey& b) {
                return a.centre < b.centre || (a.centre == b.centre && a.index < b.index);
              });

  // Copy into sorted SoA; the padding batch is far away and never reported (slots >= the
  // window's end are masked), it only keeps the last load inside the arrays.
  resize_geometric(x_, sorted + kLanes);
  resize_geometric(y_, sorted + kLanes);
  resize_geometric(z_, sorted + kLanes);
  resize_geometric(radius_, sorted + kLanes);
  resize_geometric(index_, sorted + kLanes);
  for (std::size_t k = 0; k < sorted; ++k) {
    const std::uint32_t i = keys_[k].index;
    x_[k] = s.px[i];
    y_[k] = s.py[i];
    z_[k] = s.pz[i];
    radius_[k] = s.radius[i];
    index_[k] = i;
  }
  for (std::size_t k = sorted; k < sorted + kLanes; ++k) {
    x_[k] = y_[k] = z_[k] = kPaddingPosition;
    radius_[k] = 0.0f;
    index_[k] = 0;
  }
}

SortedAxisPairsView SortedAxisPairs::view() const {
  return {axis_,          x_.data(),     y_.data(),           z_.data(),
          radius_.data(), index_.data(), class_begin_.data(), class_max_radius_.data(),
          class_count()};
}

void SortedAxisPairs::find_pairs(const SphereSoA& s, std::size_t first, std::size_t last, float margin,
                                 std::vector<SpherePair>& out, std::vector<std::uint32_t>& row) const {
  if (first >= last || class_count() == 0) return;
  row.clear();
  simd_kernels().sorted_axis_find_pairs(view(), s, first, last, margin, out, row);
}

}  // namespace hail
