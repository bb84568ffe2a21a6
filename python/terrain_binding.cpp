// hail.Terrain from a 2-D numpy array of heights, and World.set_terrain.

#include <hail/errors.h>

#include "bindings.h"

namespace hail::python {

void bind_terrain(py::module_& m, py::class_<PyWorld>& world) {
  using py::arg;
  py::class_<PyTerrain>(m, "Terrain",
                        "Terrain(heights, cell=1.0, *, cell_z=None, origin=(0, 0, 0), leaf_size=8)\n\n"
                        "A static heightmap terrain (C++ hail::Terrain) from a 2-D array of heights in metres:\n"
                        "heights[j, i] is the vertex at x = origin[0] + i * cell, z = origin[2] + j * cell_z\n"
                        "(rows along z, columns along x), y = origin[1] + heights[j, i]. Immutable; several\n"
                        "worlds may share one. Bad values raise hail.InvalidArgument.")
      .def(py::init([](const py::array_t<float, py::array::c_style | py::array::forcecast>& heights, float cell,
                       std::optional<float> cell_z, const Vec3& origin, std::uint32_t leaf_size) {
             if (heights.ndim() != 2)
               throw InvalidArgument("hail.Terrain: heights must be a 2-D array (rows along z, columns along x), got " +
                                     std::to_string(heights.ndim()) + " dimensions");
             const auto rows = static_cast<std::uint64_t>(heights.shape(0));
             const auto cols = static_cast<std::uint64_t>(heights.shape(1));
             HeightmapParams params{.cell_x = cell, .cell_z = cell_z.value_or(cell), .origin_x = origin.x(),
                                    .origin_y = origin.y(), .origin_z = origin.z()};
             check_heightmap_size(cols, rows, "hail.Terrain heights");
             std::vector<float> samples(heights.data(), heights.data() + heights.size());
             Heightmap map = Heightmap::from_samples(static_cast<std::uint32_t>(cols), static_cast<std::uint32_t>(rows),
                                                     params, std::move(samples));
             py::gil_scoped_release release;  // the BVH build takes seconds for large maps
             return PyTerrain{std::make_shared<const Terrain>(std::move(map), leaf_size)};
           }),
           arg("heights"), arg("cell") = 1.0f, py::kw_only(), arg("cell_z") = py::none(),
           arg("origin") = Vec3(Vec3::Zero()), arg("leaf_size") = Terrain::kDefaultLeafSize)
      .def_property_readonly(
          "shape", [](const PyTerrain& t) { return py::make_tuple(t.terrain->heightmap().rows(), t.terrain->heightmap().cols()); },
          "(rows, cols) of the heights")
      .def_property_readonly(
          "extent",
          [](const PyTerrain& t) {
            const HeightmapExtent e = t.terrain->heightmap().extent();
            return py::make_tuple(e.min_x, e.max_x, e.min_z, e.max_z);
          },
          "(min_x, max_x, min_z, max_z), m")
      .def_property_readonly(
          "triangle_count", [](const PyTerrain& t) { return t.terrain->triangle_count(); },
          "triangles, two per cell")
      .def("surface_height",
           [](const PyTerrain& t, const py::object& x, const py::object& z) -> py::object {
             // numpy broadcasts x against z; a pair of scalars gives a float.
             const py::tuple both = py::module_::import("numpy").attr("broadcast_arrays")(
                 py::array_t<float, py::array::forcecast>::ensure(x), py::array_t<float, py::array::forcecast>::ensure(z));
             const auto xs = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(both[0]);
             const auto zs = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(both[1]);
             if (!xs || !zs) throw py::type_error("hail.Terrain.surface_height takes numbers or arrays of them");
             const Heightmap& map = t.terrain->heightmap();
             if (xs.ndim() == 0) return py::float_(map.surface_height(*xs.data(), *zs.data()));
             py::array_t<float> out(std::vector<py::ssize_t>(xs.shape(), xs.shape() + xs.ndim()));
             float* o = out.mutable_data();
             for (py::ssize_t k = 0; k < xs.size(); ++k) o[k] = map.surface_height(xs.data()[k], zs.data()[k]);
             return out;
           },
           arg("x"), arg("z"),
           "Height of the surface at (x, z) on its triangles, NaN outside the map; x and z may be\n"
           "numpy arrays (broadcast), e.g. terrain.surface_height(world.px, world.pz).")
      .def_property_readonly(
          "heights",
          [](const PyTerrain& t) {
            const Heightmap& h = t.terrain->heightmap();
            py::array_t<float> out({static_cast<py::ssize_t>(h.rows()), static_cast<py::ssize_t>(h.cols())});
            for (std::uint32_t j = 0; j < h.rows(); ++j)
              for (std::uint32_t i = 0; i < h.cols(); ++i) out.mutable_at(j, i) = h.height(i, j);
            return out;
          },
          "The vertex heights y, m, as a (rows, cols) array (a copy)");

  world.def(
      "set_terrain",
      [](PyWorld& self, const py::object& terrain, float restitution, float friction) {
        World& w = self.get();
        if (terrain.is_none()) {
          w.set_terrain(nullptr, restitution, friction);
        } else {
          w.set_terrain(terrain.cast<const PyTerrain&>().terrain, restitution, friction);
        }
        self.terrain = terrain;
      },
      arg("terrain"), arg("restitution") = 0.5f, arg("friction") = 0.5f,
      "set_terrain(terrain, restitution=0.5, friction=0.5)\n\n"
      "Sets (None removes) the world's terrain, a hail.Terrain, with its material.");
  world.def_property_readonly(
      "terrain", [](PyWorld& self) { return self.terrain; },
      "The hail.Terrain set by set_terrain, or None (a scene file's terrain is not exposed here).");
  world.def_property_readonly(
      "has_terrain", [](PyWorld& self) { return self.get().terrain() != nullptr; }, "Whether the world has a terrain.");
}

}  // namespace hail::python
