// Heightmap validation, construction from samples, and the surface height. File loaders live in
// heightmap_pgm.cpp, heightmap_png.cpp and heightmap_raw.cpp.

#include "hail/heightmap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "hail/errors.h"

namespace hail {

namespace {
std::string number(float value) {  // %g: a cell of 1e-30 read as 0.000000 in std::to_string
  char text[32];
  std::snprintf(text, sizeof text, "%g", double(value));
  return text;
}
}  // namespace

void check_heightmap_params(const HeightmapParams& p) {
  auto finite = [](float v, const char* name) {
    if (!std::isfinite(v))
      throw InvalidArgument(std::string("hail: HeightmapParams::") + name + " must be finite, got " + number(v));
  };
  auto positive = [&](float v, const char* name) {
    finite(v, name);
    if (!(v > 0.0f))
      throw InvalidArgument(std::string("hail: HeightmapParams::") + name + " must be > 0, got " + number(v));
  };
  positive(p.cell_x, "cell_x");
  positive(p.cell_z, "cell_z");
  finite(p.height_scale, "height_scale");
  finite(p.height_offset, "height_offset");
  finite(p.origin_x, "origin_x");
  finite(p.origin_y, "origin_y");
  finite(p.origin_z, "origin_z");
  if (p.max_vertices < 4 || p.max_vertices > kMaxHeightmapVertices)
    throw InvalidArgument("hail: HeightmapParams::max_vertices must be in 4.." + std::to_string(kMaxHeightmapVertices) +
                          ", got " + std::to_string(p.max_vertices));
}

void check_heightmap_size(std::uint64_t cols, std::uint64_t rows, const std::string& where,
                          std::uint64_t max_vertices) {
  const std::string size = std::to_string(cols) + " x " + std::to_string(rows);
  if (cols < 2 || rows < 2)
    throw InvalidArgument("hail: " + where + ": a heightmap needs at least 2 x 2 vertices, got " + size);
  // Both sides are <= 2^16 before the product is formed, so it cannot overflow.
  if (cols > kMaxHeightmapSide || rows > kMaxHeightmapSide || cols * rows > kMaxHeightmapVertices)
    throw InvalidArgument("hail: " + where + ": " + size + " vertices exceeds the limit (65536 per side, 2^28 in all)");
  if (cols * rows > max_vertices)
    throw InvalidArgument("hail: " + where + ": " + size + " = " + std::to_string(cols * rows) +
                          " vertices exceeds HeightmapParams::max_vertices = " + std::to_string(max_vertices));
}

Heightmap::Heightmap(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params, std::vector<float> heights,
                     const std::string& where)
    : cols_(cols), rows_(rows), params_(params), heights_(std::move(heights)) {
  for (std::size_t k = 0; k < heights_.size(); ++k)
    if (!std::isfinite(heights_[k]))
      throw InvalidArgument("hail: " + where + ": height at column " + std::to_string(k % cols) + ", row " +
                            std::to_string(k / cols) + " is not finite (" + number(heights_[k]) + ")");
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  min_height_ = *lo;
  max_height_ = *hi;
}

Heightmap Heightmap::from_samples(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                  std::vector<float> samples) {
  check_heightmap_params(params);
  check_heightmap_size(cols, rows, "Heightmap::from_samples", params.max_vertices);
  if (samples.size() != std::size_t(cols) * rows)
    throw InvalidArgument("hail: Heightmap::from_samples: " + std::to_string(samples.size()) + " samples for " +
                          std::to_string(cols) + " x " + std::to_string(rows) + " vertices");
  for (float& s : samples) s = params.origin_y + (params.height_offset + params.height_scale * s);
  return Heightmap(cols, rows, params, std::move(samples), "Heightmap::from_samples");
}

Heightmap Heightmap::from_file_samples(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                       const HeightmapParams& params, std::vector<float> samples) {
  for (float& s : samples) s = params.origin_y + (params.height_offset + params.height_scale * s);
  try {
    return Heightmap(cols, rows, params, std::move(samples), path);
  } catch (const InvalidArgument& e) {
    throw FileError(e.what());  // a NaN sample, or scale * sample overflowing: the file's fault
  }
}

Heightmap Heightmap::moved(const Vec3& by) const {
  if (!std::isfinite(by.x()) || !std::isfinite(by.y()) || !std::isfinite(by.z()))
    throw InvalidArgument("hail: Heightmap::moved: offset (" + std::to_string(by.x()) + ", " + std::to_string(by.y()) +
                          ", " + std::to_string(by.z()) + ") is not finite");
  HeightmapParams params = params_;
  params.origin_x += by.x();
  params.origin_y += by.y();
  params.origin_z += by.z();
  check_heightmap_params(params);  // an origin pushed past float range
  std::vector<float> heights = heights_;
  if (by.y() != 0.0f)
    for (float& h : heights) h += by.y();
  return Heightmap(cols_, rows_, params, std::move(heights), "Heightmap::moved");
}

float Heightmap::surface_height(float x, float z) const {
  const float u_total = (x - params_.origin_x) / params_.cell_x, w_total = (z - params_.origin_z) / params_.cell_z;
  // Written so that NaN input fails the test too.
  if (!(u_total >= 0.0f && w_total >= 0.0f && u_total <= float(cols_ - 1) && w_total <= float(rows_ - 1)))
    return std::numeric_limits<float>::quiet_NaN();
  const std::uint32_t i = std::min<std::uint32_t>(static_cast<std::uint32_t>(u_total), cols_ - 2);
  const std::uint32_t j = std::min<std::uint32_t>(static_cast<std::uint32_t>(w_total), rows_ - 2);
  const float u = u_total - float(i), w = w_total - float(j);
  const float h00 = h(i, j), h10 = h(i + 1, j), h01 = h(i, j + 1), h11 = h(i + 1, j + 1);
  // The diagonal runs from (i+1, j) to (i, j+1): u + w <= 1 is the triangle holding vertex (i, j).
  if (u + w <= 1.0f) return h00 + u * (h10 - h00) + w * (h01 - h00);
  return h11 + (1.0f - u) * (h01 - h11) + (1.0f - w) * (h10 - h11);
}

}  // namespace hail
