// Triangle meshes: the file loaders and their errors, what is closed, and spheres against static
// meshes (docs/meshes.md): no ghost bumps on a tessellated floor, resting in concave corners,
// thin walls at 100 m/s, bounces at their time, events and determinism.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "catch.h"
#include "hail/errors.h"
#include "hail/triangle_mesh.h"
#include "hail/world.h"
#include "scenes/mesh_shapes.h"

using hail::ContactWith;
using hail::MeshTransform;
using hail::SphereDesc;
using hail::SphereId;
using hail::TriangleMesh;
using hail::Vec3;
using hail::World;
using hail::WorldSettings;
using hail::bench::box_mesh;

namespace {

namespace fs = std::filesystem;

/// A file of `content` in a fresh temporary folder, removed with the object.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& content) {
    // The process id and a serial number: unique among concurrent test processes, no clock read.
    static int serial = 0;
    dir_ = fs::temp_directory_path() / ("hail-test-mesh-" + std::to_string(::getpid()) + "-" + std::to_string(serial++));
    fs::create_directories(dir_);
    path_ = (dir_ / name).string();
    std::ofstream(path_, std::ios::binary) << content;
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  fs::path dir_;
  std::string path_;
};

/// The FileError message of `load(path)`, or "" if it loaded.
template <class Load>
std::string load_error(Load&& load) {
  try {
    (void)load();
  } catch (const hail::FileError& e) {
    return e.what();
  }
  return {};
}

/// A flat floor at y = 0 over [-half, half]^2 split into cells x cells quads of two triangles
/// each, facing up: open, so a shell.
TriangleMesh floor_mesh(float half, int cells) {
  std::vector<Vec3> v;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) v.emplace_back(-half + 2 * half * i / cells, 0.0f, -half + 2 * half * j / cells);
  std::vector<std::uint32_t> idx;
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i)
      idx.insert(idx.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
  return TriangleMesh(std::move(v), std::move(idx));
}

/// A square quad (two triangles) through `centre`, spanned by `u` and `w` (half sides).
TriangleMesh quad_mesh(const Vec3& centre, const Vec3& u, const Vec3& w) {
  return TriangleMesh({centre - u - w, centre + u - w, centre + u + w, centre - u + w}, {0, 1, 2, 0, 2, 3});
}

WorldSettings one_thread() {
  WorldSettings s;
  s.threads = 1;
  return s;
}

}  // namespace

TEST_CASE("TriangleMesh checks its vertices and indices", "[mesh]") {
  const std::vector<Vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  CHECK_NOTHROW(TriangleMesh(tri, {0, 1, 2}));
  CHECK_THROWS_AS(TriangleMesh(tri, {}), hail::InvalidArgument);
  CHECK_THROWS_AS(TriangleMesh(tri, {0, 1}), hail::InvalidArgument);
  CHECK_THROWS_WITH(TriangleMesh(tri, {0, 1, 3}),
                    Catch::Matchers::Contains("index 2") && Catch::Matchers::Contains("not below the vertex count 3"));
  CHECK_THROWS_AS(TriangleMesh({{0, 0, 0}, {1, NAN, 0}, {0, 0, 1}}, {0, 1, 2}), hail::InvalidArgument);
}

TEST_CASE("A box is closed; a quad, a box missing a face or wound inconsistently is not", "[mesh]") {
  const TriangleMesh box = box_mesh({0, 0, 0}, {1, 2, 3});
  CHECK(box.closed());
  std::vector<std::uint32_t> open(box.indices().begin(), box.indices().end() - 6);
  CHECK_FALSE(TriangleMesh(box.vertices(), open).closed());
  std::vector<std::uint32_t> flipped = box.indices();
  std::swap(flipped[1], flipped[2]);  // one triangle wound the other way
  CHECK_FALSE(TriangleMesh(box.vertices(), flipped).closed());
  CHECK_FALSE(floor_mesh(1, 2).closed());
  // The same box with every triangle's corners apart (a soup) is still closed: equal positions weld.
  std::vector<Vec3> soup;
  std::vector<std::uint32_t> soup_idx;
  for (std::uint32_t k : box.indices()) {
    soup_idx.push_back(static_cast<std::uint32_t>(soup.size()));
    soup.push_back(box.vertices()[k]);
  }
  CHECK(TriangleMesh(soup, soup_idx).closed());
}

TEST_CASE("MeshTransform scales, turns about its axis, then moves", "[mesh]") {
  const MeshTransform t{.position = {10, 0, 0}, .axis = {0, 2, 0}, .degrees = 90, .scale = 2};
  const Vec3 p = t.apply({1, 0, 0});  // scaled to (2, 0, 0), turned to (0, 0, -2), moved
  CHECK(p.x() == Approx(10).margin(1e-6));
  CHECK(p.z() == Approx(-2).margin(1e-6));
  CHECK_THROWS_AS((MeshTransform{.scale = 0}.validate()), hail::InvalidArgument);
  CHECK_THROWS_AS((MeshTransform{.axis = {0, 0, 0}, .degrees = 5}.validate()), hail::InvalidArgument);
  CHECK_NOTHROW((MeshTransform{.axis = {0, 0, 0}}.validate()));
}

TEST_CASE("OBJ files load faces of any size and report what is wrong by line", "[mesh]") {
  const TempFile cube("cube.obj",
                      "# a unit cube\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                      "vn 0 0 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2/1 3/1/1 7//1 6\n");
  const TriangleMesh m = TriangleMesh::load(cube.path());
  CHECK(m.triangle_count() == 12);
  CHECK(m.vertices().size() == 8);
  CHECK(m.closed());
  const TempFile relative("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf -3 -2 -1\n");
  CHECK(TriangleMesh::load_obj(relative.path()).triangle_count() == 1);

  const TempFile bad_index("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\n\nf 1 2 4\n");
  CHECK_THAT(load_error([&] { return TriangleMesh::load(bad_index.path()); }),
             Catch::Matchers::Contains("bad.obj:5") && Catch::Matchers::Contains("face index 4 names no vertex"));
  const TempFile bad_number("num.obj", "v 0 0 0\nv 1 zero 0\n");
  CHECK_THAT(load_error([&] { return TriangleMesh::load(bad_number.path()); }),
             Catch::Matchers::Contains("num.obj:2") && Catch::Matchers::Contains("'zero' is not a number"));
  const TempFile no_faces("empty.obj", "v 0 0 0\n");
  CHECK_THAT(load_error([&] { return TriangleMesh::load(no_faces.path()); }),
             Catch::Matchers::Contains("no triangles"));
  CHECK_THAT(load_error([&] { return TriangleMesh::load("/nonexistent/hail.obj"); }),
             Catch::Matchers::Contains("/nonexistent/hail.obj"));
  const TempFile wrong_type("mesh.ply", "ply\n");
  CHECK_THAT(load_error([&] { return TriangleMesh::load(wrong_type.path()); }),
             Catch::Matchers::Contains("unknown mesh file type '.ply'"));
}

TEST_CASE("STL files load, ASCII and binary, with shared corners welded", "[mesh]") {
  // A tetrahedron wound outwards.
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string ascii = "solid tet\n";
  std::string binary(80, ' ');
  const std::uint32_t count = 4;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : faces) {
    ascii += "  facet normal 0 0 0\n    outer loop\n";
    const float normal[3] = {0, 0, 0};
    binary.append(reinterpret_cast<const char*>(normal), 12);
    for (int c : f) {
      ascii += "      vertex " + std::to_string(v[c][0]) + " " + std::to_string(v[c][1]) + " " +
               std::to_string(v[c][2]) + "\n";
      binary.append(reinterpret_cast<const char*>(v[c]), 12);
    }
    ascii += "    endloop\n  endfacet\n";
    binary.append(2, '\0');
  }
  ascii += "endsolid tet\n";
  const TempFile text("tet.stl", ascii), bytes("tet_binary.STL", binary);
  for (const TriangleMesh& m : {TriangleMesh::load(text.path()), TriangleMesh::load(bytes.path())}) {
    CHECK(m.triangle_count() == 4);
    CHECK(m.vertices().size() == 4);
    CHECK(m.closed());
  }
  const TempFile truncated("cut.stl", binary.substr(0, binary.size() - 7));
  CHECK_THAT(load_error([&] { return TriangleMesh::load(truncated.path()); }),
             Catch::Matchers::Contains("neither binary STL"));
  const TempFile unfinished("open.stl", ascii.substr(0, ascii.find("endsolid")));
  CHECK_THAT(load_error([&] { return TriangleMesh::load(unfinished.path()); }),
             Catch::Matchers::Contains("no 'endsolid'"));
  const TempFile two_corners("two.stl",
                             "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"
                             "endfacet\nendsolid x\n");
  CHECK_THAT(load_error([&] { return TriangleMesh::load(two_corners.path()); }),
             Catch::Matchers::Contains("two.stl:6") && Catch::Matchers::Contains("2 vertices"));
}

TEST_CASE("add_mesh refuses a bad transform, material or a mesh of zero area, the world unchanged", "[mesh]") {
  World world(one_thread());
  const TriangleMesh floor = floor_mesh(1, 1);
  CHECK_THROWS_AS(world.add_mesh(floor, {}, 1.5f, 0.5f), hail::InvalidArgument);
  CHECK_THROWS_AS(world.add_mesh(floor, {.scale = -1}), hail::InvalidArgument);
  CHECK_THROWS_AS(world.add_mesh(TriangleMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0, 1, 2})), hail::InvalidArgument);
  CHECK(world.mesh_count() == 0);
  CHECK(world.add_mesh(floor) == 0);
  CHECK(world.add_mesh(floor, {.position = {0, 1, 0}}) == 1);
  CHECK(world.mesh_count() == 2);
  CHECK(world.mesh_memory_bytes() > 0);
}

TEST_CASE("shift_origin moves meshes by whole metres exactly, and the spheres on them go on", "[mesh][shift_origin]") {
  World world(one_thread());
  world.add_mesh(box_mesh({-8, -1, -8}, {8, 0, 8}), {.position = {4096, 0, -2048}});
  const SphereId id = world.add_sphere({.position = {4096.3f, 0.5f, -2047.8f}, .velocity = {1, 0, 0}, .radius = 0.5f});
  for (int k = 0; k < 30; ++k) world.step(1.0f / 60);
  std::vector<hail::TerrainTriangle> before, after;
  world.mesh_triangles(before);
  const Vec3 p = world.position(id);
  world.shift_origin({4096, 0, -2048});
  world.mesh_triangles(after);
  REQUIRE(after.size() == before.size());
  for (std::size_t k = 0; k < after.size(); ++k) {  // the same BVH order here, so entry by entry
    CHECK(after[k].a == before[k].a - Vec3(4096, 0, -2048));
    CHECK(after[k].c == before[k].c - Vec3(4096, 0, -2048));
  }
  CHECK(world.position(id) == p - Vec3(4096, 0, -2048));
  for (int k = 0; k < 60; ++k) world.step(1.0f / 60);
  CHECK(world.position(id).y() == Approx(0.5f).margin(0.005f));  // still on the floor, at home
  CHECK(world.position(id).x() > 1.0f);                          // and still rolling
}

TEST_CASE("A sphere rolls across a floor of many triangles without a bump", "[mesh]") {
  // 32 x 32 quads of 0.25 m: the sphere crosses about 40 internal edges and diagonals. With
  // edge normals there it would hop at each (the terrain's ghost bumps).
  World world(one_thread());
  world.add_mesh(floor_mesh(4, 32), {}, 0.0f, 0.5f);
  const float r = 0.3f, v = 3.0f;
  const SphereId id = world.add_sphere({.position = {-3.3f, r, 0.1f},
                                        .velocity = {v, 0, 0.4f},
                                        .angular_velocity = {0.4f / r, 0, -v / r},  // rolling already
                                        .radius = r,
                                        .mass = 1,
                                        .restitution = 0,
                                        .friction = 0.5f});
  float highest = 0.0f, lowest = 1.0f;
  for (int k = 0; k < 120; ++k) {  // 2 s: 6 m
    world.step(1.0f / 60);
    highest = std::max(highest, world.position(id).y() - r);
    lowest = std::min(lowest, world.position(id).y() - r);
  }
  CHECK(world.position(id).x() > 2.5f);
  CHECK(highest < 1e-4f);
  CHECK(lowest > -0.01f * r);
  CHECK(world.velocity(id).x() == Approx(v).epsilon(1e-3));
}

TEST_CASE("A sphere rests in concave corners of two and three faces", "[mesh]") {
  for (const bool three : {false, true}) {
    WorldSettings settings = one_thread();
    settings.gravity = {-2.0f, -9.81f, three ? -2.0f : 0.0f};  // pressed into the corner
    World world(settings);
    const float r = 0.5f;
    world.add_mesh(quad_mesh({2, 0, 2}, {2, 0, 0}, {0, 0, 2}));             // floor y = 0
    world.add_mesh(quad_mesh({0, 2, 2}, {0, 2, 0}, {0, 0, 2}));             // wall x = 0
    if (three) world.add_mesh(quad_mesh({2, 2, 0}, {2, 0, 0}, {0, 2, 0}));  // wall z = 0
    const Vec3 start{r, r, three ? r : 2.0f};
    const SphereId id = world.add_sphere({.position = start, .radius = r, .mass = 1, .friction = 0.5f});
    for (int k = 0; k < 180; ++k) world.step(1.0f / 60);
    INFO("three faces: " << three);
    CHECK((world.position(id) - start).norm() < 0.01f * r);
    CHECK(world.velocity(id).norm() < 1e-3f);
    CHECK(world.mesh_penetration(world.position(id), r) < 0.01f * r);
  }
}

TEST_CASE("A sphere at 100 m/s does not pass through a 1 mm wall, closed or a shell", "[mesh]") {
  for (const bool closed : {true, false}) {
    WorldSettings settings = one_thread();
    settings.gravity = {0, 0, 0};
    World world(settings);
    if (closed)
      world.add_mesh(box_mesh({-0.0005f, -2, -2}, {0.0005f, 2, 2}), {}, 0.5f, 0.0f);
    else
      world.add_mesh(quad_mesh({0, 0, 0}, {0, 2, 0}, {0, 0, 2}), {}, 0.5f, 0.0f);
    const SphereId id = world.add_sphere(
        {.position = {-1.0f, 0.3f, 0.2f}, .velocity = {100, 0, 0}, .radius = 0.05f, .mass = 1, .restitution = 0.5f});
    float furthest = -1.0f;
    for (int k = 0; k < 10; ++k) {
      world.step(1.0f / 60);  // 1.7 m a step: the wall is crossed within one step
      furthest = std::max(furthest, world.position(id).x());
    }
    INFO("closed: " << closed);
    CHECK(furthest < 0.0f);
    CHECK(world.velocity(id).x() == Approx(-50.0f).epsilon(1e-3));  // e = 0.5
  }
}

TEST_CASE("A bounce on a mesh floor peaks as on a plane", "[mesh]") {
  // Case A of docs/scenes.md (dropped from 10 m, e = 0.8) on a closed box's top face: the
  // speculative contact is bounced at its time (kernel/solver/bounce_timing.h), as on terrain.
  World world(one_thread());
  world.add_mesh(box_mesh({-16, -1, -16}, {16, 0, 16}), {}, 0.8f, 0.0f);
  const SphereId id = world.add_sphere(
      {.position = {0.3f, 10.5f, 0.2f}, .radius = 0.5f, .mass = 1, .restitution = 0.8f, .friction = 0});
  double highest = -1.0, apex = -1.0;
  for (int k = 0; k < 600 && apex < 0; ++k) {
    world.step(1.0f / 60);
    const double vy = world.velocity(id).y(), y = world.position(id).y() - 0.5;
    if (vy > 0) highest = std::max(highest, y);
    if (vy <= 0 && highest >= 0) apex = std::max(highest, y);
  }
  // e^2 h = 6.4 m; sampling misses the top by at most g (dt / 2)^2 / 2 = 0.3 mm.
  CHECK(apex == Approx(6.4).epsilon(0.005));
}

TEST_CASE("Hits and touches on a mesh name the mesh", "[mesh]") {
  World world(one_thread());
  world.set_events({.touch = true, .hits = true, .hit_speed = 1.0f});
  world.add_mesh(floor_mesh(2, 2), {.position = {0, 5, 0}});
  world.add_mesh(floor_mesh(2, 2));
  const SphereId id = world.add_sphere({.position = {0.1f, 2, 0.1f}, .radius = 0.5f, .mass = 1, .restitution = 0.0f});
  bool hit = false, touched = false;
  for (int k = 0; k < 60; ++k) {
    world.step(1.0f / 60);
    for (const hail::HitEvent& h : world.hit_events())
      if (h.a == id && h.with == ContactWith::Mesh && h.surface == 1) hit = true;
    for (const hail::TouchEvent& t : world.touch_begin_events())
      if (t.a == id && t.with == ContactWith::Mesh && t.surface == 1) touched = true;
  }
  CHECK(hit);
  CHECK(touched);
}

TEST_CASE("Spheres in a mesh funnel step to the same state on any thread count", "[mesh][threads]") {
  // An open eight-sided funnel (a shell) over a closed box floor: rain of 400 spheres.
  std::vector<Vec3> v;
  std::vector<std::uint32_t> idx;
  const int sides = 8;
  for (int k = 0; k < sides; ++k) {
    const float a = 6.2831853f * k / sides;
    v.emplace_back(1.0f * std::cos(a), 1.0f, 1.0f * std::sin(a));
    v.emplace_back(4.0f * std::cos(a), 5.0f, 4.0f * std::sin(a));
  }
  for (std::uint32_t k = 0; k < sides; ++k) {
    const std::uint32_t n = (k + 1) % sides;
    idx.insert(idx.end(), {2 * k, 2 * n, 2 * n + 1, 2 * k, 2 * n + 1, 2 * k + 1});
  }
  const TriangleMesh funnel(v, idx);
  std::uint64_t hashes[2] = {0, 0};
  for (int threads = 1; threads <= 2; ++threads) {
    WorldSettings settings;
    settings.threads = threads;
    World world(settings);
    world.add_mesh(funnel);
    world.add_mesh(box_mesh({-30, -1, -30}, {30, 0, 30}));  // wide enough that none rolls off in 4 s
    std::vector<SphereId> ids;
    for (int k = 0; k < 400; ++k)
      ids.push_back(world.add_sphere(
          {.position = {-2.5f + 0.5f * (k % 10), 6.0f + 0.5f * (k / 100), -2.5f + 0.5f * ((k / 10) % 10)},
           .radius = 0.2f,
           .mass = 1}));
    for (int k = 0; k < 240; ++k) world.step(1.0f / 60);
    hashes[threads - 1] = world.state_hash();
    // None fell through the funnel's walls or the floor.
    for (const SphereId id : ids) CHECK(world.position(id).y() > -0.01f);
  }
  CHECK(hashes[0] == hashes[1]);
}

TEST_CASE("Rays and swept spheres meet meshes from either side of a shell", "[mesh][queries]") {
  World world(one_thread());
  world.add_mesh(floor_mesh(4, 4), {.position = {0, 1, 0}});  // mesh 0: a shell at y = 1
  world.add_mesh(floor_mesh(4, 4), {.position = {0, 3, 0}});  // mesh 1: a shell at y = 3
  const auto down = world.raycast({.origin = {0.3f, 5, 0.2f}, .direction = {0, -2, 0}});
  REQUIRE(down);
  CHECK(down->kind == hail::QueryHitKind::Mesh);
  CHECK(down->index == 1);
  CHECK(down->distance == Approx(2.0f));
  CHECK(down->normal.y() == Approx(1.0f));
  const auto up = world.raycast({.origin = {0.3f, 0, 0.2f}, .direction = {0, 1, 0}});
  REQUIRE(up);
  CHECK(up->index == 0);
  CHECK(up->normal.y() == Approx(-1.0f));  // the face the ray came from
  const std::vector<hail::QueryHit> all = world.raycast_all({.origin = {0.3f, 5, 0.2f}, .direction = {0, -1, 0}});
  REQUIRE(all.size() == 2);
  CHECK(all[0].index == 1);
  CHECK(all[1].index == 0);
  CHECK(all[1].distance == Approx(4.0f));
  hail::QueryFilter no_meshes;
  no_meshes.meshes = false;
  CHECK_FALSE(world.raycast({.origin = {0.3f, 5, 0.2f}, .direction = {0, -1, 0}}, no_meshes));
  const auto cast = world.sphere_cast({.origin = {0.3f, 2, 0.2f}, .direction = {0, -1, 0}}, 0.5f);
  REQUIRE(cast);
  CHECK(cast->index == 0);
  CHECK(cast->distance == Approx(0.5f));
  CHECK(cast->point.y() == Approx(1.0f));
  const auto cast_up = world.sphere_cast({.origin = {0.3f, 2, 0.2f}, .direction = {0, 1, 0}}, 0.5f);
  REQUIRE(cast_up);
  CHECK(cast_up->index == 1);
  CHECK(cast_up->distance == Approx(0.5f));
  CHECK(cast_up->normal.y() == Approx(-1.0f));
}

TEST_CASE("mesh_triangles gives every mesh's triangles where they are placed", "[mesh]") {
  World world(one_thread());
  world.add_mesh(floor_mesh(1, 2), {.position = {0, 2, 0}});  // 8 triangles
  world.add_mesh(box_mesh({0, 0, 0}, {1, 1, 1}));             // 12
  std::vector<hail::TerrainTriangle> triangles;
  world.mesh_triangles(triangles);
  REQUIRE(triangles.size() == 20);
  for (std::size_t k = 0; k < 8; ++k) {
    CHECK(triangles[k].a.y() == 2.0f);
    CHECK(std::abs(triangles[k].normal.y()) == 1.0f);
  }
  // Query hits name the same entries.
  const auto hit = world.raycast({.origin = {0.5f, 1.5f, 0.5f}, .direction = {0, -1, 0}});
  REQUIRE(hit);
  CHECK(hit->index == 1);
  const hail::TerrainTriangle& t = triangles[hit->triangle];
  CHECK(std::max({t.a.y(), t.b.y(), t.c.y()}) == 1.0f);
  CHECK(t.normal.y() == 1.0f);
}

TEST_CASE("A snapshot of a world with meshes restores bitwise into one with the same meshes only", "[mesh][snapshot]") {
  auto build = [](float floor_y) {
    auto world = std::make_unique<World>(one_thread());
    world->add_mesh(floor_mesh(3, 6), {.position = {0, floor_y, 0}}, 0.3f, 0.6f);
    world->add_mesh(box_mesh({-1, 0.5f, -1}, {1, 1.5f, 1}));
    for (int k = 0; k < 40; ++k)
      world->add_sphere({.position = {-1.5f + 0.4f * (k % 8), 2.5f + 0.5f * (k / 8), 0.1f * (k % 3)}, .radius = 0.18f});
    return world;
  };
  const auto a = build(0.0f);
  for (int k = 0; k < 60; ++k) a->step(1.0f / 60);
  std::vector<std::byte> bytes;
  a->save(bytes);
  const auto b = build(0.0f);
  b->restore(bytes);
  for (int k = 0; k < 60; ++k) a->step(1.0f / 60), b->step(1.0f / 60);
  CHECK(a->state_hash() == b->state_hash());

  const auto moved = build(0.01f);  // one mesh placed elsewhere
  CHECK_THROWS_WITH(moved->restore(bytes), Catch::Matchers::Contains("wrong mesh 0"));
  World none(one_thread());
  CHECK_THROWS_WITH(none.restore(bytes), Catch::Matchers::Contains("saved with 2 meshes and this World has 0"));
  World plain(one_thread());
  plain.add_sphere({.position = {0, 1, 0}});
  plain.save(bytes);
  CHECK_THROWS_WITH(b->restore(bytes), Catch::Matchers::Contains("saved without meshes and this World has 2"));
}
