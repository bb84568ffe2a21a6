#include "view/debug_lines.h"

namespace hail::view {

void LineList::add(const Vec3& a, const Vec3& b, const Rgb& c) {
  vertices.insert(vertices.end(), {a.x(), a.y(), a.z(), c[0], c[1], c[2], b.x(), b.y(), b.z(), c[0], c[1], c[2]});
}

void LineList::add_box(const DebugBox& box, const Rgb& colour) {
  const auto corner = [&](int k) {
    return Vec3((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                (k & 4) ? box.max.z() : box.min.z());
  };
  // Corners k and k | bit share an edge along that bit's axis: 4 edges per axis.
  for (int bit = 1; bit <= 4; bit <<= 1)
    for (int k = 0; k < 8; ++k)
      if ((k & bit) == 0) add(corner(k), corner(k | bit), colour);
}

std::vector<DebugBox> bvh_level(std::span<const BvhNodeBox> nodes, int depth) {
  std::vector<DebugBox> level;
  if (depth < 0) return level;
  for (const BvhNodeBox& n : nodes)
    if (int(n.depth) == depth || (n.leaf && int(n.depth) < depth)) level.push_back(n.box);
  return level;
}

void build_debug_lines(const Frame& frame, std::span<const BvhNodeBox> terrain_bvh, const DebugDraw& draw,
                       DebugLines& out) {
  out.tested.clear();
  out.overlay.clear();
  if (draw.bvh_depth >= 0)
    for (const DebugBox& box : bvh_level(terrain_bvh, draw.bvh_depth)) out.tested.add_box(box, kBvhCyan);
  if (draw.grid)
    for (const DebugBox& cell : frame.grid_cells) out.tested.add_box(cell, kGridWhite);
  if (draw.normals)
    for (std::size_t k = 0; k + kContactFloats <= frame.contacts.size(); k += kContactFloats) {
      const float* c = &frame.contacts[k];
      const Vec3 point(c[0], c[1], c[2]), normal(c[3], c[4], c[5]);
      out.overlay.add(point, point - c[6] * normal, kNormalYellow);
    }
}

}  // namespace hail::view
