// PNG loader through stb_image (Debian's libstb-dev headers, not vendored). The implementation is
// compiled here, static and PNG-only, so hail needs no extra link dependency and cannot clash
// with an embedder's own stb_image.

#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG  // readable reasons in our messages
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "kernel/heightmap.h"
#include "kernel/heightmap_file.h"

namespace hail {
namespace {

using detail::throw_file_error;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

Heightmap Heightmap::load_png(const std::string& path, const HeightmapParams& params) {
  check_heightmap_params(params);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw_file_error(path, std::string("cannot open file (") + std::strerror(errno) + ")");
  unsigned char signature[8] = {};
  const std::size_t got = std::fread(signature, 1, sizeof signature, file.get());
  if (got == 0) throw_file_error(path, "empty file");
  static constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got != sizeof signature || std::memcmp(signature, kPngSignature, sizeof signature) != 0)
    throw_file_error(path, "not a PNG file (wrong signature)");
  std::rewind(file.get());

  // The header alone gives the size: refuse it before stb allocates the image.
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_file(file.get(), &width, &height, &channels))
    throw_file_error(path, std::string("unreadable PNG header (") + stbi_failure_reason() + ")");
  if (channels != 1 && channels != 2)
    throw_file_error(path, "colour PNG (" + std::to_string(channels) +
                               " channels): only grey (or grey + alpha) heightmaps are accepted");
  detail::check_file_heightmap_size(path, static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height));

  const std::size_t count = std::size_t(width) * std::size_t(height);
  std::vector<float> samples(count);
  int w = 0, h = 0, c = 0;
  if (stbi_is_16_bit_from_file(file.get())) {
    std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_from_file_16(file.get(), &w, &h, &c, 1));
    if (!pixels) throw_file_error(path, std::string("corrupt or truncated PNG (") + stbi_failure_reason() + ")");
    for (std::size_t k = 0; k < count; ++k) samples[k] = static_cast<float>(pixels.get()[k]);
  } else {
    std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_file(file.get(), &w, &h, &c, 1));
    if (!pixels) throw_file_error(path, std::string("corrupt or truncated PNG (") + stbi_failure_reason() + ")");
    for (std::size_t k = 0; k < count; ++k) samples[k] = static_cast<float>(pixels.get()[k]);
  }
  if (w != width || h != height) throw_file_error(path, "PNG size changed between header and data");
  return from_file_samples(path, static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), params,
                           std::move(samples));
}

}  // namespace hail
