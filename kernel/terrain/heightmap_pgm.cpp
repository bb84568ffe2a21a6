// PGM loader: binary P5 (8-bit, or 16-bit big-endian when maxval > 255) and ASCII P2.
// The header is checked in full, and the file's length against what the header promises,
// before any sample buffer is allocated; what follows the raster is checked after it.

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "hail/heightmap.h"
#include "kernel/terrain/heightmap_file.h"

namespace hail {
namespace {

using detail::throw_file_error;

/// Longest number accepted in a PGM: 10 digits hold every value below the size limits, and
/// capping the length keeps a garbage file from growing a token without bound.
constexpr std::size_t kMaxDigits = 10;

/// The next whitespace-separated token, skipping '#' comments; empty at end of file. Consumes
/// exactly one whitespace byte after the token, as P5 requires before the raster.
std::string next_token(std::istream& in) {
  std::string token;
  for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
    if (c == '#' && token.empty()) {
      while ((c = in.get()) != std::char_traits<char>::eof() && c != '\n' && c != '\r') {
      }
      continue;
    }
    if (std::isspace(c)) {
      if (token.empty()) continue;
      return token;
    }
    token.push_back(static_cast<char>(c));
    if (token.size() > kMaxDigits) return token;  // too long: the caller reports it
  }
  return token;
}

/// A non-negative decimal number read as `what`, or a FileError naming the problem.
std::uint64_t read_number(std::istream& in, const std::string& path, const std::string& what) {
  const std::string token = next_token(in);
  if (token.empty()) throw_file_error(path, "truncated: missing " + what);
  std::uint64_t value = 0;
  for (char ch : token) {
    if (!std::isdigit(static_cast<unsigned char>(ch)))
      throw_file_error(path, what + " '" + token.substr(0, kMaxDigits) + "' is not a non-negative integer");
    value = value * 10 + static_cast<std::uint64_t>(ch - '0');
  }
  if (token.size() > kMaxDigits) throw_file_error(path, what + " '" + token + "...' is too large");
  return value;
}

/// P5 raster: big-endian when two bytes per sample (the PGM rule). Read in chunks so the only
/// large allocation is the sample array itself.
void read_binary_samples(std::istream& in, const std::string& path, std::uint64_t maxval, std::vector<float>& out) {
  const std::size_t bytes_per_sample = maxval > 255 ? 2 : 1;
  std::vector<unsigned char> chunk(std::size_t{1} << 16);
  std::size_t done = 0;
  while (done < out.size()) {
    const std::size_t n = std::min(out.size() - done, chunk.size() / bytes_per_sample);
    in.read(reinterpret_cast<char*>(chunk.data()), static_cast<std::streamsize>(n * bytes_per_sample));
    if (static_cast<std::size_t>(in.gcount()) != n * bytes_per_sample)
      throw_file_error(path, "truncated data after sample " + std::to_string(done));
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t v = bytes_per_sample == 2 ? (std::uint32_t{chunk[2 * k]} << 8) | chunk[2 * k + 1] : chunk[k];
      if (v > maxval)
        throw_file_error(path, "sample " + std::to_string(done + k) + " = " + std::to_string(v) + " exceeds maxval " +
                                   std::to_string(maxval));
      out[done + k] = static_cast<float>(v);
    }
    done += n;
  }
}

void read_ascii_samples(std::istream& in, const std::string& path, std::uint64_t maxval, std::vector<float>& out) {
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::string what = "sample " + std::to_string(k);
    const std::uint64_t v = read_number(in, path, what);
    if (v > maxval)
      throw_file_error(path, what + " = " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
    out[k] = static_cast<float>(v);
  }
}

/// After the raster only whitespace (and, in P2, '#' comments) or the next image of a
/// multi-image file may follow. Anything else is data the header did not account for: a wrong
/// width, height or maxval, which would otherwise load a sheared or truncated map silently.
void check_after_raster(std::istream& in, const std::string& path, bool ascii) {
  const std::uint64_t trailing = detail::bytes_remaining(in);
  for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
    if (std::isspace(c)) continue;
    if (c == '#' && ascii) {
      while ((c = in.get()) != std::char_traits<char>::eof() && c != '\n' && c != '\r') {
      }
      continue;
    }
    const int kind = in.get(), after = in.peek();
    if (c == 'P' && (kind == '5' || kind == '2') && std::isspace(after)) return;  // the next image
    throw_file_error(path, std::to_string(trailing) + " bytes follow the raster, not only whitespace or a next image " +
                               "(is the header's width, height or maxval wrong?)");
  }
}

}  // namespace

Heightmap Heightmap::load_pgm(const std::string& path, const HeightmapParams& params) {
  check_heightmap_params(params);
  std::ifstream in = detail::open_heightmap_file(path);
  char magic[2] = {0, 0};
  in.read(magic, 2);
  if (in.gcount() == 0) throw_file_error(path, "empty file");
  if (in.gcount() != 2 || magic[0] != 'P' || (magic[1] != '5' && magic[1] != '2'))
    throw_file_error(path, "not a PGM file (magic number must be P5 or P2)");
  if (!std::isspace(in.peek())) throw_file_error(path, "not a PGM file (no whitespace after the magic number)");
  const bool binary = magic[1] == '5';
  const std::uint64_t cols = read_number(in, path, "width");
  const std::uint64_t rows = read_number(in, path, "height");
  const std::uint64_t maxval = read_number(in, path, "maxval");
  if (maxval == 0 || maxval > 65535) throw_file_error(path, "maxval " + std::to_string(maxval) + " outside 1..65535");
  detail::check_file_heightmap_size(path, cols, rows, params.max_vertices);

  // Refuse a file too short for its header before allocating what the header promises. An
  // ASCII sample takes at least two bytes (a digit and a separator; the last needs none).
  const std::uint64_t count = cols * rows;
  const std::uint64_t needed = binary ? count * (maxval > 255 ? 2 : 1) : 2 * count - 1;
  const std::uint64_t present = detail::bytes_remaining(in);
  if (present < needed)
    throw_file_error(path, "truncated data: " + std::to_string(present) + " bytes after the header, " +
                               std::to_string(cols) + " x " + std::to_string(rows) + " samples need " +
                               (binary ? "" : "at least ") + std::to_string(needed));

  std::vector<float> samples(count);
  if (binary)
    read_binary_samples(in, path, maxval, samples);
  else
    read_ascii_samples(in, path, maxval, samples);
  check_after_raster(in, path, !binary);
  return from_file_samples(path, static_cast<std::uint32_t>(cols), static_cast<std::uint32_t>(rows), params,
                           std::move(samples));
}

}  // namespace hail
