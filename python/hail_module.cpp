// The Python module `hail` (docs/python.md): hail's exceptions as Python exceptions, then each
// file's part of the API, then the ParaView writer of the scenes library.

#include <hail/errors.h>
#include <hail/version.h>

#include "bindings.h"
#include "scenes/vtk_frames.h"

namespace hail::python {
namespace {

void bind_exceptions(py::module_& m) {
  // Base first: pybind11 tries the translators registered last first, so a SizeLimitError is
  // raised as itself, not as its base FileError.
  auto& invalid = py::register_exception<InvalidArgument>(m, "InvalidArgument", PyExc_ValueError);
  auto& file = py::register_exception<FileError>(m, "FileError", PyExc_OSError);
  auto& size = py::register_exception<SizeLimitError>(m, "SizeLimitError", file.ptr());
  invalid.attr("__doc__") = "A value passed to hail is out of its domain; the message names it (hail::InvalidArgument).";
  file.attr("__doc__") = "A file could not be read, written or parsed; the message names it (hail::FileError).";
  size.attr("__doc__") = "A heightmap file asks for more vertices than allowed (hail::SizeLimitError).";
}

void bind_vtk(py::module_& m) {
  using py::arg;
  py::class_<bench::VtkFrames>(
      m, "VtkFrames",
      "VtkFrames(directory, format='vtp', name='frame')\n\n"
      "ParaView frames of a world (scenes/vtk_frames.h): write(world, time) adds name_000000.vtp,\n"
      "name_000001.vtp, ... (format 'vtp': VTK XML PolyData; 'vtu': UnstructuredGrid, which meshio\n"
      "reads) with the spheres as points and radius, velocity, speed, angular_velocity, sleeping\n"
      "and handle as point data, and rewrites name.pvd, the time index ParaView opens.\n"
      "hail.FileError when the folder or a file cannot be written.")
      .def(py::init([](const std::string& dir, const std::string& format, const std::string& name) {
             if (format != "vtp" && format != "vtu")
               throw InvalidArgument("hail.VtkFrames: format must be 'vtp' or 'vtu', got '" + format + "'");
             return std::make_unique<bench::VtkFrames>(
                 dir, format == "vtp" ? bench::VtkFormat::PolyData : bench::VtkFormat::UnstructuredGrid, name);
           }),
           arg("directory"), arg("format") = "vtp", arg("name") = "frame")
      .def(
          "write", [](bench::VtkFrames& f, PyWorld& w, double time) { return f.write(w.get(), time); }, arg("world"),
          arg("time"), "Writes the world's spheres as the next frame at this time (s); returns its path.")
      .def_property_readonly("frame_count", &bench::VtkFrames::frame_count, "frames written")
      .def_property_readonly("index_path", &bench::VtkFrames::index_path, "the .pvd file")
      .def_property_readonly("directory", &bench::VtkFrames::dir, "the folder of the frames");
}

}  // namespace
}  // namespace hail::python

PYBIND11_MODULE(hail, m) {
  using namespace hail::python;
  m.doc() =
      "hail: many spheres colliding with each other, planes and terrain (Python bindings of the\n"
      "C++ kernel; docs/python.md).\n\n"
      "    import hail, numpy as np\n"
      "    world = hail.World(threads=2)\n"
      "    world.add_plane()\n"
      "    handles = world.add_spheres(np.random.rand(1000, 3) * 10 + (0, 1, 0), radii=0.2)\n"
      "    world.step(1 / 60, n=120)\n"
      "    print(world.positions.mean(axis=0), world.kinetic_energy(), hex(world.state_hash()))\n\n"
      "Handles are ints (index | generation << 32); arrays are numpy; hail.InvalidArgument\n"
      "(a ValueError) and hail.FileError (an OSError) report bad values and files.";
  m.attr("__version__") = HAIL_VERSION_STRING;
  bind_exceptions(m);
  bind_settings(m);
  py::class_<PyWorld> world(m, "World");
  bind_world(m, world);
  bind_world_arrays(m, world);
  bind_world_queries(m, world);
  bind_terrain(m, world);
  bind_mesh(m, world);
  bind_vtk(m);
}
