#include "scenes/steep_heightmaps.h"

#include <random>
#include <vector>

namespace hail::bench {

const char* steep_kind_name(SteepKind kind) {
  switch (kind) {
    case SteepKind::Noise:
      return "noise";
    case SteepKind::Cliffs:
      return "cliffs";
    case SteepKind::Spikes:
      return "spikes";
    case SteepKind::Folds:
      return "folds";
  }
  return "?";
}

Heightmap steep_heightmap(SteepKind kind, std::uint32_t seed, std::uint32_t cols, std::uint32_t rows) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  // Terraces: a few random cut lines in x and z, each a step up or down.
  const int cut_x = 3 + static_cast<int>(rng() % 5), cut_z = 3 + static_cast<int>(rng() % 5);
  const float step_x = 6.0f + 4.0f * u(rng), step_z = -(6.0f + 4.0f * u(rng));
  std::vector<float> heights(std::size_t(cols) * rows);
  for (std::uint32_t j = 0; j < rows; ++j) {
    for (std::uint32_t i = 0; i < cols; ++i) {
      float y = 0.0f;
      switch (kind) {
        case SteepKind::Noise:
          y = 16.0f * (u(rng) - 0.5f);
          break;
        case SteepKind::Cliffs:
          y = step_x * static_cast<float>(static_cast<int>(i) / cut_x) +
              step_z * static_cast<float>(static_cast<int>(j) / cut_z) + 0.3f * u(rng);
          break;
        case SteepKind::Spikes: {
          const float roll = u(rng), size = 5.0f + 10.0f * u(rng);
          y = roll < 1.0f / 24.0f ? size : roll < 1.0f / 12.0f ? -size : 0.2f * u(rng);
          break;
        }
        case SteepKind::Folds:
          y = ((i + j) % 2 ? 6.0f : -6.0f) + u(rng);
          break;
      }
      heights[std::size_t(j) * cols + i] = y;
    }
  }
  HeightmapParams params;
  params.cell_x = 1.0f;
  params.cell_z = 0.8f;
  return Heightmap::from_samples(cols, rows, params, std::move(heights));
}

}  // namespace hail::bench
