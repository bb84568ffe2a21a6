#include "kernel/bvh/bvh_build.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <string>

#include "hail/errors.h"
#include "soa/grow.h"

namespace hail {
namespace {

constexpr int kSahBins = 16;
// SAH splits may be arbitrarily uneven; from this depth on the median split takes over, which
// adds at most log2(kMaxBvhPrimitives) = 28 levels, so every leaf stays above kMaxBvhDepth.
constexpr int kSahMaxDepth = kMaxBvhDepth - 1 - (32 - static_cast<int>(kLeafCountBits));
static_assert(kSahMaxDepth > 16);

// Nodes of a median-split tree, to reserve exactly (and not allocate on a rebuild). The sizes
// on one level are floor or ceil of n / 2^depth: s or s + 1 for one s, so a level is two counts.
std::size_t median_node_count(std::size_t n, std::size_t leaf_size) {
  std::size_t total = 0, s = n, small = 1, large = 0;  // `small` nodes of size s, `large` of s + 1
  while (small + large > 0) {
    total += small + large;
    const std::size_t b = s / 2;  // children of sizes s and s + 1 are b or b + 1
    std::size_t next_small = 0, next_large = 0;
    auto split = [&](std::size_t size, std::size_t count) {
      if (size <= leaf_size) return;  // leaves end here
      for (const std::size_t child : {size / 2, size - size / 2}) (child == b ? next_small : next_large) += count;
    };
    split(s, small);
    split(s + 1, large);
    s = b;
    small = next_small;
    large = next_large;
  }
  return total;
}

struct Range {
  std::uint32_t first, count;
  int depth;
};

class Builder {
 public:
  Builder(std::span<const Aabb> bounds, const BvhBuildOptions& options, std::vector<FlatNode>& nodes,
          std::vector<std::uint32_t>& order)
      : bounds_(bounds),
        options_(options),
        leaf_size_(static_cast<std::uint32_t>(options.leaf_size)),
        nodes_(nodes),
        order_(order) {}

  void run() {
    const auto n = static_cast<std::uint32_t>(bounds_.size());
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0u);
    nodes_.clear();
    if (n == 0) return;
    // Exact for Median; a first guess for SAH (the vector grows if SAH makes smaller leaves).
    // The first build reserves exactly (a terrain's BVH is built once, and large); a rebuild
    // that needs more (the per-step sphere and path BVHs of a growing world) grows
    // geometrically, so that adding a sphere per step does not reallocate every step.
    const std::size_t nodes = median_node_count(n, leaf_size_);
    if (nodes_.capacity() == 0)
      nodes_.reserve(nodes);
    else
      reserve_geometric(nodes_, nodes);
    if (options_.split == BvhSplit::InputOrder)
      (void)emit_input_order(0, n);
    else
      emit_preorder(n);
    link_skips();
  }

 private:
  float centre(std::uint32_t prim, int axis) const { return centroid(bounds_[prim], axis); }

  // Depth-first pre-order without recursion: emit a node, continue with its left child and
  // keep the right one on a stack, which therefore never holds more than one range per level.
  void emit_preorder(std::uint32_t n) {
    std::array<Range, kMaxBvhDepth> pending;
    int top = 0;
    Range range{0, n, 0};
    for (;;) {
      Aabb box = empty_aabb(), centres = empty_aabb();
      for (std::uint32_t k = range.first; k < range.first + range.count; ++k) {
        const Aabb& b = bounds_[order_[k]];
        grow(box, b);
        const float c[3] = {centroid(b, 0), centroid(b, 1), centroid(b, 2)};
        grow(centres, c);
      }
      FlatNode node{{box.min[0], box.min[1], box.min[2]}, 0, {box.max[0], box.max[1], box.max[2]}, 0};
      if (range.count <= leaf_size_) {
        // Sorting makes the leaf's order canonical: nth_element and partition leave the
        // order inside a range up to the standard library.
        std::sort(order_.begin() + range.first, order_.begin() + range.first + range.count);
        node.leaf = encode_leaf(range.first, range.count);
        nodes_.push_back(node);
        if (top == 0) return;
        range = pending[--top];
        continue;
      }
      nodes_.push_back(node);
      const std::uint32_t left = options_.split == BvhSplit::BinnedSah && range.depth < kSahMaxDepth
                                     ? split_sah(range, centres)
                                     : split_median(range, centres);
      pending[top++] = Range{range.first + left, range.count - left, range.depth + 1};
      range = Range{range.first, left, range.depth + 1};
    }
  }

  // BvhSplit::InputOrder: the node for [first, first + count) and its subtree in pre-order, the
  // left child the first count / 2 primitives (the median split's shape, so median_node_count
  // reserved exactly); returns its box. Recursion depth log2(n / leaf_size) + 1.
  Aabb emit_input_order(std::uint32_t first, std::uint32_t count) {
    const std::size_t at = nodes_.size();
    nodes_.emplace_back();
    Aabb box = empty_aabb();
    std::uint32_t leaf = 0;
    if (count <= leaf_size_) {
      for (std::uint32_t k = first; k < first + count; ++k) grow(box, bounds_[k]);
      leaf = encode_leaf(first, count);
    } else {
      const std::uint32_t left = count / 2;
      grow(box, emit_input_order(first, left));
      grow(box, emit_input_order(first + left, count - left));
    }
    nodes_[at] = FlatNode{{box.min[0], box.min[1], box.min[2]}, 0, {box.max[0], box.max[1], box.max[2]}, leaf};
    return box;
  }

  // Puts the lower half (by centroid on the centroids' longest axis, ties by index) first.
  std::uint32_t split_median(const Range& range, const Aabb& centres) {
    const int axis = longest_axis(centres);
    const std::uint32_t half = range.count / 2;
    auto first = order_.begin() + range.first;
    std::nth_element(first, first + half, first + range.count, [&](std::uint32_t a, std::uint32_t b) {
      const float ca = centre(a, axis), cb = centre(b, axis);
      return ca < cb || (ca == cb && a < b);
    });
    return half;
  }

  // Bin of a centroid; NaN (from a zero extent) and overshoot are clamped, never UB.
  static int bin_of(float c, float lo, float scale) {
    const float f = (c - lo) * scale;
    return f >= kSahBins - 1 ? kSahBins - 1 : (f > 0.0f ? static_cast<int>(f) : 0);
  }

  // Binned SAH (Wald 2007): cost of a split after bin s = area(left) * n_left + area(right) * n_right.
  std::uint32_t split_sah(const Range& range, const Aabb& centres) {
    Aabb bin_box[3][kSahBins];
    std::uint32_t bin_count[3][kSahBins] = {};
    float scale[3];
    for (int a = 0; a < 3; ++a) {
      const float extent = centres.max[a] - centres.min[a];
      scale[a] = extent > 0.0f ? kSahBins / extent : 0.0f;
      for (Aabb& b : bin_box[a]) b = empty_aabb();
    }
    for (std::uint32_t k = range.first; k < range.first + range.count; ++k) {
      const Aabb& b = bounds_[order_[k]];
      for (int a = 0; a < 3; ++a) {
        const int bin = bin_of(centroid(b, a), centres.min[a], scale[a]);
        grow(bin_box[a][bin], b);
        ++bin_count[a][bin];
      }
    }
    int best_axis = -1, best_split = 0;
    float best_cost = 0.0f;
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0f) continue;
      float right_area[kSahBins];  // area of bins [s, kSahBins)
      Aabb right = empty_aabb();
      for (int s = kSahBins - 1; s > 0; --s) {
        grow(right, bin_box[a][s]);
        right_area[s] = surface_area(right);
      }
      Aabb left = empty_aabb();
      std::uint32_t left_count = 0;
      for (int s = 1; s < kSahBins; ++s) {  // split between bins s - 1 and s
        grow(left, bin_box[a][s - 1]);
        left_count += bin_count[a][s - 1];
        const std::uint32_t right_count = range.count - left_count;
        if (left_count == 0 || right_count == 0) continue;
        const float cost =
            surface_area(left) * static_cast<float>(left_count) + right_area[s] * static_cast<float>(right_count);
        if (best_axis < 0 || cost < best_cost) {  // strict: the first axis and plane win ties
          best_axis = a;
          best_split = s;
          best_cost = cost;
        }
      }
    }
    if (best_axis < 0) return split_median(range, centres);  // all centroids in one point
    const int a = best_axis;
    auto first = order_.begin() + range.first;
    const auto middle = std::partition(first, first + range.count, [&](std::uint32_t p) {
      return bin_of(centre(p, a), centres.min[a], scale[a]) < best_split;
    });
    return static_cast<std::uint32_t>(middle - first);
  }

  // skip = the node after the subtree: i + 1 for a leaf, the right child's skip for an inner
  // node (right child = nodes[i + 1].skip). Both lie after i, hence one backward pass.
  void link_skips() {
    const auto count = static_cast<std::uint32_t>(nodes_.size());
    for (std::uint32_t i = count; i-- > 0;)
      nodes_[i].skip = is_leaf(nodes_[i]) ? i + 1 : nodes_[nodes_[i + 1].skip].skip;
    for (FlatNode& node : nodes_)
      if (node.skip == count) node.skip = kFlatBvhEnd;
  }

  std::span<const Aabb> bounds_;
  const BvhBuildOptions& options_;
  std::uint32_t leaf_size_;
  std::vector<FlatNode>& nodes_;
  std::vector<std::uint32_t>& order_;
};

void check(std::span<const Aabb> bounds, const BvhBuildOptions& options) {
  if (options.leaf_size < 1 || options.leaf_size > static_cast<int>(kMaxLeafSize))
    throw InvalidArgument("hail: BVH leaf_size must be in 1.." + std::to_string(kMaxLeafSize) + ", got " +
                          std::to_string(options.leaf_size));
  if (options.split != BvhSplit::Median && options.split != BvhSplit::BinnedSah &&
      options.split != BvhSplit::InputOrder)
    throw InvalidArgument("hail: unknown BvhSplit " + std::to_string(static_cast<int>(options.split)));
  if (bounds.size() > kMaxBvhPrimitives)
    throw InvalidArgument("hail: BVH over " + std::to_string(bounds.size()) + " primitives exceeds " +
                          std::to_string(kMaxBvhPrimitives));
  for (std::size_t k = 0; k < bounds.size(); ++k)
    if (!is_valid(bounds[k]))
      throw InvalidArgument("hail: BVH primitive " + std::to_string(k) + " has a non-finite or inverted box");
}

}  // namespace

void build_bvh(std::span<const Aabb> bounds, const BvhBuildOptions& options, std::vector<FlatNode>& nodes,
               std::vector<std::uint32_t>& primitive_order) {
  check(bounds, options);
  Builder(bounds, options, nodes, primitive_order).run();
}

}  // namespace hail
