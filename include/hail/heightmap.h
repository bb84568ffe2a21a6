#pragma once
// A static heightmap: a grid of cols (along x, index i) x rows (along z, index j) vertex heights
// in metres, row-major (j * cols + i). Vertex (i, j) sits at
//   x = origin_x + i cell_x,   z = origin_z + j cell_z,   y = origin_y + height_offset + height_scale * sample.
// Each cell (i, j)-(i+1, j+1) is two triangles split along the diagonal from vertex (i+1, j) to
// vertex (i, j+1) (Bullet's default); kernel/terrain/terrain_triangles.h builds them, and
// surface_height() interpolates on exactly those triangles.
//
// Factories validate everything before allocating and either return a whole map or throw:
// InvalidArgument for bad values passed in, FileError ("hail: <path>: <problem>") for bad files.
// The loaders open regular files only (a FIFO would block, a directory or device has no length),
// check the header's size against HeightmapParams::max_vertices and the file's length before
// allocating, and refuse data after the image (see each loader).
//
// A Heightmap is a value: it owns its heights (one float per vertex, allocated by the factory;
// copying copies them, moving does not) and has no mutating members, so its const members may
// be called from any number of threads at once. None of them allocates. Terrain takes one by
// value (move it in).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hail/vec3.h"

namespace hail {

/// Largest heightmap accepted, checked before any sample buffer is allocated: at most 65,536
/// vertices per side and 2^28 vertices in all (1 GiB of float heights). A file header claiming
/// more is refused at once, so a corrupt or hostile file cannot make hail allocate gigabytes.
inline constexpr std::uint64_t kMaxHeightmapSide = 65536;
inline constexpr std::uint64_t kMaxHeightmapVertices = std::uint64_t{1} << 28;

/// Where a heightmap lies, how file samples become metres, and how big a map may be. Every
/// float field must be finite.
struct HeightmapParams {
  float cell_x = 1.0f;         ///< m between columns (along x), > 0
  float cell_z = 1.0f;         ///< m between rows (along z), > 0
  float height_scale = 1.0f;   ///< m per file sample unit (loaders and from_samples only)
  float height_offset = 0.0f;  ///< m added to every scaled sample (loaders and from_samples only)
  float origin_x = 0.0f;       ///< m, x of column 0
  float origin_y = 0.0f;       ///< m, added to every height (all factories)
  float origin_z = 0.0f;       ///< m, z of row 0
  /// Most vertices (cols * rows) a factory accepts, 4 .. kMaxHeightmapVertices, checked before
  /// anything is allocated. The default allows the hard limit (1 GiB of heights); lower it to
  /// bound memory, e.g. from a memory budget: a Terrain built on the map takes about 600 bytes
  /// per cell at its peak (include/hail/terrain.h). A file header over it throws SizeLimitError.
  std::uint64_t max_vertices = kMaxHeightmapVertices;
};

/// The rectangle a heightmap covers in x and z, metres.
struct HeightmapExtent {
  float min_x, max_x, min_z, max_z;
};

/// Throws InvalidArgument unless every float field of `params` is finite, both cells are > 0
/// and 4 <= max_vertices <= kMaxHeightmapVertices.
void check_heightmap_params(const HeightmapParams& params);

/// Throws InvalidArgument naming `where` unless 2 <= cols, rows <= kMaxHeightmapSide and
/// cols * rows <= max_vertices (<= kMaxHeightmapVertices). Cheap: call it before allocating.
void check_heightmap_size(std::uint64_t cols, std::uint64_t rows, const std::string& where,
                          std::uint64_t max_vertices = kMaxHeightmapVertices);

class Heightmap {
 public:
  /// Samples `height_at(x, z)` at every vertex's world x, z (m) and takes its value, in metres,
  /// as the height above origin_y: y = origin_y + height_at(x, z). height_scale and
  /// height_offset are not applied (they convert file samples). `height_at` is any callable
  /// float(float, float); a non-finite value throws InvalidArgument.
  template <class HeightAt>
  static Heightmap from_function(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                 HeightAt&& height_at) {
    check_heightmap_params(params);
    check_heightmap_size(cols, rows, "Heightmap::from_function", params.max_vertices);
    std::vector<float> heights(std::size_t(cols) * rows);
    for (std::uint32_t j = 0; j < rows; ++j)
      for (std::uint32_t i = 0; i < cols; ++i)
        heights[std::size_t(j) * cols + i] =
            params.origin_y + static_cast<float>(height_at(params.origin_x + static_cast<float>(i) * params.cell_x,
                                                           params.origin_z + static_cast<float>(j) * params.cell_z));
    return Heightmap(cols, rows, params, std::move(heights), "Heightmap::from_function");
  }

  /// From raw samples in memory (row-major, j * cols + i):
  /// y = origin_y + height_offset + height_scale * sample. Throws InvalidArgument.
  static Heightmap from_samples(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params,
                                std::vector<float> samples);

  /// PGM: binary P5 with 8-bit samples (maxval 1..255) or 16-bit big-endian samples (maxval
  /// 256..65535), or ASCII P2; '#' comments allowed in the header. Samples are used raw
  /// (y = origin_y + height_offset + height_scale * sample). File row 0 becomes j = 0: in the
  /// shipped DEMs row 0 is the north edge, so z grows southwards. Only the first image of a
  /// multi-image file is read. After the raster only whitespace (and, in P2, '#' comments) or
  /// the next image's magic number may follow: other trailing data means the header's size or
  /// maxval is wrong. Throws FileError (InvalidArgument for bad params).
  static Heightmap load_pgm(const std::string& path, const HeightmapParams& params);

  /// PNG, 8- or 16-bit grey (grey + alpha accepted, alpha ignored; 1/2/4-bit grey is widened
  /// to 0..255 by stb_image). Colour and palette PNGs are refused rather than guessed at.
  /// Samples used raw as in load_pgm; image row 0 becomes j = 0. The chunks are walked before
  /// decoding: bytes after IEND are refused, and so is compressed data too short for the size
  /// the header claims (deflate expands at most 1032:1). Throws FileError.
  static Heightmap load_png(const std::string& path, const HeightmapParams& params);

  /// Headerless little-endian IEEE-754 float32 samples, row-major; the file must be exactly
  /// cols * rows * 4 bytes and every sample finite. Throws FileError (InvalidArgument for a
  /// bad cols, rows or params).
  static Heightmap load_raw_f32(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                const HeightmapParams& params);

  /// Headerless unsigned 16-bit samples, row-major, little- or big-endian; the file must be
  /// exactly cols * rows * 2 bytes. Throws FileError (InvalidArgument for bad arguments).
  static Heightmap load_raw_u16(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                const HeightmapParams& params, bool little_endian = true);

  /// The same map moved by `by` (m): origin x and z plus by.x and by.z, every height plus by.y
  /// (by.y = 0 keeps the heights bit for bit). The samples are copied, not re-sampled: a
  /// function map keeps the shape it was sampled with. Throws InvalidArgument (naming the
  /// value) for a non-finite `by`, or an origin or height that is no longer a finite float.
  [[nodiscard]] Heightmap moved(const Vec3& by) const;

  /// Vertices along x (>= 2).
  [[nodiscard]] std::uint32_t cols() const { return cols_; }
  /// Vertices along z (>= 2).
  [[nodiscard]] std::uint32_t rows() const { return rows_; }
  [[nodiscard]] const HeightmapParams& params() const { return params_; }
  /// All vertex heights y in metres, row-major (j * cols + i).
  [[nodiscard]] std::span<const float> heights() const { return heights_; }
  /// Height y of vertex (i, j) in metres (origin, offset and scale applied). No bounds check.
  [[nodiscard]] float h(std::uint32_t i, std::uint32_t j) const { return heights_[std::size_t(j) * cols_ + i]; }
  /// Same as h(i, j).
  [[nodiscard]] float height(std::uint32_t i, std::uint32_t j) const { return h(i, j); }
  /// World x (m) of column i.
  [[nodiscard]] float x_of(std::uint32_t i) const { return params_.origin_x + static_cast<float>(i) * params_.cell_x; }
  /// World z (m) of row j.
  [[nodiscard]] float z_of(std::uint32_t j) const { return params_.origin_z + static_cast<float>(j) * params_.cell_z; }
  /// World position (m) of vertex (i, j).
  [[nodiscard]] Vec3 vertex(std::uint32_t i, std::uint32_t j) const { return {x_of(i), h(i, j), z_of(j)}; }
  /// Lowest vertex height, m.
  [[nodiscard]] float min_height() const { return min_height_; }
  /// Highest vertex height, m.
  [[nodiscard]] float max_height() const { return max_height_; }
  /// x and z covered by the map, m.
  [[nodiscard]] HeightmapExtent extent() const { return {x_of(0), max_x(), z_of(0), max_z()}; }
  /// Largest world x (m): column cols - 1.
  [[nodiscard]] float max_x() const { return x_of(cols_ - 1); }
  /// Largest world z (m): row rows - 1.
  [[nodiscard]] float max_z() const { return z_of(rows_ - 1); }
  /// Height y (m) of the triangulated surface at world (x, z), on the same triangles as
  /// build_terrain_triangles(); NaN outside the extent (or for NaN input).
  [[nodiscard]] float surface_height(float x, float z) const;

 private:
  /// Takes final heights (m); checks they are finite (InvalidArgument naming `where`).
  Heightmap(std::uint32_t cols, std::uint32_t rows, const HeightmapParams& params, std::vector<float> heights,
            const std::string& where);
  /// For the file loaders: raw samples to heights as from_samples, but every problem is a
  /// FileError "hail: <path>: ..." (params are checked by the loader before it opens the file).
  static Heightmap from_file_samples(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                     const HeightmapParams& params, std::vector<float> samples);

  std::uint32_t cols_ = 0, rows_ = 0;
  HeightmapParams params_;
  std::vector<float> heights_;
  float min_height_ = 0.0f, max_height_ = 0.0f;
};

}  // namespace hail
