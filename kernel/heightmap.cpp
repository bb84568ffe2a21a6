#include "kernel/heightmap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/errors.h"

namespace hail {
namespace {

void check_params(const HeightmapParams& p) {
  auto positive = [](float v, const char* name) {
    if (!(std::isfinite(v) && v > 0.0f))
      throw InvalidArgument(std::string("hail: HeightmapParams::") + name + " must be finite and > 0, got " + std::to_string(v));
  };
  auto finite = [](float v, const char* name) {
    if (!std::isfinite(v))
      throw InvalidArgument(std::string("hail: HeightmapParams::") + name + " must be finite, got " + std::to_string(v));
  };
  positive(p.cell_x, "cell_x");
  positive(p.cell_z, "cell_z");
  finite(p.height_scale, "height_scale");
  finite(p.height_offset, "height_offset");
  finite(p.origin_x, "origin_x");
  finite(p.origin_z, "origin_z");
}

}  // namespace

void check_heightmap_size(std::uint64_t cols, std::uint64_t rows, const std::string& where) {
  if (cols < 2 || rows < 2)
    throw InvalidArgument("hail: " + where + ": a heightmap needs at least 2 x 2 vertices, got " + std::to_string(cols) +
                          " x " + std::to_string(rows));
  if (cols > kMaxHeightmapSide || rows > kMaxHeightmapSide || cols * rows > kMaxHeightmapVertices)
    throw InvalidArgument("hail: " + where + ": " + std::to_string(cols) + " x " + std::to_string(rows) +
                          " vertices exceeds the limit (65,536 per side, 2^28 in all)");
}

Heightmap::Heightmap(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params, std::vector<float> heights)
    : cols_(cols), rows_(rows), params_(params), heights_(std::move(heights)) {
  const auto [lo, hi] = std::minmax_element(heights_.begin(), heights_.end());
  min_height_ = *lo;
  max_height_ = *hi;
}

Heightmap Heightmap::from_samples(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                  std::vector<float> samples) {
  check_params(params);
  check_heightmap_size(cols, rows, "heightmap");
  if (samples.size() != std::size_t(cols) * rows)
    throw InvalidArgument("hail: heightmap: " + std::to_string(samples.size()) + " samples for " + std::to_string(cols) +
                          " x " + std::to_string(rows) + " vertices");
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const float h = params.height_offset + params.height_scale * samples[k];
    if (!std::isfinite(h))
      throw InvalidArgument("hail: heightmap: sample " + std::to_string(k) + " (column " + std::to_string(k % cols) +
                            ", row " + std::to_string(k / cols) + ") is not finite");
    samples[k] = h;
  }
  return Heightmap(cols, rows, params, std::move(samples));
}

Heightmap Heightmap::from_function(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                   const std::function<float(float, float)>& h) {
  check_params(params);
  check_heightmap_size(cols, rows, "heightmap");
  std::vector<float> samples(std::size_t(cols) * rows);
  for (std::uint32_t j = 0; j < rows; ++j)
    for (std::uint32_t i = 0; i < cols; ++i)
      samples[std::size_t(j) * cols + i] = h(params.origin_x + static_cast<float>(i) * params.cell_x,
                                             params.origin_z + static_cast<float>(j) * params.cell_z);
  return from_samples(cols, rows, params, std::move(samples));
}

float Heightmap::surface_height(float x, float z) const {
  const float fx = (x - params_.origin_x) / params_.cell_x, fz = (z - params_.origin_z) / params_.cell_z;
  if (!(fx >= 0.0f && fz >= 0.0f && fx <= float(cols_ - 1) && fz <= float(rows_ - 1)))
    return std::numeric_limits<float>::quiet_NaN();
  const std::uint32_t i = std::min<std::uint32_t>(static_cast<std::uint32_t>(fx), cols_ - 2);
  const std::uint32_t j = std::min<std::uint32_t>(static_cast<std::uint32_t>(fz), rows_ - 2);
  const float u = fx - float(i), w = fz - float(j);
  const float h00 = height(i, j), h10 = height(i + 1, j), h01 = height(i, j + 1), h11 = height(i + 1, j + 1);
  if (u + w <= 1.0f) return h00 + u * (h10 - h00) + w * (h01 - h00);  // triangle (00, 01, 10)
  return h11 + (1.0f - u) * (h01 - h11) + (1.0f - w) * (h10 - h11);   // triangle (10, 01, 11)
}

}  // namespace hail
