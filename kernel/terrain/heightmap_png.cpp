// PNG loader through stb_image (Debian's libstb-dev headers, not vendored). The implementation is
// compiled here, static and PNG-only, so hail needs no extra link dependency and cannot clash
// with an embedder's own stb_image.

#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG  // readable reasons in our messages
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hail/heightmap.h"
#include "kernel/terrain/heightmap_file.h"

namespace hail {
namespace {

using detail::throw_file_error;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

/// stb_image's reason for its last failure, emptied first: stb sets none for some corrupt
/// data (a deflate block of type 3 returns without one), so an unset reason is either null
/// or one left over from an earlier file on this thread (stb keeps it thread-local).
void clear_stb_reason() { stbi__g_failure_reason = nullptr; }
std::string stb_reason() {
  const char* reason = stbi_failure_reason();
  return reason && *reason ? reason : "stb_image gave no reason";
}

/// What the chunk walk learns before stb decodes anything.
struct PngChunks {
  std::uint64_t width = 0, height = 0;
  unsigned bit_depth = 0, colour_type = 0;
  std::uint64_t idat_bytes = 0;  ///< compressed image data, all IDAT chunks together
};

std::uint32_t be32(const unsigned char* b) {
  return std::uint32_t{b[0]} << 24 | std::uint32_t{b[1]} << 16 | std::uint32_t{b[2]} << 8 | b[3];
}

/// Walks the chunks after the signature (the file is positioned there) up to IEND, without
/// reading their data except IHDR's. Refuses a chunk running past the end of the file, a
/// missing IHDR or IEND, and bytes after IEND (data the image does not account for).
PngChunks walk_chunks(std::FILE* file, const std::string& path, std::uint64_t file_size) {
  PngChunks found;
  std::uint64_t at = 8;
  bool have_header = false;
  for (;;) {
    unsigned char head[8];
    if (std::fread(head, 1, sizeof head, file) != sizeof head) throw_file_error(path, "truncated PNG: no IEND chunk");
    const std::uint64_t length = be32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    at += 8;
    if (length + 4 > file_size - at)
      throw_file_error(path,
                       "truncated PNG: chunk " + type + " of " + std::to_string(length) + " bytes runs past the end");
    if (type == "IHDR") {
      unsigned char ihdr[13];
      if (length != sizeof ihdr || std::fread(ihdr, 1, sizeof ihdr, file) != sizeof ihdr)
        throw_file_error(path, "corrupt PNG: IHDR is not 13 bytes");
      found.width = be32(ihdr);
      found.height = be32(ihdr + 4);
      found.bit_depth = ihdr[8];
      found.colour_type = ihdr[9];
      have_header = true;
    } else if (type == "IDAT") {
      // stb_image reads a leading empty IDAT through a null pointer (memcpy(NULL, .., 0):
      // undefined behaviour, found by fuzz-heightmap); no image needs one.
      if (length == 0) throw_file_error(path, "corrupt PNG: empty IDAT chunk");
      found.idat_bytes += length;
    }
    at += length + 4;
    if (std::fseek(file, static_cast<long>(at), SEEK_SET) != 0) throw_file_error(path, "seek failed");
    if (type == "IEND") break;
  }
  if (!have_header) throw_file_error(path, "corrupt PNG: no IHDR chunk");
  if (at != file_size) throw_file_error(path, std::to_string(file_size - at) + " bytes follow the PNG's IEND chunk");
  return found;
}

/// Refuses an image whose compressed data could not hold the samples its header claims.
/// Deflate expands at most 1032:1 (a 258-byte match in two bits), so fewer compressed bytes
/// than raw_bytes / 1032 mean a truncated or lying file; checked before stb allocates the
/// image from the header's size.
void check_compressed_size(const std::string& path, const PngChunks& png) {
  static constexpr unsigned kChannels[7] = {1, 0, 3, 1, 2, 0, 4};  // by colour type
  const unsigned channels = png.colour_type < 7 ? kChannels[png.colour_type] : 1;
  // Scanline filter bytes left out: a lower bound, valid for interlaced images too.
  const std::uint64_t raw_bits = png.width * png.height * std::max(1u, channels) * std::max(1u, png.bit_depth);
  const std::uint64_t raw_bytes = (raw_bits + 7) / 8;
  if (raw_bytes > 1032 * (png.idat_bytes + 1))
    throw_file_error(path, "truncated or corrupt PNG: " + std::to_string(png.idat_bytes) +
                               " bytes of compressed data cannot hold the " + std::to_string(png.width) + " x " +
                               std::to_string(png.height) +
                               " image the header claims (deflate expands at most 1032:1)");
}

}  // namespace

Heightmap Heightmap::load_png(const std::string& path, const HeightmapParams& params) {
  check_heightmap_params(params);
  detail::require_regular_file(path);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw_file_error(path, std::string("cannot open file (") + std::strerror(errno) + ")");
  unsigned char signature[8] = {};
  const std::size_t got = std::fread(signature, 1, sizeof signature, file.get());
  if (got == 0) throw_file_error(path, "empty file");
  static constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got != sizeof signature || std::memcmp(signature, kPngSignature, sizeof signature) != 0)
    throw_file_error(path, "not a PNG file (wrong signature)");
  std::error_code size_error;
  const std::uint64_t file_size = std::filesystem::file_size(path, size_error);
  if (size_error) throw_file_error(path, "cannot read the file's size (" + size_error.message() + ")");
  const PngChunks chunks = walk_chunks(file.get(), path, file_size);
  std::rewind(file.get());

  // The header alone gives the size: refuse it before stb allocates the image.
  int width = 0, height = 0, channels = 0;
  clear_stb_reason();
  if (!stbi_info_from_file(file.get(), &width, &height, &channels))
    throw_file_error(path, "unreadable PNG header (" + stb_reason() + ")");
  if (channels != 1 && channels != 2)
    throw_file_error(path, "colour PNG (" + std::to_string(channels) +
                               " channels): only grey (or grey + alpha) heightmaps are accepted");
  detail::check_file_heightmap_size(path, static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height),
                                    params.max_vertices);
  check_compressed_size(path, chunks);

  const std::size_t count = std::size_t(width) * std::size_t(height);
  std::vector<float> samples(count);
  int w = 0, h = 0, c = 0;
  clear_stb_reason();
  if (stbi_is_16_bit_from_file(file.get())) {
    std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_from_file_16(file.get(), &w, &h, &c, 1));
    if (!pixels) throw_file_error(path, "corrupt or truncated PNG (" + stb_reason() + ")");
    for (std::size_t k = 0; k < count; ++k) samples[k] = static_cast<float>(pixels.get()[k]);
  } else {
    std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_file(file.get(), &w, &h, &c, 1));
    if (!pixels) throw_file_error(path, "corrupt or truncated PNG (" + stb_reason() + ")");
    for (std::size_t k = 0; k < count; ++k) samples[k] = static_cast<float>(pixels.get()[k]);
  }
  if (w != width || h != height) throw_file_error(path, "PNG size changed between header and data");
  return from_file_samples(path, static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), params,
                           std::move(samples));
}

}  // namespace hail
