// Headerless raw loaders (float32 little-endian, uint16 either byte order). With no header the
// caller states the size, and the file's length must match it exactly: a wrong size is the
// most common raw-file mistake and would otherwise silently shear the terrain.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "hail/heightmap.h"
#include "kernel/terrain/heightmap_file.h"

namespace hail {
namespace {

using detail::throw_file_error;

/// Opens `path`, checks its length is exactly cols * rows * bytes_per_sample and returns the
/// bytes. Arguments are checked first, so nothing is allocated for an absurd size.
std::vector<unsigned char> read_exact(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                      const HeightmapParams& params, std::size_t bytes_per_sample) {
  check_heightmap_params(params);
  check_heightmap_size(cols, rows, path, params.max_vertices);
  std::ifstream in = detail::open_heightmap_file(path);
  const std::uint64_t size = detail::bytes_remaining(in);
  const std::uint64_t expected = std::uint64_t{cols} * rows * bytes_per_sample;
  if (size == 0) throw_file_error(path, "empty file");
  if (size != expected)
    throw_file_error(path, std::to_string(size) + " bytes, but " + std::to_string(cols) + " x " + std::to_string(rows) +
                               " samples of " + std::to_string(bytes_per_sample) + " bytes need exactly " +
                               std::to_string(expected) + (size < expected ? " (truncated)" : " (wrong size)"));
  std::vector<unsigned char> bytes(expected);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(expected));
  if (static_cast<std::uint64_t>(in.gcount()) != expected) throw_file_error(path, "read failed");
  return bytes;
}

}  // namespace

Heightmap Heightmap::load_raw_f32(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                  const HeightmapParams& params) {
  const std::vector<unsigned char> bytes = read_exact(path, cols, rows, params, 4);
  std::vector<float> samples(std::size_t(cols) * rows);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const unsigned char* b = &bytes[4 * k];
    const std::uint32_t bits =
        std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
    std::memcpy(&samples[k], &bits, 4);
    if (!std::isfinite(samples[k]))
      throw_file_error(path, "sample at column " + std::to_string(k % cols) + ", row " + std::to_string(k / cols) +
                                 " is " + (std::isnan(samples[k]) ? "NaN" : "infinite"));
  }
  return from_file_samples(path, cols, rows, params, std::move(samples));
}

Heightmap Heightmap::load_raw_u16(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                                  const HeightmapParams& params, bool little_endian) {
  const std::vector<unsigned char> bytes = read_exact(path, cols, rows, params, 2);
  std::vector<float> samples(std::size_t(cols) * rows);
  const int hi = little_endian ? 1 : 0, lo = 1 - hi;
  for (std::size_t k = 0; k < samples.size(); ++k)
    samples[k] = static_cast<float>((unsigned{bytes[2 * k + hi]} << 8) | bytes[2 * k + lo]);
  return from_file_samples(path, cols, rows, params, std::move(samples));
}

}  // namespace hail
