// The mesh file loaders (TriangleMesh::load, load_obj, load_stl). Each reads its file whole
// through kernel/files/ (regular files only, never past the size the file system gave), checks
// every number and index, and names the line (or triangle) at fault.

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "hail/errors.h"
#include "hail/triangle_mesh.h"
#include "kernel/files/regular_file.h"

namespace hail {
namespace {

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& problem) {
  throw FileError("hail: " + path + (line ? ":" + std::to_string(line) : std::string()) + ": " + problem);
}

std::string_view as_text(const std::vector<std::byte>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

/// Splits a line into whitespace-separated words (at most `max`; the rest are ignored).
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
    std::size_t end = k;
    while (end < line.size() && !std::isspace(static_cast<unsigned char>(line[end]))) ++end;
    if (end > k) out.push_back(line.substr(k, end - k));
    k = end;
  }
  return out;
}

float parse_float(std::string_view word, const std::string& path, std::size_t line, const char* what) {
  float v = 0.0f;
  const char* end = word.data() + word.size();
  const auto [ptr, ec] = std::from_chars(word.data(), end, v);
  if (ec != std::errc() || ptr != end)
    fail(path, line, std::string(what) + " '" + std::string(word) + "' is not a number");
  if (!std::isfinite(v)) fail(path, line, std::string(what) + " '" + std::string(word) + "' is not finite");
  return v;
}

/// Calls `on_line(number, text)` for each line (1-based), without its end-of-line characters.
template <class OnLine>
void for_each_line(std::string_view text, OnLine&& on_line) {
  std::size_t number = 0, k = 0;
  while (k < text.size()) {
    std::size_t end = text.find('\n', k);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(k, end - k);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    on_line(++number, line);
    k = end + 1;
  }
}

TriangleMesh finish(const std::string& path, std::vector<Vec3> vertices, std::vector<std::uint32_t> indices) {
  if (indices.empty()) fail(path, 0, "no triangles");
  try {
    return TriangleMesh(std::move(vertices), std::move(indices));
  } catch (const InvalidArgument& e) {
    fail(path, 0, e.what());
  }
}

/// Merges vertices with equal coordinates (STL stores each triangle's corners apart).
class VertexWelder {
 public:
  std::uint32_t add(const Vec3& p) {
    const std::array<float, 3> key{p.x(), p.y(), p.z()};
    const auto [it, fresh] = index_.try_emplace(key, static_cast<std::uint32_t>(vertices_.size()));
    if (fresh) vertices_.push_back(p);
    return it->second;
  }
  std::vector<Vec3> take() { return std::move(vertices_); }

 private:
  std::map<std::array<float, 3>, std::uint32_t> index_;
  std::vector<Vec3> vertices_;
};

TriangleMesh load_stl_binary(const std::string& path, const std::vector<std::byte>& bytes, std::uint32_t count) {
  VertexWelder welder;
  std::vector<std::uint32_t> indices;
  indices.reserve(std::size_t{count} * 3);
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::byte* record = bytes.data() + 84 + std::size_t{t} * 50;
    for (int corner = 0; corner < 3; ++corner) {
      float xyz[3];
      std::memcpy(xyz, record + 12 + 12 * corner, 12);  // little-endian floats, as every host hail builds on
      for (float v : xyz)
        if (!std::isfinite(v)) fail(path, 0, "triangle " + std::to_string(t) + " has a corner that is not finite");
      indices.push_back(welder.add(Vec3(xyz[0], xyz[1], xyz[2])));
    }
  }
  return finish(path, welder.take(), std::move(indices));
}

TriangleMesh load_stl_ascii(const std::string& path, std::string_view text) {
  VertexWelder welder;
  std::vector<std::uint32_t> indices;
  std::vector<std::uint32_t> loop;  // the current facet's corners
  bool in_solid = false, in_loop = false, ended = false;
  for_each_line(text, [&](std::size_t line, std::string_view content) {
    const std::vector<std::string_view> w = words(content);
    if (w.empty()) return;
    if (ended) fail(path, line, "text after endsolid");
    if (!in_solid) {
      if (w[0] != "solid")
        fail(path, line, "an ASCII STL file starts with 'solid', this one with '" + std::string(w[0]) + "'");
      in_solid = true;
    } else if (w[0] == "facet" || w[0] == "endfacet") {
    } else if (w[0] == "outer") {
      if (in_loop) fail(path, line, "'outer loop' inside a loop");
      in_loop = true;
      loop.clear();
    } else if (w[0] == "vertex") {
      if (!in_loop) fail(path, line, "'vertex' outside 'outer loop'");
      if (w.size() != 4) fail(path, line, "'vertex' needs three coordinates");
      loop.push_back(welder.add(Vec3(parse_float(w[1], path, line, "x"), parse_float(w[2], path, line, "y"),
                                     parse_float(w[3], path, line, "z"))));
    } else if (w[0] == "endloop") {
      if (!in_loop) fail(path, line, "'endloop' without 'outer loop'");
      if (loop.size() < 3) fail(path, line, "a facet with " + std::to_string(loop.size()) + " vertices (3 needed)");
      for (std::size_t k = 1; k + 1 < loop.size(); ++k) indices.insert(indices.end(), {loop[0], loop[k], loop[k + 1]});
      in_loop = false;
    } else if (w[0] == "endsolid") {
      if (in_loop) fail(path, line, "'endsolid' inside a loop");
      ended = true;
    } else {
      fail(path, line, "unknown keyword '" + std::string(w[0]) + "'");
    }
  });
  if (!in_solid) fail(path, 0, "empty file");
  if (!ended) fail(path, 0, "truncated: no 'endsolid'");
  return finish(path, welder.take(), std::move(indices));
}

/// One OBJ face index ("i", "i/t", "i//n", "i/t/n"; negative: from the end) as 0-based.
std::uint32_t obj_index(std::string_view word, std::size_t vertex_count, const std::string& path, std::size_t line) {
  const std::string_view first = word.substr(0, word.find('/'));
  long long i = 0;
  const auto [ptr, ec] = std::from_chars(first.data(), first.data() + first.size(), i);
  if (ec != std::errc() || ptr != first.data() + first.size() || i == 0)
    fail(path, line, "face index '" + std::string(word) + "' is not a non-zero whole number");
  const long long resolved = i > 0 ? i - 1 : static_cast<long long>(vertex_count) + i;
  if (resolved < 0 || resolved >= static_cast<long long>(vertex_count))
    fail(path, line,
         "face index " + std::to_string(i) + " names no vertex (" + std::to_string(vertex_count) + " so far)");
  return static_cast<std::uint32_t>(resolved);
}

}  // namespace

TriangleMesh TriangleMesh::load_obj(const std::string& path) {
  const std::vector<std::byte> bytes = files::read_regular_file(path, {}, "a mesh file");
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  for_each_line(as_text(bytes), [&](std::size_t line, std::string_view content) {
    const std::vector<std::string_view> w = words(content.substr(0, content.find('#')));
    if (w.empty()) return;
    if (w[0] == "v") {
      if (w.size() < 4) fail(path, line, "'v' needs three coordinates");
      vertices.emplace_back(parse_float(w[1], path, line, "x"), parse_float(w[2], path, line, "y"),
                            parse_float(w[3], path, line, "z"));
    } else if (w[0] == "f") {
      if (w.size() < 4) fail(path, line, "a face needs three or more vertices");
      const std::uint32_t first = obj_index(w[1], vertices.size(), path, line);
      std::uint32_t previous = obj_index(w[2], vertices.size(), path, line);
      for (std::size_t k = 3; k < w.size(); ++k) {
        const std::uint32_t next = obj_index(w[k], vertices.size(), path, line);
        indices.insert(indices.end(), {first, previous, next});
        previous = next;
      }
      if (indices.size() / 3 > kMaxMeshTriangles) fail(path, line, "more than kMaxMeshTriangles triangles");
    }
  });
  return finish(path, std::move(vertices), std::move(indices));
}

TriangleMesh TriangleMesh::load_stl(const std::string& path) {
  const std::vector<std::byte> bytes = files::read_regular_file(path, {}, "a mesh file");
  if (bytes.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (84 + std::uint64_t{count} * 50 == bytes.size()) {
      if (count > kMaxMeshTriangles) fail(path, 0, std::to_string(count) + " triangles, more than kMaxMeshTriangles");
      return load_stl_binary(path, bytes, count);
    }
  }
  const std::string_view text = as_text(bytes);
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos) fail(path, 0, "empty file");
  if (text.substr(start, 5) != "solid")
    fail(path, 0,
         std::to_string(bytes.size()) +
             " bytes: neither binary STL (84 + 50 bytes a triangle, as its header counts) nor ASCII STL "
             "(starting with 'solid')");
  return load_stl_ascii(path, text);
}

TriangleMesh TriangleMesh::load(const std::string& path) {
  std::string extension =
      path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return load_obj(path);
  if (extension == ".stl") return load_stl(path);
  fail(path, 0, "unknown mesh file type '" + extension + "' (.obj or .stl)");
}

}  // namespace hail
