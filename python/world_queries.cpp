// World queries from Python: rays, swept spheres and overlaps, one at a time or, for rays, a
// batch from two (n, 3) arrays answered in parallel without the GIL.

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "bindings.h"

namespace hail::python {
namespace {

using Self = PyWorld&;
constexpr float kInf = std::numeric_limits<float>::infinity();

const char* kind_name(QueryHitKind kind) {
  switch (kind) {
    case QueryHitKind::Sphere: return "sphere";
    case QueryHitKind::Terrain: return "terrain";
    case QueryHitKind::Plane: return "plane";
    case QueryHitKind::Mesh:
      return "mesh";
  }
  return "?";
}

QueryFilter make_filter(std::uint32_t mask, bool terrain, bool planes, std::optional<SphereId> ignore,
                        bool meshes = true) {
  return QueryFilter{
      .mask = mask, .terrain = terrain, .planes = planes, .ignore = ignore.value_or(SphereId{}), .meshes = meshes};
}

py::object hit_or_none(const std::optional<QueryHit>& hit) { return hit ? py::cast(*hit) : py::none(); }

py::array ids_array(const std::vector<SphereId>& ids) {
  py::array_t<std::uint64_t> out(static_cast<py::ssize_t>(ids.size()));
  for (std::size_t k = 0; k < ids.size(); ++k) out.mutable_at(static_cast<py::ssize_t>(k)) = pack(ids[k]);
  return out;
}

/// The structured array raycast_batch returns (hail.ray_hit_dtype).
py::dtype ray_hit_dtype() {
  py::dict spec;
  spec["names"] = py::make_tuple("hit", "kind", "sphere", "index", "point", "normal", "distance");
  spec["formats"] = py::make_tuple("?", "u1", "<u8", "<u4", "(3,)<f4", "(3,)<f4", "<f4");
  return py::dtype::from_args(spec);
}

struct RayHitRecord {
  bool hit;
  std::uint8_t kind;
  std::uint64_t sphere;
  std::uint32_t index;
  float point[3], normal[3], distance;
} __attribute__((packed));
static_assert(sizeof(RayHitRecord) == 1 + 1 + 8 + 4 + 12 + 12 + 4);

}  // namespace

void bind_world_queries(py::module_& m, py::class_<PyWorld>& c) {
  using py::arg;
  py::class_<QueryHit>(m, "QueryHit", "One hit of a ray or a swept sphere (read-only).")
      .def_property_readonly(
          "kind", [](const QueryHit& h) { return kind_name(h.kind); }, "'sphere', 'terrain', 'plane' or 'mesh'")
      .def_property_readonly(
          "sphere",
          [](const QueryHit& h) -> py::object {
            return h.kind == QueryHitKind::Sphere ? py::cast(h.sphere) : py::none();
          },
          "the handle of the sphere hit, or None")
      .def_readonly("index", &QueryHit::index, "terrain triangle, plane or mesh index (0 for a sphere)")
      .def_readonly("triangle", &QueryHit::triangle,
                    "a mesh hit's triangle among all the world's mesh triangles, else 0")
      .def_property_readonly(
          "point", [](const QueryHit& h) { return py::make_tuple(h.point.x(), h.point.y(), h.point.z()); },
          "where the surface was met, m")
      .def_property_readonly(
          "normal", [](const QueryHit& h) { return py::make_tuple(h.normal.x(), h.normal.y(), h.normal.z()); },
          "unit normal out of what was hit")
      .def_readonly("distance", &QueryHit::distance, "along the normalised direction from the origin, m")
      .def("__repr__", [](const QueryHit& h) {
        return "<hail.QueryHit " + std::string(kind_name(h.kind)) + " " +
               (h.kind == QueryHitKind::Sphere ? std::to_string(pack(h.sphere)) : std::to_string(h.index)) +
               " at distance " + std::to_string(h.distance) + ">";
      });
  m.attr("ray_hit_dtype") = ray_hit_dtype();
  m.attr("KIND_SPHERE") = 0;
  m.attr("KIND_TERRAIN") = 1;
  m.attr("KIND_PLANE") = 2;
  m.attr("KIND_MESH") = 3;
  m.attr("NO_SPHERE") = pack(SphereId{});

  // Keywords of every query: mask (categories of spheres reported), terrain, planes and meshes
  // (report them), ignore (a handle to leave out), as QueryFilter.
  c.def(
      "raycast",
      [](Self self, const Vec3& origin, const Vec3& direction, float max_distance, std::uint32_t mask, bool terrain,
         bool planes, std::optional<SphereId> ignore, bool meshes) {
        return hit_or_none(self.get().raycast(Ray{origin, direction, max_distance},
                                              make_filter(mask, terrain, planes, ignore, meshes)));
      },
      arg("origin"), arg("direction"), arg("max_distance") = kInf, py::kw_only(), arg("mask") = kAllCategories,
      arg("terrain") = true, arg("planes") = true, arg("ignore") = py::none(), arg("meshes") = true,
      "raycast(origin, direction, max_distance=inf, *, mask=0xFFFFFFFF, terrain=True, planes=True,\n"
      "        ignore=None, meshes=True) -> QueryHit | None\n\n"
      "The closest hit along the ray against spheres, terrain, planes and meshes, or None.");
  c.def(
      "raycast_all",
      [](Self self, const Vec3& origin, const Vec3& direction, float max_distance, std::uint32_t mask, bool terrain,
         bool planes, std::optional<SphereId> ignore, bool meshes) {
        return self.get().raycast_all(Ray{origin, direction, max_distance},
                                      make_filter(mask, terrain, planes, ignore, meshes));
      },
      arg("origin"), arg("direction"), arg("max_distance") = kInf, py::kw_only(), arg("mask") = kAllCategories,
      arg("terrain") = true, arg("planes") = true, arg("ignore") = py::none(), arg("meshes") = true,
      "Every hit along the ray, nearest first (list of QueryHit).");
  c.def(
      "raycast_batch",
      [](Self self, const py::handle& origins, const py::handle& directions, float max_distance, std::uint32_t mask,
         bool terrain, bool planes, std::optional<SphereId> ignore, bool meshes) {
        const auto o = rows_of_3(origins, "origins");
        const auto d = rows_of_3(directions, "directions");
        if (o.shape(0) != d.shape(0))
          throw InvalidArgument("hail.World.raycast_batch: " + std::to_string(o.shape(0)) + " origins and " +
                                std::to_string(d.shape(0)) + " directions");
        const std::size_t n = static_cast<std::size_t>(o.shape(0));
        std::vector<Ray> rays(n);
        for (std::size_t k = 0; k < n; ++k)
          rays[k] = Ray{Vec3(o.at(k, 0), o.at(k, 1), o.at(k, 2)), Vec3(d.at(k, 0), d.at(k, 1), d.at(k, 2)),
                        max_distance};
        std::vector<std::optional<QueryHit>> hits(n);
        const World& world = self.get();
        {
          // Const, like every query: the World's own threads answer blocks of rays meanwhile.
          py::gil_scoped_release release;
          world.raycast_batch(rays, hits, make_filter(mask, terrain, planes, ignore, meshes));
        }
        py::array out(ray_hit_dtype(), py::array::ShapeContainer{static_cast<py::ssize_t>(n)});
        auto* records = static_cast<RayHitRecord*>(out.mutable_data());
        for (std::size_t k = 0; k < n; ++k) {
          RayHitRecord r{};
          r.hit = hits[k].has_value();
          if (r.hit) {
            const QueryHit& h = *hits[k];
            r.kind = static_cast<std::uint8_t>(h.kind);
            r.sphere = h.kind == QueryHitKind::Sphere ? pack(h.sphere) : pack(SphereId{});
            r.index = h.index;
            for (int a = 0; a < 3; ++a) r.point[a] = h.point[a], r.normal[a] = h.normal[a];
            r.distance = h.distance;
          } else {
            r.sphere = pack(SphereId{});
            r.distance = kInf;
          }
          std::memcpy(&records[k], &r, sizeof r);
        }
        return out;
      },
      arg("origins"), arg("directions"), arg("max_distance") = kInf, py::kw_only(), arg("mask") = kAllCategories,
      arg("terrain") = true, arg("planes") = true, arg("ignore") = py::none(), arg("meshes") = true,
      "raycast_batch(origins, directions, max_distance=inf, *, ...) -> numpy structured array\n\n"
      "raycast for each row of two (n, 3) arrays, in parallel with the GIL released. Fields\n"
      "(hail.ray_hit_dtype): hit (bool), kind (KIND_SPHERE, KIND_TERRAIN, KIND_PLANE, KIND_MESH), sphere\n"
      "(handle, NO_SPHERE unless a sphere), index, point, normal, distance (inf for a miss).");
  c.def(
      "sphere_cast",
      [](Self self, const Vec3& origin, const Vec3& direction, float radius, float max_distance, std::uint32_t mask,
         bool terrain, bool planes, std::optional<SphereId> ignore, bool meshes) {
        return hit_or_none(self.get().sphere_cast(Ray{origin, direction, max_distance}, radius,
                                                  make_filter(mask, terrain, planes, ignore, meshes)));
      },
      arg("origin"), arg("direction"), arg("radius"), arg("max_distance") = kInf, py::kw_only(),
      arg("mask") = kAllCategories, arg("terrain") = true, arg("planes") = true, arg("ignore") = py::none(),
      arg("meshes") = true, "The first hit of a sphere of this radius swept along the ray, or None.");
  c.def(
      "overlap_sphere",
      [](Self self, const Vec3& centre, float radius, std::uint32_t mask, std::optional<SphereId> ignore) {
        return ids_array(self.get().overlap_sphere(centre, radius, make_filter(mask, false, false, ignore)));
      },
      arg("centre"), arg("radius"), py::kw_only(), arg("mask") = kAllCategories, arg("ignore") = py::none(),
      "Handles (uint64 array) of every sphere touching the ball, by handle index.");
  c.def(
      "overlap_box",
      [](Self self, const Vec3& lo, const Vec3& hi, std::uint32_t mask, std::optional<SphereId> ignore) {
        return ids_array(self.get().overlap_box(lo, hi, make_filter(mask, false, false, ignore)));
      },
      arg("min"), arg("max"), py::kw_only(), arg("mask") = kAllCategories, arg("ignore") = py::none(),
      "Handles (uint64 array) of every sphere touching the closed box [min, max].");
}

}  // namespace hail::python
