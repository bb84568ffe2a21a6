// hail.TriangleMesh from numpy arrays or an OBJ/STL file, and World.add_mesh.

#include <hail/errors.h>
#include <hail/triangle_mesh.h>

#include <array>

#include "bindings.h"

namespace hail::python {

void bind_mesh(py::module_& m, py::class_<PyWorld>& world) {
  using py::arg;
  py::class_<TriangleMesh>(m, "TriangleMesh",
                           "TriangleMesh(vertices, indices)\n\n"
                           "A triangle mesh (C++ hail::TriangleMesh): vertices an (n, 3) array of metres, indices\n"
                           "an (m, 3) array (or a flat one of 3 m) of vertex numbers, one row per triangle. A\n"
                           "closed mesh is a solid that collides on the side its counter-clockwise triangles face;\n"
                           "any other is a two-sided shell (docs/meshes.md). Bad values raise\n"
                           "hail.InvalidArgument.")
      .def(py::init([](const py::array_t<float, py::array::c_style | py::array::forcecast>& vertices,
                       const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& indices) {
             if (vertices.ndim() != 2 || vertices.shape(1) != 3)
               throw InvalidArgument("hail.TriangleMesh: vertices must be an (n, 3) array");
             if (!(indices.ndim() == 1 || (indices.ndim() == 2 && indices.shape(1) == 3)))
               throw InvalidArgument("hail.TriangleMesh: indices must be an (m, 3) or a flat array");
             std::vector<Vec3> v;
             v.reserve(static_cast<std::size_t>(vertices.shape(0)));
             for (py::ssize_t k = 0; k < vertices.shape(0); ++k)
               v.emplace_back(vertices.at(k, 0), vertices.at(k, 1), vertices.at(k, 2));
             std::vector<std::uint32_t> idx(static_cast<std::size_t>(indices.size()));
             for (std::size_t k = 0; k < idx.size(); ++k) {
               const std::int64_t i = indices.data()[k];
               if (i < 0 || i > 0xFFFFFFFFll)
                 throw InvalidArgument("hail.TriangleMesh: index " + std::to_string(k) + " is " + std::to_string(i) +
                                       ", not a vertex number");
               idx[k] = static_cast<std::uint32_t>(i);
             }
             return TriangleMesh(std::move(v), std::move(idx));
           }),
           arg("vertices"), arg("indices"))
      .def_static("load", &TriangleMesh::load, arg("path"),
                  "load(path) -> TriangleMesh\n\nAn .obj or .stl file (binary or ASCII); hail.FileError names the\n"
                  "line at fault in a malformed file.")
      .def_property_readonly("triangle_count", &TriangleMesh::triangle_count, "triangles in the mesh")
      .def_property_readonly("closed", &TriangleMesh::closed,
                             "whether every edge is shared by two triangles wound oppositely (a solid)")
      .def_property_readonly(
          "vertices",
          [](const TriangleMesh& t) {
            py::array_t<float> out({static_cast<py::ssize_t>(t.vertices().size()), py::ssize_t{3}});
            for (std::size_t k = 0; k < t.vertices().size(); ++k)
              for (int d = 0; d < 3; ++d) out.mutable_at(k, d) = t.vertices()[k][d];
            return out;
          },
          "the (n, 3) vertices, m (a copy)")
      .def_property_readonly(
          "indices",
          [](const TriangleMesh& t) {
            py::array_t<std::uint32_t> out({static_cast<py::ssize_t>(t.triangle_count()), py::ssize_t{3}});
            std::copy(t.indices().begin(), t.indices().end(), out.mutable_data());
            return out;
          },
          "the (m, 3) vertex numbers of each triangle (a copy)");

  world.def(
      "add_mesh",
      // Vec3 through pybind11's Eigen caster trips GCC's -Wmaybe-uninitialized here: plain arrays.
      [](PyWorld& self, const TriangleMesh& mesh, const std::array<float, 3>& position,
         const std::array<float, 3>& axis, float degrees, float scale, float restitution, float friction) {
        World& w = self.get();
        MeshTransform transform;
        transform.position = Vec3(position[0], position[1], position[2]);
        transform.axis = Vec3(axis[0], axis[1], axis[2]);
        transform.degrees = degrees;
        transform.scale = scale;
        // With the GIL held: another Python thread could otherwise call into this World while
        // it changes (step() guards itself with PyWorld::stepping; add_mesh is short).
        return w.add_mesh(mesh, transform, restitution, friction);
      },
      arg("mesh"), py::kw_only(), arg("position") = std::array<float, 3>{0.0f, 0.0f, 0.0f},
      arg("axis") = std::array<float, 3>{0.0f, 1.0f, 0.0f}, arg("degrees") = 0.0f, arg("scale") = 1.0f,
      arg("restitution") = 0.5f, arg("friction") = 0.5f,
      "add_mesh(mesh, *, position=(0, 0, 0), axis=(0, 1, 0), degrees=0, scale=1, restitution=0.5,\n"
      "friction=0.5) -> int\n\n"
      "Adds a static hail.TriangleMesh, scaled, turned by degrees about axis, then moved to\n"
      "position, with its material; returns its index (events name it with WITH_MESH).");
  world.def_property_readonly(
      "mesh_count", [](PyWorld& self) { return self.get().mesh_count(); }, "Meshes added with add_mesh.");
}

}  // namespace hail::python
