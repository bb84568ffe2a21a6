#pragma once
// What the files of the Python module share: the World the module wraps, the handle conversion
// and each file's bind function (hail_module.cpp calls them in order).

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <bit>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <hail/world.h>

namespace hail::python {
namespace py = pybind11;

/// A handle as Python sees it: one int, index | generation << 32, which is also its bytes in
/// memory (SphereId is {index, generation} on a little-endian machine), so World::handles()
/// reads as a numpy uint64 array with no copy.
static_assert(sizeof(SphereId) == 8 && std::endian::native == std::endian::little);
[[nodiscard]] inline std::uint64_t pack(SphereId id) {
  return std::uint64_t{id.index} | (std::uint64_t{id.generation} << 32);
}
[[nodiscard]] inline SphereId unpack(std::uint64_t h) {
  return SphereId{static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(h >> 32)};
}

/// What a World read from a scene file adds to it (World.from_scene).
struct SceneInfo {
  std::string path, description;
  float dt = 0.0f;
  int steps = 0;
  std::vector<SphereId> handles;  ///< in the order the file adds the spheres
};

/// hail.World: the C++ World and what Python keeps beside it.
struct PyWorld {
  std::unique_ptr<World> world;
  /// The terrain set from Python (World::terrain() gives only a pointer).
  py::object terrain = py::none();
  std::unique_ptr<SceneInfo> scene;
  /// step() runs without the GIL: another Python thread could call in meanwhile, and a World
  /// takes one caller at a time (include/hail/world.h), so every call checks this first.
  std::atomic<bool> stepping{false};

  World& get() {
    if (stepping.load(std::memory_order_acquire))
      throw std::runtime_error("hail.World is stepping on another thread: call it again once step() has returned");
    return *world;
  }
};

/// hail.Terrain: an immutable terrain, shareable by several worlds.
struct PyTerrain {
  std::shared_ptr<const Terrain> terrain;
};

/// The settings table as keyword arguments (settings_args.cpp): "soft_step.substeps" is
/// spelt soft_step_substeps, or given in a dict, soft_step={"substeps": 8}.
WorldSettings settings_from_kwargs(const py::kwargs& kwargs, const char* caller);
/// Only the settings in kwargs, as "NAME=VALUE" texts by their table names (scene overrides).
std::vector<std::string> setting_assignments(const py::kwargs& kwargs, const char* caller);
py::dict settings_to_dict(const WorldSettings& s);
/// The keyword arguments' part of hail.World's docstring: one line per setting.
std::string settings_doc();
void bind_settings(py::module_& m);

void bind_world(py::module_& m, py::class_<PyWorld>& world);
void bind_world_arrays(py::module_& m, py::class_<PyWorld>& world);
void bind_world_queries(py::module_& m, py::class_<PyWorld>& world);
void bind_terrain(py::module_& m, py::class_<PyWorld>& world);
void bind_mesh(py::module_& m, py::class_<PyWorld>& world);

/// A numpy array over `count` elements at `data` that owns nothing: `owner` (the Python World)
/// is its base, so the World outlives it; numpy refuses writes to it.
template <class T>
py::array read_only_view(const T* data, std::size_t count, py::handle owner) {
  py::array a(py::dtype::of<T>(), {count}, {sizeof(T)}, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// An (n, 3) float32 C-contiguous array from any array-like (numpy converts lists, float64, ...);
/// TypeError-style ValueError naming `what` for another shape.
py::array_t<float, py::array::c_style | py::array::forcecast> rows_of_3(const py::handle& values, const char* what);

}  // namespace hail::python

namespace pybind11::detail {
/// SphereId <-> int (hail::python::pack): a Python int, or anything with __index__ (numpy's
/// uint64 scalars, what iterating a handle array gives).
template <>
struct type_caster<hail::SphereId> {
  PYBIND11_TYPE_CASTER(hail::SphereId, const_name("int"));
  bool load(handle src, bool) {
    if (!src || PyBool_Check(src.ptr()) || PyFloat_Check(src.ptr()) || !PyIndex_Check(src.ptr())) return false;
    object index = reinterpret_steal<object>(PyNumber_Index(src.ptr()));
    if (!index) {
      PyErr_Clear();
      return false;
    }
    const unsigned long long h = PyLong_AsUnsignedLongLong(index.ptr());
    if (PyErr_Occurred()) {  // negative or beyond 64 bits: not a handle
      PyErr_Clear();
      return false;
    }
    value = hail::python::unpack(h);
    return true;
  }
  static handle cast(hail::SphereId id, return_value_policy, handle) {
    return PyLong_FromUnsignedLongLong(hail::python::pack(id));
  }
};
}  // namespace pybind11::detail
