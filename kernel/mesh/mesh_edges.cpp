#include "kernel/mesh/mesh_edges.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace hail {

std::vector<std::uint32_t> weld_vertices(std::span<const Vec3> vertices) {
  std::vector<std::uint32_t> order(vertices.size());
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](std::uint32_t v) { return std::array<float, 3>{vertices[v].x(), vertices[v].y(), vertices[v].z()}; };
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
  std::vector<std::uint32_t> welded(vertices.size());
  for (std::size_t k = 0; k < order.size();) {
    std::size_t end = k + 1;
    while (end < order.size() && key(order[end]) == key(order[k])) ++end;
    for (std::size_t m = k; m < end; ++m) welded[order[m]] = order[k];  // order[k] is the lowest index
    k = end;
  }
  return welded;
}

bool degenerate_triangle(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices, std::size_t t) {
  const Vec3& a = vertices[indices[3 * t]];
  const Vec3& b = vertices[indices[3 * t + 1]];
  const Vec3& c = vertices[indices[3 * t + 2]];
  const double u[3] = {double(b.x()) - a.x(), double(b.y()) - a.y(), double(b.z()) - a.z()};
  const double w[3] = {double(c.x()) - a.x(), double(c.y()) - a.y(), double(c.z()) - a.z()};
  const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  return n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0;
}

std::vector<std::uint32_t> edge_neighbours(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices,
                                           std::span<const std::uint32_t> welded,
                                           std::vector<std::uint8_t>* same_direction) {
  struct Use {
    std::uint64_t edge;    // lower welded vertex << 32 | higher
    std::uint32_t corner;  // 3t + k
    bool forward;          // runs from the lower vertex to the higher
  };
  const std::size_t triangles = indices.size() / 3;
  std::vector<Use> uses;
  uses.reserve(indices.size());
  for (std::size_t t = 0; t < triangles; ++t) {
    if (degenerate_triangle(vertices, indices, t)) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t from = welded[indices[3 * t + k]], to = welded[indices[3 * t + (k + 1) % 3]];
      const std::uint32_t lo = std::min(from, to), hi = std::max(from, to);
      uses.push_back({(std::uint64_t{lo} << 32) | hi, static_cast<std::uint32_t>(3 * t + k), from < to});
    }
  }
  std::sort(uses.begin(), uses.end(),
            [](const Use& a, const Use& b) { return a.edge != b.edge ? a.edge < b.edge : a.corner < b.corner; });
  std::vector<std::uint32_t> neighbour(indices.size(), kNoNeighbour);
  if (same_direction) same_direction->assign(indices.size(), 0);
  for (std::size_t k = 0; k < uses.size();) {
    std::size_t end = k + 1;
    while (end < uses.size() && uses[end].edge == uses[k].edge) ++end;
    if (end - k == 2) {
      const Use& p = uses[k];
      const Use& q = uses[k + 1];
      neighbour[p.corner] = q.corner / 3;
      neighbour[q.corner] = p.corner / 3;
      if (same_direction) (*same_direction)[p.corner] = (*same_direction)[q.corner] = p.forward == q.forward;
    }
    k = end;
  }
  return neighbour;
}

bool mesh_is_closed(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices) {
  const std::vector<std::uint32_t> welded = weld_vertices(vertices);
  std::vector<std::uint8_t> same;
  const std::vector<std::uint32_t> neighbour = edge_neighbours(vertices, indices, welded, &same);
  bool any = false;
  for (std::size_t t = 0; t < indices.size() / 3; ++t) {
    if (degenerate_triangle(vertices, indices, t)) continue;
    any = true;
    for (std::size_t k = 0; k < 3; ++k)
      if (neighbour[3 * t + k] == kNoNeighbour || same[3 * t + k]) return false;
  }
  return any;
}

}  // namespace hail
