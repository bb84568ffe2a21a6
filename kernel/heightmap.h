#pragma once
// A static heightmap: a grid of cols (along x, index i) x rows (along z, index j) vertex
// heights. Vertex (i, j) sits at x = origin_x + i cell_x, z = origin_z + j cell_z,
// y = height_offset + height_scale * sample. Each cell (i, j)-(i+1, j+1) is two triangles split
// along the diagonal from vertex (i+1, j) to vertex (i, j+1) (Bullet's default).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hail {

/// Largest heightmap accepted, checked before anything is allocated: 2^28 vertices in all
/// (1 GiB of float heights) and at most 65,536 vertices per side.
inline constexpr std::uint64_t kMaxHeightmapVertices = std::uint64_t{1} << 28;
inline constexpr std::uint32_t kMaxHeightmapSide = 65536;

/// Throws InvalidArgument (naming `where`) unless 2 <= cols, rows and the size is within the limits.
void check_heightmap_size(std::uint64_t cols, std::uint64_t rows, const std::string& where);

struct HeightmapParams {
  float cell_x = 1.0f;        ///< m between columns, > 0
  float cell_z = 1.0f;        ///< m between rows, > 0
  float height_scale = 1.0f;  ///< m per sample unit (file loaders)
  float height_offset = 0.0f; ///< m added to every height
  float origin_x = 0.0f;      ///< m, x of column 0
  float origin_z = 0.0f;      ///< m, z of row 0
};

class Heightmap {
 public:
  /// Samples h(x, z) (metres, world coordinates) at every vertex; scale and offset are applied
  /// on top (leave them 1 and 0 for a function already in metres).
  static Heightmap from_function(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                 const std::function<float(float, float)>& h);
  /// Binary (P5, 8- or 16-bit big-endian) or ASCII (P2) PGM. File row 0 becomes j = 0 (for the
  /// shipped DEMs row 0 is the north edge, so z grows southwards). Throws FileError naming the
  /// file and the problem; never returns a partial map.
  static Heightmap load_pgm(const std::string& path, const HeightmapParams& params);
  /// From samples already in memory (row-major, j * cols + i). Throws InvalidArgument.
  static Heightmap from_samples(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                std::vector<float> samples);

  [[nodiscard]] std::uint32_t cols() const { return cols_; }
  [[nodiscard]] std::uint32_t rows() const { return rows_; }
  [[nodiscard]] const HeightmapParams& params() const { return params_; }
  /// Height of vertex (i, j) in metres.
  [[nodiscard]] float height(std::uint32_t i, std::uint32_t j) const { return heights_[std::size_t(j) * cols_ + i]; }
  [[nodiscard]] float x_of(std::uint32_t i) const { return params_.origin_x + static_cast<float>(i) * params_.cell_x; }
  [[nodiscard]] float z_of(std::uint32_t j) const { return params_.origin_z + static_cast<float>(j) * params_.cell_z; }
  [[nodiscard]] float min_height() const { return min_height_; }
  [[nodiscard]] float max_height() const { return max_height_; }
  [[nodiscard]] float max_x() const { return x_of(cols_ - 1); }
  [[nodiscard]] float max_z() const { return z_of(rows_ - 1); }
  /// Height of the triangulated surface at (x, z); NaN outside the map.
  [[nodiscard]] float surface_height(float x, float z) const;

 private:
  Heightmap(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params, std::vector<float> heights);
  std::uint32_t cols_ = 0, rows_ = 0;
  HeightmapParams params_;
  std::vector<float> heights_;
  float min_height_ = 0, max_height_ = 0;
};

}  // namespace hail
