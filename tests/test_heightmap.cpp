// Heightmaps: sampling, the real DEMs in data/, file round trips, every refused file, and the
// per-triangle terrain data (layout, normals, planes, internal edges).

#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/stat.h>
#endif

#include "catch.h"
#include "hail/errors.h"
#include "hail/heightmap.h"
#include "kernel/terrain/terrain_triangles.h"

using hail::FileError;
using hail::Heightmap;
using hail::HeightmapParams;
using hail::InvalidArgument;

namespace {

namespace fs = std::filesystem;

/// A fresh directory for one test's files, removed afterwards.
struct TempDir {
  fs::path path;
  TempDir() {
    static int serial = 0;
    const auto stamp = static_cast<long>(::getpid());
    path =
        fs::temp_directory_path() / ("hail-test-heightmap-" + std::to_string(stamp) + "-" + std::to_string(serial++));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  std::string write(const std::string& name, const std::vector<unsigned char>& bytes) const {
    const std::string file = (path / name).string();
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return file;
  }
  std::string write(const std::string& name, const std::string& text) const {
    return write(name, std::vector<unsigned char>(text.begin(), text.end()));
  }
};

std::vector<unsigned char> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

void append(std::vector<unsigned char>& out, const std::vector<unsigned char>& more) {
  out.insert(out.end(), more.begin(), more.end());
}

void put_be32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}

std::uint32_t crc32(const unsigned char* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t k = 0; k < n; ++k) {
    c ^= p[k];
    for (int b = 0; b < 8; ++b) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

/// A minimal valid PNG (zlib "stored" blocks, filter 0): stb_image_write cannot write 16-bit.
/// colour_type 0 = grey, 2 = RGB; `samples` holds width * height * channels values.
std::vector<unsigned char> make_png(std::uint32_t width, std::uint32_t height, int bit_depth, int colour_type,
                                    const std::vector<std::uint16_t>& samples) {
  const std::size_t channels = colour_type == 2 ? 3 : 1, per_row = width * channels;
  std::vector<unsigned char> raw;
  for (std::uint32_t y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    for (std::size_t k = 0; k < per_row; ++k) {
      const std::uint16_t v = samples[y * per_row + k];
      if (bit_depth == 16) raw.push_back(static_cast<unsigned char>(v >> 8));
      raw.push_back(static_cast<unsigned char>(v));
    }
  }
  std::vector<unsigned char> zlib = {0x78, 0x01};
  for (std::size_t at = 0; at < raw.size(); at += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    zlib.push_back(at + n >= raw.size() ? 1 : 0);
    for (std::uint16_t v : {std::uint16_t(n), std::uint16_t(~n)}) {
      zlib.push_back(static_cast<unsigned char>(v));
      zlib.push_back(static_cast<unsigned char>(v >> 8));
    }
    zlib.insert(zlib.end(), raw.begin() + std::ptrdiff_t(at), raw.begin() + std::ptrdiff_t(at + n));
  }
  std::uint32_t a = 1, b = 0;
  for (unsigned char byte : raw) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  put_be32(zlib, (b << 16) | a);

  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  auto chunk = [&](const char* type, const std::vector<unsigned char>& data) {
    put_be32(png, static_cast<std::uint32_t>(data.size()));
    std::vector<unsigned char> body(type, type + 4);
    append(body, data);
    append(png, body);
    put_be32(png, crc32(body.data(), body.size()));
  };
  std::vector<unsigned char> ihdr;
  put_be32(ihdr, width);
  put_be32(ihdr, height);
  append(ihdr, {static_cast<unsigned char>(bit_depth), static_cast<unsigned char>(colour_type), 0, 0, 0});
  chunk("IHDR", ihdr);
  chunk("IDAT", zlib);
  chunk("IEND", {});
  return png;
}

/// Binary PGM: 8-bit when maxval < 256, else 16-bit big-endian.
std::vector<unsigned char> make_p5(std::uint32_t cols, std::uint32_t rows, std::uint32_t maxval,
                                   const std::vector<std::uint16_t>& samples) {
  std::vector<unsigned char> out = bytes_of("P5\n# made by test_heightmap\n" + std::to_string(cols) + " " +
                                            std::to_string(rows) + "\n" + std::to_string(maxval) + "\n");
  for (std::uint16_t v : samples) {
    if (maxval > 255) out.push_back(static_cast<unsigned char>(v >> 8));
    out.push_back(static_cast<unsigned char>(v));
  }
  return out;
}

/// The "key = value" lines of a data/*.txt note.
std::map<std::string, std::string> read_note(const std::string& path) {
  std::map<std::string, std::string> note;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (eq == std::string::npos) continue;
    std::string value = line.substr(eq + 3);
    value = value.substr(0, value.find("  #"));
    note[line.substr(0, eq)] = value;
  }
  return note;
}

/// Runs `load` and checks it throws E with a message naming `path` (the file's name at least).
template <class E, class Load>
void require_refused(const std::string& path, Load&& load) {
  INFO(path);
  bool threw = false;
  try {
    load();
  } catch (const E& e) {
    threw = true;
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find(fs::path(path).filename().string()) != std::string::npos);
    CHECK(message.rfind("hail: ", 0) == 0);
  }
  CHECK(threw);
}

/// The (i, j) grid vertices of triangle t in the documented layout.
std::array<std::array<std::uint32_t, 2>, 3> layout_corners(const Heightmap& h, std::size_t t) {
  const std::uint32_t cells_x = h.cols() - 1, cell = static_cast<std::uint32_t>(t / 2), i = cell % cells_x,
                      j = cell / cells_x;
  if (t % 2 == 0) return {{{i, j}, {i, j + 1}, {i + 1, j}}};
  return {{{i + 1, j}, {i, j + 1}, {i + 1, j + 1}}};
}

/// Whether edge e of triangle t lies on the map's boundary.
bool on_boundary(const Heightmap& h, std::size_t t, int e) {
  const auto c = layout_corners(h, t);
  const auto a = c[e], b = c[(e + 1) % 3];
  const std::uint32_t last_i = h.cols() - 1, last_j = h.rows() - 1;
  return (a[0] == b[0] && (a[0] == 0 || a[0] == last_i)) || (a[1] == b[1] && (a[1] == 0 || a[1] == last_j));
}

bool internal(const hail::TerrainTriangles& s, std::size_t t, int e) { return (s.internal_edges[t] >> e) & 1u; }

}  // namespace

TEST_CASE("from_function samples world x, z and adds origin_y only", "[heightmap]") {
  HeightmapParams p;
  p.cell_x = 0.5f;
  p.cell_z = 2.0f;
  p.origin_x = 1.0f;
  p.origin_y = 10.0f;
  p.origin_z = -3.0f;
  p.height_scale = 5.0f;  // for file samples: must not apply here
  p.height_offset = 7.0f;
  const Heightmap h = Heightmap::from_function(5, 4, p, [](float x, float z) { return 2.0f * x + 3.0f * z; });
  REQUIRE(h.cols() == 5);
  REQUIRE(h.rows() == 4);
  REQUIRE(h.heights().size() == 20);
  for (std::uint32_t j = 0; j < 4; ++j)
    for (std::uint32_t i = 0; i < 5; ++i) {
      const float x = 1.0f + 0.5f * float(i), z = -3.0f + 2.0f * float(j);
      CHECK(h.h(i, j) == Approx(10.0f + 2.0f * x + 3.0f * z));
      CHECK(h.heights()[j * 5 + i] == h.h(i, j));
      const hail::Vec3 v = h.vertex(i, j);
      CHECK(v.x() == x);
      CHECK(v.y() == h.h(i, j));
      CHECK(v.z() == z);
    }
  const hail::HeightmapExtent e = h.extent();
  CHECK(e.min_x == 1.0f);
  CHECK(e.max_x == 3.0f);
  CHECK(e.min_z == -3.0f);
  CHECK(e.max_z == 3.0f);
  CHECK(h.min_height() == Approx(10.0f + 2.0f - 9.0f));
  CHECK(h.max_height() == Approx(10.0f + 6.0f + 9.0f));

  // from_samples applies scale and offset (and origin_y) to raw samples.
  const Heightmap s = Heightmap::from_samples(2, 2, p, {0.0f, 1.0f, 2.0f, 3.0f});
  CHECK(s.h(1, 1) == Approx(10.0f + 7.0f + 5.0f * 3.0f));
}

TEST_CASE("The smallest maps work: one cell, and 3 x 2 vertices", "[heightmap]") {
  const Heightmap one = Heightmap::from_function(2, 2, {}, [](float x, float z) { return x + z; });
  CHECK(hail::build_terrain_triangles(one).size() == 2);
  const Heightmap strip = Heightmap::from_function(3, 2, {}, [](float x, float) { return x * x; });
  const hail::TerrainTriangles t = hail::build_terrain_triangles(strip);
  CHECK(t.size() == 4);
  CHECK(hail::terrain_triangle_count(strip) == 4);
  CHECK(strip.surface_height(1.5f, 0.25f) == Approx(2.5f));  // 1 + 0.5 * (4 - 1), on the (1, 0) half
  CHECK(strip.surface_height(2.0f, 1.0f) == Approx(4.0f));
}

TEST_CASE("Bad params, sizes and heights are InvalidArgument", "[heightmap]") {
  auto flat = [](float, float) { return 0.0f; };
  HeightmapParams p;
  p.cell_x = 0.0f;
  CHECK_THROWS_AS(Heightmap::from_function(4, 4, p, flat), InvalidArgument);
  p = {};
  p.cell_z = -1.0f;
  CHECK_THROWS_AS(Heightmap::from_function(4, 4, p, flat), InvalidArgument);
  p = {};
  p.origin_y = NAN;
  CHECK_THROWS_AS(Heightmap::from_function(4, 4, p, flat), InvalidArgument);
  p = {};
  p.height_scale = INFINITY;
  CHECK_THROWS_AS(Heightmap::from_samples(2, 2, p, {0, 0, 0, 0}), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_function(1, 4, {}, flat), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_function(4, 0, {}, flat), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_function(65537, 2, {}, flat), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_function(65536, 65536, {}, flat), InvalidArgument);  // before allocating
  CHECK_THROWS_AS(Heightmap::from_function(3, 3, {}, [](float x, float) { return x > 1.5f ? NAN : 0.0f; }),
                  InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_samples(2, 2, {}, {0, 0, 0}), InvalidArgument);
}

TEST_CASE("The real DEMs load with their notes' scale, offset and spacing", "[heightmap]") {
  for (const char* name : {"jacksboro_srtm3_403x344", "salish_topobathy_120x91"}) {
    const std::string base = std::string(HAIL_SOURCE_DIR) + "/data/" + name;
    const auto note = read_note(base + ".txt");
    INFO(name);
    REQUIRE(note.count("scale_m") == 1);
    HeightmapParams p;
    p.cell_x = std::stof(note.at("dx_m"));
    p.cell_z = std::stof(note.at("dy_m"));
    p.height_scale = std::stof(note.at("scale_m"));
    p.height_offset = std::stof(note.at("offset_m"));
    const Heightmap h = Heightmap::load_pgm(base + ".pgm", p);
    CHECK(h.cols() == std::stoul(note.at("cols")));
    CHECK(h.rows() == std::stoul(note.at("rows")));
    const float error = std::stof(note.at("max_roundtrip_error_m"));
    CHECK(h.min_height() == Approx(std::stof(note.at("min_height_m"))).margin(error));
    CHECK(h.max_height() == Approx(std::stof(note.at("max_height_m"))).margin(error));
    CHECK(h.extent().max_x == Approx(p.cell_x * float(h.cols() - 1)));
    CHECK(h.extent().max_z == Approx(p.cell_z * float(h.rows() - 1)));
    const hail::TerrainTriangles t = hail::build_terrain_triangles(h);
    CHECK(t.size() == 2 * std::size_t(h.cols() - 1) * (h.rows() - 1));
  }
}

TEST_CASE("PGM, PNG and raw files round-trip", "[heightmap]") {
  const TempDir dir;
  const std::uint32_t cols = 5, rows = 3;
  std::vector<std::uint16_t> wide(cols * rows), narrow(cols * rows);
  for (std::size_t k = 0; k < wide.size(); ++k) {
    wide[k] = static_cast<std::uint16_t>(k * 4099 + 7);  // spans both bytes, up to 57393
    narrow[k] = static_cast<std::uint16_t>(k * 17);
  }
  HeightmapParams p;
  p.height_scale = 0.5f;
  p.height_offset = -3.0f;
  p.origin_y = 1.0f;
  auto check = [&](const Heightmap& h, const std::vector<std::uint16_t>& expect) {
    REQUIRE(h.cols() == cols);
    REQUIRE(h.rows() == rows);
    for (std::uint32_t j = 0; j < rows; ++j)
      for (std::uint32_t i = 0; i < cols; ++i) CHECK(h.h(i, j) == 1.0f + (-3.0f + 0.5f * float(expect[j * cols + i])));
  };
  SECTION("P5 8-bit") { check(Heightmap::load_pgm(dir.write("a.pgm", make_p5(cols, rows, 255, narrow)), p), narrow); }
  SECTION("P5 16-bit big-endian") {
    check(Heightmap::load_pgm(dir.write("b.pgm", make_p5(cols, rows, 65535, wide)), p), wide);
  }
  SECTION("P2 ASCII with comments") {
    std::string text = "P2\n# a comment\n5 # inline comment\n3\n65535\n";
    for (std::size_t k = 0; k < wide.size(); ++k) text += std::to_string(wide[k]) + (k % cols == cols - 1 ? "\n" : " ");
    check(Heightmap::load_pgm(dir.write("c.pgm", text), p), wide);
  }
  SECTION("PNG 8-bit grey") {
    check(Heightmap::load_png(dir.write("d.png", make_png(cols, rows, 8, 0, narrow)), p), narrow);
  }
  SECTION("PNG 16-bit grey") {
    check(Heightmap::load_png(dir.write("e.png", make_png(cols, rows, 16, 0, wide)), p), wide);
  }
  SECTION("raw float32 little-endian") {
    std::vector<unsigned char> bytes;
    for (std::uint16_t v : wide) {
      const float f = float(v);
      std::uint32_t bits;
      std::memcpy(&bits, &f, 4);
      for (int s = 0; s < 32; s += 8) bytes.push_back(static_cast<unsigned char>(bits >> s));
    }
    check(Heightmap::load_raw_f32(dir.write("f.r32", bytes), cols, rows, p), wide);
  }
  SECTION("raw uint16, both byte orders") {
    std::vector<unsigned char> le, be;
    for (std::uint16_t v : wide) {
      le.insert(le.end(), {static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8)});
      be.insert(be.end(), {static_cast<unsigned char>(v >> 8), static_cast<unsigned char>(v)});
    }
    check(Heightmap::load_raw_u16(dir.write("g.r16", le), cols, rows, p), wide);
    check(Heightmap::load_raw_u16(dir.write("h.r16", be), cols, rows, p, false), wide);
  }
}

TEST_CASE("Bad files are refused with FileError naming the file", "[heightmap]") {
  const TempDir dir;
  const std::vector<std::uint16_t> four(16, 9);
  auto pgm = [](const std::string& path) { return [path] { (void)Heightmap::load_pgm(path, {}); }; };
  auto png = [](const std::string& path) { return [path] { (void)Heightmap::load_png(path, {}); }; };
  auto f32 = [](const std::string& path, std::uint32_t c, std::uint32_t r) {
    return [=] { (void)Heightmap::load_raw_f32(path, c, r, {}); };
  };
  auto u16 = [](const std::string& path, std::uint32_t c, std::uint32_t r) {
    return [=] { (void)Heightmap::load_raw_u16(path, c, r, {}); };
  };

  SECTION("missing file") {
    const std::string missing = (dir.path / "no-such-file.pgm").string();
    require_refused<FileError>(missing, pgm(missing));
    require_refused<FileError>(missing, png(missing));
    require_refused<FileError>(missing, f32(missing, 2, 2));
    require_refused<FileError>(missing, u16(missing, 2, 2));
  }
  SECTION("empty file") {
    const std::string empty = dir.write("empty.bin", std::string());
    require_refused<FileError>(empty, pgm(empty));
    require_refused<FileError>(empty, png(empty));
    require_refused<FileError>(empty, f32(empty, 2, 2));
    require_refused<FileError>(empty, u16(empty, 2, 2));
  }
  SECTION("wrong magic") {
    require_refused<FileError>("p6.pgm", pgm(dir.write("p6.pgm", "P6\n2 2\n255\n0123456789ab")));
    require_refused<FileError>("text.pgm", pgm(dir.write("text.pgm", "hello world")));
    const std::string not_png = dir.write("pgm.png", make_p5(4, 4, 255, four));
    require_refused<FileError>(not_png, png(not_png));
  }
  SECTION("truncated data") {
    std::vector<unsigned char> p5 = make_p5(4, 4, 65535, four);
    p5.resize(p5.size() - 3);
    require_refused<FileError>("short16.pgm", pgm(dir.write("short16.pgm", p5)));
    p5 = make_p5(4, 4, 255, four);
    p5.pop_back();
    require_refused<FileError>("short8.pgm", pgm(dir.write("short8.pgm", p5)));
    require_refused<FileError>("short.pgm", pgm(dir.write("short.pgm", "P2 3 3 255 1 2 3 4 5 6 7 8")));
    require_refused<FileError>("header.pgm", pgm(dir.write("header.pgm", "P5 4 4")));
    std::vector<unsigned char> png_bytes = make_png(4, 4, 8, 0, four);
    png_bytes.resize(png_bytes.size() / 2);
    require_refused<FileError>("short.png", png(dir.write("short.png", png_bytes)));
    // An empty IDAT chunk before the data (fuzz-heightmap: stb_image then copied through a null
    // pointer, undefined behaviour under UBSan).
    std::vector<unsigned char> empty_idat;
    put_be32(empty_idat, 0);
    append(empty_idat, {'I', 'D', 'A', 'T'});
    put_be32(empty_idat, crc32(empty_idat.data() + 4, 4));
    png_bytes = make_png(4, 4, 8, 0, four);
    png_bytes.insert(png_bytes.begin() + 33, empty_idat.begin(), empty_idat.end());  // after IHDR (8 + 25 bytes)
    require_refused<FileError>("empty-idat.png", png(dir.write("empty-idat.png", png_bytes)));
    // A deflate block of the reserved type 3: stb_image fails without setting a reason, and the
    // loader appended a null reason to its message (a segfault), or, where an earlier failure on
    // this thread had left one (the truncated PNG above), named that stale reason instead.
    png_bytes = make_png(4, 4, 8, 0, four);
    png_bytes[43] = 0x07;  // the first block's header after IDAT's zlib header: BFINAL 1, BTYPE 3
    const std::uint32_t idat_length = 2 + 5 + 4 * 5 + 4;  // zlib header, stored header, rows, adler32
    std::vector<unsigned char> checked(png_bytes.begin() + 37, png_bytes.begin() + 41 + idat_length);
    png_bytes.erase(png_bytes.begin() + 41 + idat_length, png_bytes.begin() + 45 + idat_length);
    std::vector<unsigned char> crc;
    put_be32(crc, crc32(checked.data(), checked.size()));
    png_bytes.insert(png_bytes.begin() + 41 + idat_length, crc.begin(), crc.end());
    const std::string type3 = dir.write("deflate-type3.png", png_bytes);
    CHECK_THROWS_WITH(png(type3)(),
                      Catch::Contains("deflate-type3.png") && Catch::Contains("stb_image gave no reason"));
    require_refused<FileError>("short.r32", f32(dir.write("short.r32", std::string(15, '\0')), 2, 2));
    require_refused<FileError>("long.r16", u16(dir.write("long.r16", std::string(9, '\0')), 2, 2));
  }
  SECTION("zero or one-vertex sizes") {
    require_refused<FileError>("zero.pgm", pgm(dir.write("zero.pgm", "P5 0 4 255\n")));
    require_refused<FileError>("line.pgm", pgm(dir.write("line.pgm", "P2 1 4 255 1 2 3 4")));
    const std::string raw = dir.write("zero.r16", std::string(8, '\0'));
    require_refused<InvalidArgument>(raw, u16(raw, 0, 4));
  }
  SECTION("maxval 0 or above 65535") {
    require_refused<FileError>("max0.pgm", pgm(dir.write("max0.pgm", "P2 2 2 0 0 0 0 0")));
    require_refused<FileError>("max70k.pgm", pgm(dir.write("max70k.pgm", "P2 2 2 70000 0 0 0 0")));
    require_refused<FileError>("over.pgm", pgm(dir.write("over.pgm", "P2 2 2 10 0 11 0 0")));  // sample > maxval
  }
  SECTION("garbage header and samples") {
    require_refused<FileError>("abc.pgm", pgm(dir.write("abc.pgm", "P5 abc 4 255\n")));
    require_refused<FileError>("neg.pgm", pgm(dir.write("neg.pgm", "P2 -2 2 255 0 0 0 0")));
    require_refused<FileError>("long.pgm", pgm(dir.write("long.pgm", "P5 " + std::string(5000, '9') + " 2 255\n")));
    require_refused<FileError>("x.pgm", pgm(dir.write("x.pgm", "P2 2 2 255 0 1 x 3")));
  }
  SECTION("NaN and infinite raw samples") {
    for (float bad : {NAN, INFINITY, -INFINITY}) {
      std::vector<unsigned char> bytes(16, 0);
      std::memcpy(&bytes[8], &bad, 4);  // x86 and ARM are little-endian, as the format
      require_refused<FileError>("bad.r32", f32(dir.write("bad.r32", bytes), 2, 2));
    }
  }
  SECTION("colour PNG") {
    const std::string rgb = dir.write("rgb.png", make_png(2, 2, 8, 2, std::vector<std::uint16_t>(12, 100)));
    require_refused<FileError>(rgb, png(rgb));
  }
  SECTION("absurd sizes are refused before allocating") {
#if defined(__linux__)
    rusage before{};
    getrusage(RUSAGE_SELF, &before);
#endif
    require_refused<FileError>("huge.pgm", pgm(dir.write("huge.pgm", "P5 65536 65536 65535\n\x01\x02")));
    require_refused<FileError>("wide.pgm", pgm(dir.write("wide.pgm", "P5 4000000000 2 255\n\x01\x02")));
    // Within the limits (2^28 vertices) but the data is missing: refused by the file's length.
    require_refused<FileError>("liar.pgm", pgm(dir.write("liar.pgm", "P5 16384 16384 65535\n\x01\x02")));
    require_refused<FileError>("liar2.pgm", pgm(dir.write("liar2.pgm", "P2 16384 16384 65535\n1 2 3")));
    std::vector<unsigned char> big_png = make_png(2, 2, 8, 0, four);
    // Width 70000 in IHDR: within stb's own limit, beyond hail's 65536 (stb skips the CRC).
    big_png[16] = 0x00, big_png[17] = 0x01, big_png[18] = 0x11, big_png[19] = 0x70;
    require_refused<FileError>("huge.png", png(dir.write("huge.png", big_png)));
    const std::string raw = dir.write("huge.r32", std::string(16, '\0'));
    require_refused<InvalidArgument>(raw, f32(raw, 65536, 65536));
#if defined(__linux__)
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    CHECK(after.ru_maxrss - before.ru_maxrss < 64 * 1024);  // KiB: nothing near a gigabyte was touched
#endif
  }
}

TEST_CASE("The loaders open regular files only", "[heightmap]") {
  const TempDir dir;
  auto all_refuse = [](const std::string& path, const std::string& why) {
    INFO(path);
    const std::vector<std::function<void()>> loads = {
        [&] { (void)Heightmap::load_pgm(path, {}); }, [&] { (void)Heightmap::load_png(path, {}); },
        [&] { (void)Heightmap::load_raw_f32(path, 2, 2, {}); }, [&] { (void)Heightmap::load_raw_u16(path, 2, 2, {}); }};
    for (const auto& load : loads) {
      require_refused<FileError>(path, load);
      CHECK_THROWS_WITH(load(), Catch::Contains(why));
    }
  };
  // A directory read as "empty file" (PGM, PNG) or a 9223372036854775807-byte file (raw).
  all_refuse(dir.path.string(), "is a directory");
  // /dev/null read as "empty file"; /dev/zero would be endless.
  all_refuse("/dev/null", "is a device");
#if defined(__linux__)
  // A FIFO blocked the open forever (no writer ever comes): with the check missing this test hangs.
  const std::string fifo = (dir.path / "pipe.pgm").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  all_refuse(fifo, "is a FIFO");
#endif
  // A symbolic link to a regular file is that file.
  const std::string target = dir.write("real.pgm", "P2 2 2 255 1 2 3 4");
  const fs::path link = dir.path / "link.pgm";
  fs::create_symlink(target, link);
  CHECK(Heightmap::load_pgm(link.string(), {}).max_height() == 4.0f);
}

TEST_CASE("PGM: data after the raster is refused; whitespace and a next image are not", "[heightmap]") {
  const TempDir dir;
  const std::vector<std::uint16_t> samples = {1, 2, 3, 4};
  auto pgm = [](const std::string& path) { return [path] { (void)Heightmap::load_pgm(path, {}); }; };

  // Loaded silently before: a header whose size is too small leaves raster behind.
  std::vector<unsigned char> garbage = make_p5(2, 2, 255, samples);
  append(garbage, std::vector<unsigned char>(1000, 'x'));
  const std::string garbage_path = dir.write("garbage.pgm", garbage);
  require_refused<FileError>(garbage_path, pgm(garbage_path));
  CHECK_THROWS_WITH(pgm(garbage_path)(), Catch::Contains("1000 bytes follow the raster"));
  std::vector<unsigned char> binary_zeros = make_p5(2, 2, 255, samples);
  append(binary_zeros, {0, 0});
  require_refused<FileError>("zeros.pgm", pgm(dir.write("zeros.pgm", binary_zeros)));
  require_refused<FileError>("extra.pgm", pgm(dir.write("extra.pgm", "P2 2 2 255 1 2 3 4 5")));
  require_refused<FileError>("p5x.pgm", pgm(dir.write("p5x.pgm", "P2 2 2 255 1 2 3 4 P5x")));

  // Tolerated: trailing whitespace, comments after an ASCII raster, and a next image.
  std::vector<unsigned char> spaces = make_p5(2, 2, 255, samples);
  append(spaces, bytes_of("\n \t\r\n"));
  CHECK(Heightmap::load_pgm(dir.write("spaces.pgm", spaces), {}).max_height() == 4.0f);
  CHECK(Heightmap::load_pgm(dir.write("comment.pgm", "P2 2 2 255 1 2 3 4\n# the end\n"), {}).max_height() == 4.0f);
  std::vector<unsigned char> two_images = make_p5(2, 2, 255, samples);
  append(two_images, make_p5(3, 3, 255, std::vector<std::uint16_t>(9, 200)));
  CHECK(Heightmap::load_pgm(dir.write("two.pgm", two_images), {}).max_height() == 4.0f);
}

TEST_CASE("PNG: data after IEND, and compressed data too short for its header, are refused", "[heightmap]") {
  const TempDir dir;
  const std::vector<std::uint16_t> four(16, 9);
  auto png = [](const std::string& path) { return [path] { (void)Heightmap::load_png(path, {}); }; };
  std::vector<unsigned char> after_end = make_png(4, 4, 8, 0, four);
  append(after_end, bytes_of("trailing junk"));
  const std::string after_end_path = dir.write("after-end.png", after_end);
  require_refused<FileError>(after_end_path, png(after_end_path));
  CHECK_THROWS_WITH(png(after_end_path)(), Catch::Contains("13 bytes follow the PNG's IEND chunk"));

#if defined(__linux__)
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
#endif
  // Within the 2^28-vertex limit, but a few dozen bytes cannot inflate to 16,384^2 samples:
  // this took 1 GB (the float samples, then stb's image) before stb found the data missing.
  std::vector<unsigned char> liar = make_png(2, 2, 8, 0, four);
  liar[16] = 0x00, liar[17] = 0x00, liar[18] = 0x40, liar[19] = 0x00;  // width 16384 (stb skips the CRC)
  liar[20] = 0x00, liar[21] = 0x00, liar[22] = 0x40, liar[23] = 0x00;  // height 16384
  const std::string liar_path = dir.write("liar.png", liar);
  require_refused<FileError>(liar_path, png(liar_path));
  CHECK_THROWS_WITH(png(liar_path)(), Catch::Contains("cannot hold the 16384 x 16384 image"));
#if defined(__linux__)
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  CHECK(after.ru_maxrss - before.ru_maxrss < 64 * 1024);  // KiB
#endif
  // A chunk longer than the file.
  std::vector<unsigned char> long_chunk = make_png(4, 4, 8, 0, four);
  long_chunk[33 + 0] = 0x7f;  // IDAT's length, just after IHDR's 25 bytes
  require_refused<FileError>("long-chunk.png", png(dir.write("long-chunk.png", long_chunk)));
}

TEST_CASE("HeightmapParams::max_vertices bounds every factory before allocating", "[heightmap]") {
  const TempDir dir;
  const std::vector<std::uint16_t> sixteen(16, 7);
  HeightmapParams fifteen;
  fifteen.max_vertices = 15;
  HeightmapParams exactly;
  exactly.max_vertices = 16;
  // A file's header over the caller's limit: SizeLimitError, a FileError naming the file.
  const std::string pgm = dir.write("four.pgm", make_p5(4, 4, 255, sixteen));
  require_refused<hail::SizeLimitError>(pgm, [&] { (void)Heightmap::load_pgm(pgm, fifteen); });
  CHECK_THROWS_WITH(Heightmap::load_pgm(pgm, fifteen),
                    Catch::Contains("4 x 4 = 16 vertices exceeds HeightmapParams::max_vertices = 15"));
  CHECK(Heightmap::load_pgm(pgm, exactly).cols() == 4);
  const std::string png = dir.write("four.png", make_png(4, 4, 8, 0, sixteen));
  require_refused<hail::SizeLimitError>(png, [&] { (void)Heightmap::load_png(png, fifteen); });
  CHECK(Heightmap::load_png(png, exactly).rows() == 4);
  // A size the caller gives: InvalidArgument.
  const std::string raw = dir.write("four.r16", std::string(32, '\0'));
  CHECK_THROWS_AS(Heightmap::load_raw_u16(raw, 4, 4, fifteen), InvalidArgument);
  CHECK(Heightmap::load_raw_u16(raw, 4, 4, exactly).cols() == 4);
  CHECK_THROWS_AS(Heightmap::from_function(4, 4, fifteen, [](float, float) { return 0.0f; }), InvalidArgument);
  CHECK_THROWS_AS(Heightmap::from_samples(4, 4, fifteen, std::vector<float>(16, 0.0f)), InvalidArgument);
  // The limit itself must make sense.
  HeightmapParams bad;
  bad.max_vertices = 3;
  CHECK_THROWS_AS(hail::check_heightmap_params(bad), InvalidArgument);
  bad.max_vertices = hail::kMaxHeightmapVertices + 1;
  CHECK_THROWS_AS(hail::check_heightmap_params(bad), InvalidArgument);
}

TEST_CASE("Terrain triangles follow the documented layout", "[heightmap]") {
  HeightmapParams p;
  p.cell_x = 1.5f;
  p.cell_z = 0.75f;
  p.origin_x = -2.0f;
  p.origin_z = 4.0f;
  const Heightmap h =
      Heightmap::from_function(6, 4, p, [](float x, float z) { return std::sin(x) * 2.0f + 0.3f * z * z; });
  const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
  REQUIRE(s.size() == 2 * 5 * 3);
  for (std::size_t t = 0; t < s.size(); ++t) {
    INFO("triangle " << t);
    const auto corners = layout_corners(h, t);
    const float v[3][3] = {
        {s.v0x[t], s.v0y[t], s.v0z[t]}, {s.v1x[t], s.v1y[t], s.v1z[t]}, {s.v2x[t], s.v2y[t], s.v2z[t]}};
    for (int k = 0; k < 3; ++k) {
      const hail::Vec3 expect = h.vertex(corners[k][0], corners[k][1]);
      for (int c = 0; c < 3; ++c) CHECK(v[k][c] == expect[c]);
    }
    // The diagonal: edge 1 of the even triangle and edge 0 of the odd one join (i+1, j) and (i, j+1).
    const int diagonal = t % 2 == 0 ? 1 : 0;
    const auto a = corners[diagonal], b = corners[(diagonal + 1) % 3];
    CHECK(((a[0] == b[0] + 1 && a[1] + 1 == b[1]) || (b[0] == a[0] + 1 && b[1] + 1 == a[1])));
    const float e[3][3] = {
        {s.e0x[t], s.e0y[t], s.e0z[t]}, {s.e1x[t], s.e1y[t], s.e1z[t]}, {s.e2x[t], s.e2y[t], s.e2z[t]}};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) CHECK(e[k][c] == v[(k + 1) % 3][c] - v[k][c]);
    const float n[3] = {s.nx[t], s.ny[t], s.nz[t]};
    CHECK(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) == Approx(1.0f).margin(1e-6));
    CHECK(n[1] > 0.0f);
    for (int k = 0; k < 3; ++k) CHECK(n[0] * v[k][0] + n[1] * v[k][1] + n[2] * v[k][2] == Approx(s.d[t]).margin(1e-4));
    float lo[3], hi[3];
    hail::terrain_triangle_bounds(s, t, lo, hi);
    for (int c = 0; c < 3; ++c) {
      CHECK(lo[c] == std::min({v[0][c], v[1][c], v[2][c]}));
      CHECK(hi[c] == std::max({v[0][c], v[1][c], v[2][c]}));
    }
  }
}

TEST_CASE("surface_height lies on the plane of the triangle under (x, z)", "[heightmap]") {
  HeightmapParams p;
  p.cell_x = 2.0f;
  p.cell_z = 0.5f;
  p.origin_x = 3.0f;
  p.origin_z = -1.0f;
  const Heightmap h = Heightmap::from_function(
      7, 9, p, [](float x, float z) { return std::sin(0.7f * x) * 3.0f + std::cos(2.0f * z); });
  const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
  for (int a = 0; a <= 60; ++a)
    for (int b = 0; b <= 40; ++b) {
      const float x = 3.0f + 12.0f * float(a) / 60.0f, z = -1.0f + 4.0f * float(b) / 40.0f;
      const float u = (x - 3.0f) / 2.0f, w = (z + 1.0f) / 0.5f;
      const std::uint32_t i = std::min<std::uint32_t>(std::uint32_t(u), 5),
                          j = std::min<std::uint32_t>(std::uint32_t(w), 7);
      const std::size_t t = 2 * (j * 6 + i) + ((u - float(i)) + (w - float(j)) > 1.0f ? 1 : 0);
      const float plane = (s.d[t] - s.nx[t] * x - s.nz[t] * z) / s.ny[t];
      INFO("x " << x << " z " << z);
      CHECK(h.surface_height(x, z) == Approx(plane).margin(1e-4));
    }
  CHECK(h.surface_height(3.0f, -1.0f) == h.h(0, 0));
  CHECK(h.surface_height(15.0f, 3.0f) == Approx(h.h(6, 8)));
  CHECK(std::isnan(h.surface_height(2.99f, 0.0f)));
  CHECK(std::isnan(h.surface_height(5.0f, 3.01f)));
  CHECK(std::isnan(h.surface_height(NAN, 0.0f)));
}

TEST_CASE("Internal edges: flat and gentle folds are internal, boundaries and ridges active", "[heightmap]") {
  SECTION("flat map: every shared edge internal, every boundary edge active") {
    const Heightmap h = Heightmap::from_function(5, 4, {}, [](float, float) { return 2.0f; });
    const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
    for (std::size_t t = 0; t < s.size(); ++t)
      for (int e = 0; e < 3; ++e) {
        INFO("triangle " << t << " edge " << e);
        CHECK(internal(s, t, e) == !on_boundary(h, t, e));
      }
    CHECK(s.internal_edges[0] == hail::kEdge1Internal);  // corner triangle: only its diagonal is shared
  }
  // A tent along z: heights rise 3 m per m towards x = 2 (column i = 2), then fall.
  auto fold_edge = [](const Heightmap& h, std::size_t t, int e) {
    const auto c = layout_corners(h, t);
    return c[e][0] == 2 && c[(e + 1) % 3][0] == 2;  // both ends on the column x = 2
  };
  SECTION("sharp convex ridge: its edges are active, the planar slopes' edges internal") {
    const Heightmap h =
        Heightmap::from_function(5, 4, {}, [](float x, float) { return 10.0f - 3.0f * std::fabs(x - 2.0f); });
    const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
    int ridge_edges = 0;
    for (std::size_t t = 0; t < s.size(); ++t)
      for (int e = 0; e < 3; ++e) {
        INFO("triangle " << t << " edge " << e);
        if (on_boundary(h, t, e)) {
          CHECK_FALSE(internal(s, t, e));
        } else if (fold_edge(h, t, e)) {
          CHECK_FALSE(internal(s, t, e));
          ++ridge_edges;
        } else {
          CHECK(internal(s, t, e));
        }
      }
    CHECK(ridge_edges == 2 * 3);  // three cells along z, seen from both sides
  }
  SECTION("sharp concave valley: internal (as Jolt), the neighbour face stops the sphere") {
    const Heightmap h = Heightmap::from_function(5, 4, {}, [](float x, float) { return 3.0f * std::fabs(x - 2.0f); });
    const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
    for (std::size_t t = 0; t < s.size(); ++t)
      for (int e = 0; e < 3; ++e)
        if (fold_edge(h, t, e)) CHECK(internal(s, t, e));
  }
  SECTION("convex folds: 4 degrees internal, 6 degrees active") {
    for (const auto& [degrees, expect_internal] : {std::pair{4.0, true}, std::pair{6.0, false}}) {
      const float slope = static_cast<float>(std::tan(degrees * 3.14159265358979 / 180.0));
      const Heightmap h =
          Heightmap::from_function(5, 3, {}, [slope](float x, float) { return x > 2.0f ? -slope * (x - 2.0f) : 0.0f; });
      const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
      for (std::size_t t = 0; t < s.size(); ++t)
        for (int e = 0; e < 3; ++e)
          if (fold_edge(h, t, e)) {
            INFO(degrees << " degrees, triangle " << t << " edge " << e);
            CHECK(internal(s, t, e) == expect_internal);
          }
    }
  }
}

TEST_CASE("Terrain triangles can be reordered (e.g. into BVH order)", "[heightmap]") {
  const Heightmap h = Heightmap::from_function(3, 3, {}, [](float x, float z) { return x * z; });
  const hail::TerrainTriangles s = hail::build_terrain_triangles(h);
  const std::vector<std::uint32_t> order = {7, 0, 3, 3};
  const hail::TerrainTriangles r = hail::reorder_terrain_triangles(s, order);
  REQUIRE(r.size() == 4);
  for (std::size_t k = 0; k < order.size(); ++k) {
    CHECK(r.v2z[k] == s.v2z[order[k]]);
    CHECK(r.e1y[k] == s.e1y[order[k]]);
    CHECK(r.d[k] == s.d[order[k]]);
    CHECK(r.internal_edges[k] == s.internal_edges[order[k]]);
  }
  const std::vector<std::uint32_t> bad = {8};
  CHECK_THROWS_AS(hail::reorder_terrain_triangles(s, bad), InvalidArgument);
}
