// PGM (P5 binary 8/16-bit, P2 ASCII) loader. Every problem is a FileError naming the file;
// sizes are checked against the limits before any sample buffer is allocated.

#include <cctype>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "kernel/errors.h"
#include "kernel/heightmap.h"

namespace hail {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw FileError("hail: " + path + ": " + problem);
}

/// Next whitespace-separated header token, skipping '#' comments.
std::string next_token(std::istream& in, const std::string& path, const char* what) {
  std::string token;
  int c;
  while ((c = in.get()) != EOF) {
    if (c == '#') {
      while ((c = in.get()) != EOF && c != '\n') {}
      continue;
    }
    if (std::isspace(c)) {
      if (!token.empty()) return token;
      continue;
    }
    token.push_back(static_cast<char>(c));
    if (token.size() > 20) fail(path, std::string("malformed header: ") + what + " is not a number");
  }
  if (token.empty()) fail(path, std::string("truncated header: missing ") + what);
  return token;
}

std::uint64_t header_number(std::istream& in, const std::string& path, const char* what) {
  const std::string token = next_token(in, path, what);
  for (char ch : token)
    if (!std::isdigit(static_cast<unsigned char>(ch))) fail(path, std::string("malformed header: ") + what + " '" + token + "' is not a number");
  return std::stoull(token);
}

}  // namespace

Heightmap Heightmap::load_pgm(const std::string& path, const HeightmapParams& params) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  char magic[2] = {0, 0};
  in.read(magic, 2);
  if (in.gcount() != 2 || magic[0] != 'P' || (magic[1] != '5' && magic[1] != '2'))
    fail(path, "not a PGM file (magic must be P5 or P2)");
  const bool binary = magic[1] == '5';
  const std::uint64_t cols = header_number(in, path, "width");
  const std::uint64_t rows = header_number(in, path, "height");
  const std::uint64_t maxval = header_number(in, path, "maxval");
  if (cols == 0 || rows == 0) fail(path, "zero width or height");
  if (maxval == 0 || maxval > 65535) fail(path, "maxval " + std::to_string(maxval) + " outside 1..65535");
  try {
    check_heightmap_size(cols, rows, path);
  } catch (const InvalidArgument& e) {
    throw FileError(e.what());
  }
  const std::size_t count = cols * rows;
  std::vector<float> samples(count);
  if (binary) {
    // Exactly one whitespace byte separates the header from the samples (already consumed).
    const std::size_t bytes_per = maxval > 255 ? 2 : 1;
    std::vector<unsigned char> raw(count * bytes_per);
    in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
    if (static_cast<std::size_t>(in.gcount()) != raw.size())
      fail(path, "truncated data: " + std::to_string(in.gcount()) + " of " + std::to_string(raw.size()) + " sample bytes");
    for (std::size_t k = 0; k < count; ++k) {
      const unsigned v = bytes_per == 2 ? (unsigned(raw[2 * k]) << 8) | raw[2 * k + 1] : raw[k];
      if (v > maxval) fail(path, "sample " + std::to_string(k) + " = " + std::to_string(v) + " exceeds maxval");
      samples[k] = static_cast<float>(v);
    }
  } else {
    for (std::size_t k = 0; k < count; ++k) {
      std::string token;
      if (!(in >> token)) fail(path, "truncated data: " + std::to_string(k) + " of " + std::to_string(count) + " samples");
      for (char ch : token)
        if (!std::isdigit(static_cast<unsigned char>(ch))) fail(path, "sample " + std::to_string(k) + " '" + token + "' is not a number");
      const unsigned long v = token.size() > 6 ? maxval + 1 : std::stoul(token);
      if (v > maxval) fail(path, "sample " + std::to_string(k) + " exceeds maxval");
      samples[k] = static_cast<float>(v);
    }
  }
  try {
    return from_samples(static_cast<std::uint32_t>(cols), static_cast<std::uint32_t>(rows), params, std::move(samples));
  } catch (const InvalidArgument& e) {
    throw FileError("hail: " + path + ": " + e.what());
  }
}

}  // namespace hail
