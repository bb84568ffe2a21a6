// hail.World: construction (keyword settings, scene files), stepping without the GIL, adding
// and removing spheres (one or arrays of them), the control calls, snapshots and figures.

#include <filesystem>
#include <span>

#include <hail/errors.h>

#include "bindings.h"
#include "scenes/scene_file.h"

namespace hail::python {
namespace {

/// Clears PyWorld::stepping however the step ends.
struct SteppingFlag {
  std::atomic<bool>& flag;
  explicit SteppingFlag(std::atomic<bool>& f) : flag(f) {
    bool expected = false;
    if (!flag.compare_exchange_strong(expected, true, std::memory_order_acq_rel))
      throw std::runtime_error("hail.World is stepping on another thread: call it again once step() has returned");
  }
  ~SteppingFlag() { flag.store(false, std::memory_order_release); }
};

std::unique_ptr<PyWorld> make_world(const py::kwargs& kwargs) {
  auto w = std::make_unique<PyWorld>();
  w->world = std::make_unique<World>(settings_from_kwargs(kwargs, "hail.World()"));
  return w;
}

std::unique_ptr<PyWorld> from_scene(const std::string& path, std::optional<int> threads,
                                    std::optional<std::size_t> spheres, std::optional<float> dt,
                                    std::optional<int> steps, const py::kwargs& kwargs) {
  // The scene reader reports every problem as std::invalid_argument; a file that is not there
  // or not a file is an OSError in Python, so it is told apart first.
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw FileError(path + ": no such scene file");
  if (std::filesystem::is_directory(status)) throw FileError(path + ": is a directory, not a scene file");
  bench::SceneOverrides overrides{.spheres = spheres, .threads = threads, .steps = steps, .dt = dt,
                                  .set = setting_assignments(kwargs, "hail.World.from_scene()")};
  bench::Scene scene;
  try {
    scene = bench::load_scene_file(path, overrides);
  } catch (const FileError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InvalidArgument(e.what());
  }
  auto w = std::make_unique<PyWorld>();
  w->world = std::move(scene.world);
  w->scene = std::make_unique<SceneInfo>(
      SceneInfo{path, scene.description, scene.dt, scene.default_steps, std::move(scene.ids)});
  return w;
}

void step(PyWorld& self, float dt, long long n) {
  if (n < 0) throw InvalidArgument("hail.World.step: n must be >= 0, got " + std::to_string(n));
  World& world = self.get();
  check_step(world.settings(), dt);  // refused before anything runs, as World::step would
  SteppingFlag flag(self.stepping);
  py::gil_scoped_release release;
  for (long long k = 0; k < n; ++k) {
    world.step(dt);
    if (k + 1 < n) {
      // Ctrl-C between steps: a long run stops at a step's end, the World whole.
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
  }
}

/// Per-sphere values of add_spheres: a scalar for all, or an array of n.
template <class T>
std::vector<T> per_sphere(const py::handle& v, std::size_t n, const char* what) {
  const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(v);
  if (!a) throw py::type_error(std::string("hail.World.add_spheres: ") + what + " must be a number or an array");
  if (a.ndim() == 0) return std::vector<T>(n, *a.data());
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw InvalidArgument(std::string("hail.World.add_spheres: ") + what + " must be a scalar or have " +
                          std::to_string(n) + " values (one per position), got shape " +
                          py::str(a.attr("shape")).cast<std::string>());
  return std::vector<T>(a.data(), a.data() + n);
}

std::vector<Vec3> vec3_rows(const py::handle& v, std::size_t n, const char* what) {
  const auto a = rows_of_3(v, what);
  if (static_cast<std::size_t>(a.shape(0)) != n)
    throw InvalidArgument(std::string("hail.World: ") + what + " has " + std::to_string(a.shape(0)) +
                          " rows, expected " + std::to_string(n));
  std::vector<Vec3> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = Vec3(a.at(k, 0), a.at(k, 1), a.at(k, 2));
  return out;
}

std::vector<SphereId> handle_list(const py::handle& v) {
  const auto a = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(v);
  if (!a || a.ndim() != 1) throw py::type_error("hail.World: handles must be a 1-D array of handles (uint64)");
  std::vector<SphereId> out(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = unpack(a.at(k));
  return out;
}

py::array add_spheres(PyWorld& self, const py::handle& positions, const py::handle& radii, const py::handle& masses,
                      const py::object& velocities, const py::object& angular_velocities, const py::handle& restitution,
                      const py::handle& friction, bool is_static, bool is_kinematic, std::uint32_t category,
                      std::uint32_t mask) {
  World& world = self.get();
  const std::size_t n = static_cast<std::size_t>(rows_of_3(positions, "positions").shape(0));
  const std::vector<Vec3> p = vec3_rows(positions, n, "positions");
  const std::vector<float> r = per_sphere<float>(radii, n, "radii");
  const std::vector<float> m = per_sphere<float>(masses, n, "masses");
  const std::vector<float> e = per_sphere<float>(restitution, n, "restitution");
  const std::vector<float> f = per_sphere<float>(friction, n, "friction");
  const std::vector<Vec3> v = velocities.is_none() ? std::vector<Vec3>(n, Vec3::Zero()) : vec3_rows(velocities, n, "velocities");
  const std::vector<Vec3> w = angular_velocities.is_none() ? std::vector<Vec3>(n, Vec3::Zero())
                                                           : vec3_rows(angular_velocities, n, "angular_velocities");
  auto desc = [&](std::size_t k) {
    return SphereDesc{.position = p[k], .velocity = v[k], .angular_velocity = w[k], .radius = r[k], .mass = m[k],
                      .restitution = e[k], .friction = f[k], .is_static = is_static, .is_kinematic = is_kinematic,
                      .filter = CollisionFilter{category, mask}};
  };
  // All or nothing: every sphere is first added to a scratch World with the same settings (what
  // add_sphere checks depends on the sphere and the settings alone), a chunk at a time, each
  // chunk removed again from the last slot down, so the scratch stays small. A refusal there
  // leaves this World untouched, its handle tables included.
  {
    WorldSettings scratch_settings = world.settings();
    scratch_settings.threads = 1;
    World scratch(scratch_settings);
    constexpr std::size_t kChunk = 1024;
    std::vector<SphereId> ids;
    for (std::size_t first = 0; first < n; first += kChunk) {
      ids.clear();
      for (std::size_t k = first; k < std::min(n, first + kChunk); ++k) {
        try {
          ids.push_back(scratch.add_sphere(desc(k)));
        } catch (const InvalidArgument& error) {
          throw InvalidArgument("hail.World.add_spheres: sphere " + std::to_string(k) +
                                " refused, no sphere added: " + error.what());
        }
      }
      for (auto id = ids.rbegin(); id != ids.rend(); ++id) scratch.remove_sphere(*id);
    }
  }
  world.reserve(world.sphere_count() + n);
  py::array_t<std::uint64_t> handles(static_cast<py::ssize_t>(n));
  auto out = handles.mutable_unchecked<1>();
  for (std::size_t k = 0; k < n; ++k) out(static_cast<py::ssize_t>(k)) = pack(world.add_sphere(desc(k)));
  return handles;
}

}  // namespace

py::array_t<float, py::array::c_style | py::array::forcecast> rows_of_3(const py::handle& values, const char* what) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!a) throw py::type_error(std::string("hail: ") + what + " must be an (n, 3) array of numbers");
  if (a.ndim() == 1 && a.shape(0) == 3) a = a.reshape({1, 3});
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InvalidArgument(std::string("hail: ") + what + " must be an (n, 3) array, got shape " +
                          py::str(a.attr("shape")).cast<std::string>());
  return a;
}

void bind_world(py::module_& m, py::class_<PyWorld>& c) {
  using py::arg;
  using Self = PyWorld&;
  static const std::string init_doc =
      "World(**settings)\n\n"
      "A world of spheres, planes and terrain (C++ hail::World). Every setting of the settings\n"
      "table is a keyword argument, checked as the C++ constructor checks it (hail.InvalidArgument\n"
      "naming the value; TypeError for a wrong type or an unknown name). A nested setting is\n"
      "spelt with '_' (soft_step_substeps=8) or given as a dict (soft_step={'substeps': 8}).\n"
      "hail.settings_table() lists them with their ranges; world.settings reads them back.\n\n"
      "Settings:\n" +
      settings_doc();
  c.def(py::init([](const py::kwargs& kwargs) { return make_world(kwargs); }), init_doc.c_str());
  c.def_static("from_scene", &from_scene, arg("path"), py::kw_only(), arg("threads") = py::none(),
               arg("spheres") = py::none(), arg("dt") = py::none(), arg("steps") = py::none(),
               "from_scene(path, *, threads=None, spheres=None, dt=None, steps=None, **settings) -> World\n\n"
               "The world of a scene file (docs/scene_format.md), read by the scenes library's loader\n"
               "as `hail-bench run --scene PATH` reads it; the keywords override the file's values as\n"
               "that command's flags do (settings by keyword as in World()). world.scene holds the\n"
               "file's dt, step count, description and the handles in the order the file adds them.\n"
               "Raises hail.FileError for a missing file, hail.InvalidArgument for a bad one.");
  c.def_property_readonly(
      "scene",
      [](Self self) -> py::object {
        if (!self.scene) return py::none();
        py::dict d;
        d["path"] = self.scene->path;
        d["description"] = self.scene->description;
        d["dt"] = self.scene->dt;
        d["steps"] = self.scene->steps;
        py::array_t<std::uint64_t> handles(static_cast<py::ssize_t>(self.scene->handles.size()));
        for (std::size_t k = 0; k < self.scene->handles.size(); ++k)
          handles.mutable_at(static_cast<py::ssize_t>(k)) = pack(self.scene->handles[k]);
        d["handles"] = handles;
        return d;
      },
      "For a world from World.from_scene: a dict of the file's path, description, dt, steps (its\n"
      "default step count) and handles (uint64, in the order the file adds the spheres); else None.");

  c.def("step", &step, arg("dt"), arg("n") = 1,
        "step(dt, n=1)\n\n"
        "Advances the world n times by dt * time_scale seconds (World::step), with the GIL released:\n"
        "other Python threads run meanwhile (calls on this World from them raise RuntimeError until\n"
        "it returns). dt must be finite and > 0 and need at most max_substeps substeps\n"
        "(hail.InvalidArgument, nothing stepped). Ctrl-C stops between two steps.");

  c.def(
      "add_sphere",
      [](Self self, const Vec3& position, float radius, float mass, const Vec3& velocity, const Vec3& angular_velocity,
         float restitution, float friction, bool is_static, bool is_kinematic, std::uint32_t category,
         std::uint32_t mask) {
        return self.get().add_sphere(SphereDesc{.position = position, .velocity = velocity,
                                                .angular_velocity = angular_velocity, .radius = radius,
                                                .mass = mass, .restitution = restitution, .friction = friction,
                                                .is_static = is_static, .is_kinematic = is_kinematic,
                                                .filter = CollisionFilter{category, mask}});
      },
      arg("position"), arg("radius") = 0.5f, arg("mass") = 1.0f, py::kw_only(),
      arg("velocity") = Vec3(Vec3::Zero()), arg("angular_velocity") = Vec3(Vec3::Zero()), arg("restitution") = 0.5f,
      arg("friction") = 0.5f, arg("is_static") = false, arg("is_kinematic") = false,
      arg("category") = kDefaultCategory, arg("mask") = kAllCategories,
      "add_sphere(position, radius=0.5, mass=1.0, *, velocity=(0,0,0), angular_velocity=(0,0,0),\n"
      "           restitution=0.5, friction=0.5, is_static=False, is_kinematic=False,\n"
      "           category=1, mask=0xFFFFFFFF) -> int\n\n"
      "Adds a sphere and returns its handle (an int: index | generation << 32). Bad values raise\n"
      "hail.InvalidArgument naming them, the world unchanged.");
  c.def("add_spheres", &add_spheres, arg("positions"), arg("radii") = 0.5f, arg("masses") = 1.0f, py::kw_only(),
        arg("velocities") = py::none(), arg("angular_velocities") = py::none(), arg("restitution") = 0.5f,
        arg("friction") = 0.5f, arg("is_static") = false, arg("is_kinematic") = false,
        arg("category") = kDefaultCategory, arg("mask") = kAllCategories,
        "add_spheres(positions, radii=0.5, masses=1.0, *, velocities=None, angular_velocities=None,\n"
        "            restitution=0.5, friction=0.5, is_static=False, is_kinematic=False,\n"
        "            category=1, mask=0xFFFFFFFF) -> numpy.ndarray[uint64]\n\n"
        "Adds n spheres from an (n, 3) array of positions; radii, masses, restitution and friction\n"
        "are scalars or arrays of n, velocities (n, 3) arrays. Returns their handles in order.\n"
        "All or nothing: a refused sphere (hail.InvalidArgument naming its index) leaves the\n"
        "world unchanged.");
  c.def(
      "remove_sphere", [](Self self, SphereId id) { return self.get().remove_sphere(id); }, arg("handle"),
      "Removes a sphere; False for a stale handle. The last slot's sphere moves into its slot.");
  c.def(
      "add_plane",
      [](Self self, const Vec3& normal, float offset, float restitution, float friction) {
        return self.get().add_plane(
            PlaneDesc{.normal = normal, .offset = offset, .restitution = restitution, .friction = friction});
      },
      arg("normal") = Vec3(0.0f, 1.0f, 0.0f), arg("offset") = 0.0f, py::kw_only(), arg("restitution") = 0.5f,
      arg("friction") = 0.5f,
      "add_plane(normal=(0, 1, 0), offset=0.0, *, restitution=0.5, friction=0.5) -> int\n\n"
      "A static plane, the solid half-space normal . x < offset; returns its index.");
  c.def(
      "reserve", [](Self self, std::size_t n) { self.get().reserve(n); }, arg("spheres"),
      "Room for n spheres, so that adding them does not move the arrays (views stay valid).");
  c.def("__len__", [](Self self) { return self.get().sphere_count(); });
  c.def_property_readonly(
      "sphere_count", [](Self self) { return self.get().sphere_count(); }, "Number of spheres.");
  c.def_property_readonly(
      "settings", [](Self self) { return settings_to_dict(self.get().settings()); },
      "The settings as a dict of keyword names (a copy: settings are fixed at construction).");
  c.def_property_readonly(
      "thread_count", [](Self self) { return self.get().thread_count(); }, "Threads a step may use.");

  // Per-sphere reads and control calls: a stale handle raises hail.InvalidArgument.
  c.def(
      "position", [](Self self, SphereId id) { return self.get().position(id); }, arg("handle"), "Centre of a sphere, m (hail.InvalidArgument for a stale handle).");
  c.def(
      "velocity", [](Self self, SphereId id) { return self.get().velocity(id); }, arg("handle"), "Velocity of a sphere, m/s.");
  c.def(
      "angular_velocity", [](Self self, SphereId id) { return self.get().angular_velocity(id); }, arg("handle"), "Angular velocity of a sphere, rad/s.");
  c.def(
      "slot_of", [](Self self, SphereId id) { return self.get().slot_of(id); }, arg("handle"),
      "Dense slot of a handle (its index in the array views), or -1 for a stale one.");
  c.def(
      "id_at",
      [](Self self, std::size_t slot) {
        World& w = self.get();
        if (slot >= w.sphere_count())
          throw InvalidArgument("hail.World.id_at: slot " + std::to_string(slot) + " is not below sphere_count " +
                                std::to_string(w.sphere_count()));
        return w.id_at(slot);
      },
      arg("slot"), "Handle of the sphere in a dense slot.");
  c.def(
      "contains", [](Self self, SphereId id) { return self.get().slot_of(id) >= 0; }, arg("handle"), "Whether the handle names a live sphere.");
  c.def(
      "user_data", [](Self self, SphereId id) { return self.get().user_data(id); }, arg("handle"), "The game's 64-bit value for a sphere (set_user_data; 0 until set).");
  c.def(
      "collision_filter",
      [](Self self, SphereId id) {
        const CollisionFilter f = self.get().collision_filter(id);
        return py::make_tuple(f.category, f.mask);
      },
      arg("handle"), "(category, mask) of a sphere.");
  c.def(
      "is_kinematic", [](Self self, SphereId id) { return self.get().is_kinematic(id); }, arg("handle"), "Whether the sphere is kinematic (moved by its velocity alone).");
  c.def(
      "is_sleeping", [](Self self, SphereId id) { return self.get().is_sleeping(id); }, arg("handle"), "Whether the sphere sleeps (always False with sleep off).");

  c.def(
      "set_position", [](Self self, SphereId id, const Vec3& v) { self.get().set_position(id, v); }, arg("handle"),
      arg("position"), "Teleports a sphere (its velocity kept, its warm-start impulses dropped).");
  c.def(
      "set_velocity", [](Self self, SphereId id, const Vec3& v) { self.get().set_velocity(id, v); }, arg("handle"),
      arg("velocity"), "Sets a dynamic or kinematic sphere's velocity, m/s.");
  c.def(
      "set_angular_velocity", [](Self self, SphereId id, const Vec3& v) { self.get().set_angular_velocity(id, v); },
      arg("handle"), arg("angular_velocity"), "Sets a sphere's spin, rad/s (zero only, with rotation off).");
  c.def(
      "apply_impulse", [](Self self, SphereId id, const Vec3& v) { self.get().apply_impulse(id, v); }, arg("handle"),
      arg("impulse"), "v += impulse / m (N s, at the centre).");
  c.def(
      "apply_impulse_at",
      [](Self self, SphereId id, const Vec3& v, const Vec3& point) { self.get().apply_impulse_at(id, v, point); },
      arg("handle"), arg("impulse"), arg("point"), "An impulse at a world point (spins the sphere with rotation on).");
  c.def(
      "apply_force", [](Self self, SphereId id, const Vec3& v) { self.get().apply_force(id, v); }, arg("handle"),
      arg("force"), "Adds a force (N) that the next step applies, then clears.");
  c.def(
      "apply_torque", [](Self self, SphereId id, const Vec3& v) { self.get().apply_torque(id, v); }, arg("handle"),
      arg("torque"), "Adds a torque (N m) that the next step applies, then clears.");
  c.def(
      "set_restitution", [](Self self, SphereId id, float v) { self.get().set_restitution(id, v); }, arg("handle"),
      arg("restitution"), "Restitution in [0, 1].");
  c.def(
      "set_friction", [](Self self, SphereId id, float v) { self.get().set_friction(id, v); }, arg("handle"),
      arg("friction"), "Coulomb friction coefficient, >= 0.");
  c.def(
      "set_mass", [](Self self, SphereId id, float v) { self.get().set_mass(id, v); }, arg("handle"), arg("mass"), "Mass of a dynamic sphere, kg (the inertia follows; velocities kept).");
  c.def(
      "set_radius", [](Self self, SphereId id, float v) { self.get().set_radius(id, v); }, arg("handle"),
      arg("radius"), "Radius, m (the inertia follows; an overlap it makes is pushed apart by the next steps).");
  c.def(
      "set_gravity_scale", [](Self self, SphereId id, float v) { self.get().set_gravity_scale(id, v); },
      arg("handle"), arg("scale"), "The sphere's gravity becomes gravity * scale (0 floats, -1 rises).");
  c.def(
      "set_user_data", [](Self self, SphereId id, std::uint64_t v) { self.get().set_user_data(id, v); },
      arg("handle"), arg("value"), "Stores the game's 64-bit value for a sphere (hail never reads it).");
  c.def(
      "set_collision_filter",
      [](Self self, SphereId id, std::uint32_t category, std::uint32_t mask) {
        self.get().set_collision_filter(id, CollisionFilter{category, mask});
      },
      arg("handle"), arg("category") = kDefaultCategory, arg("mask") = kAllCategories,
      "Category and mask bits: two things collide when each one's category is in the other's mask.");
  c.def(
      "set_kinematic", [](Self self, SphereId id) { self.get().set_kinematic(id); }, arg("handle"), "Makes a sphere kinematic: infinite mass, moved by its velocity alone.");
  c.def(
      "set_dynamic", [](Self self, SphereId id, float mass) { self.get().set_dynamic(id, mass); }, arg("handle"),
      arg("mass"), "Makes a kinematic or static sphere dynamic with this mass, kg.");
  c.def(
      "move_kinematic",
      [](Self self, SphereId id, const Vec3& target, float dt) { self.get().move_kinematic(id, target, dt); },
      arg("handle"), arg("target"), arg("dt"),
      "Sets a kinematic sphere's velocity so that a step of dt ends it at target.");
  c.def(
      "set_positions",
      [](Self self, const py::handle& handles, const py::handle& positions) {
        const std::vector<SphereId> ids = handle_list(handles);
        const std::vector<Vec3> v = vec3_rows(positions, ids.size(), "positions");
        self.get().set_positions(ids, v);
      },
      arg("handles"), arg("positions"),
      "Batch set_position: handles (n,) and (n, 3) values; all checked first, then all applied.");
  c.def(
      "set_velocities",
      [](Self self, const py::handle& handles, const py::handle& velocities) {
        const std::vector<SphereId> ids = handle_list(handles);
        const std::vector<Vec3> v = vec3_rows(velocities, ids.size(), "velocities");
        self.get().set_velocities(ids, v);
      },
      arg("handles"), arg("velocities"), "Batch set_velocity (all checked first).");
  c.def(
      "apply_impulses",
      [](Self self, const py::handle& handles, const py::handle& impulses) {
        const std::vector<SphereId> ids = handle_list(handles);
        const std::vector<Vec3> v = vec3_rows(impulses, ids.size(), "impulses");
        self.get().apply_impulses(ids, v);
      },
      arg("handles"), arg("impulses"), "Batch apply_impulse (all checked first; a handle twice adds both).");
  c.def(
      "set_ground_filter",
      [](Self self, std::uint32_t category, std::uint32_t mask) {
        self.get().set_ground_filter(CollisionFilter{category, mask});
      },
      arg("category") = kDefaultCategory, arg("mask") = kAllCategories,
      "The collision filter of the terrain and every plane together.");
  c.def(
      "shift_origin", [](Self self, const Vec3& offset) { self.get().shift_origin(offset); }, arg("offset"),
      "Moves the world's origin to offset (every position becomes position - offset).");

  c.def(
      "set_events",
      [](Self self, bool touch, bool hits, float hit_speed) {
        self.get().set_events(EventSettings{.touch = touch, .hits = hits, .hit_speed = hit_speed});
      },
      py::kw_only(), arg("touch") = false, arg("hits") = false, arg("hit_speed") = 1.0f,
      "set_events(*, touch=False, hits=False, hit_speed=1.0)\n\n"
      "Turns touch and hit events on or off; after each step touch_begin_events,\n"
      "touch_end_events and hit_events hold them (structured numpy arrays).");

  // Snapshots.
  c.def(
      "save",
      [](Self self) {
        std::vector<std::byte> bytes;
        self.get().save(bytes);
        return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      },
      "A snapshot of everything that decides the world's future, as bytes (docs/snapshot_format.md).");
  c.def(
      "restore",
      [](Self self, const py::buffer& snapshot) {
        const py::buffer_info info = snapshot.request();
        if (info.ndim > 1) throw py::type_error("hail.World.restore takes bytes (or another 1-D buffer)");
        self.get().restore(std::span<const std::byte>(static_cast<const std::byte*>(info.ptr),
                                                      static_cast<std::size_t>(info.size * info.itemsize)));
      },
      arg("snapshot"),
      "Makes this world the one saved (bitwise: the same steps then give the same states).\n"
      "hail.InvalidArgument, the world unchanged, for a truncated, corrupt or foreign snapshot.");
  c.def(
      "save_file", [](Self self, const std::string& path) { self.get().save_file(path); }, arg("path"),
      "save() into a file, atomically (hail.FileError when it cannot be written).");
  c.def(
      "restore_file", [](Self self, const std::string& path) { self.get().restore_file(path); }, arg("path"),
      "restore() from a file (hail.FileError when it cannot be read).");

  // Figures.
  c.def(
      "state_hash", [](Self self) { return self.get().state_hash(); },
      "FNV-1a over the positions and velocities in slot order: equal hashes, bitwise equal states.\n"
      "hail-bench prints it as 16 hex digits: f'{world.state_hash():016x}'.");
  c.def(
      "kinetic_energy", [](Self self) { return self.get().kinetic_energy(); },
      "Translational + rotational kinetic energy of the movable spheres, J.");
  c.def(
      "linear_momentum",
      [](Self self) {
        const Eigen::Vector3d p = self.get().linear_momentum();
        return py::make_tuple(p.x(), p.y(), p.z());
      },
      "Total linear momentum of the movable spheres, kg m/s.");
  c.def(
      "nan_count", [](Self self) { return self.get().nan_count(); },
      "Number of non-finite position or velocity components.");
  c.def(
      "query_cache_builds", [](Self self) { return self.get().query_cache_builds(); },
      "How many times the query BVH over the spheres has been built.");
  c.def(
      "memory_use",
      [](Self self) {
        const MemoryUse m = self.get().memory_use();
        py::dict d;
        m.for_each_part([&](const char* name, std::size_t bytes) { d[name] = bytes; });
        d["total"] = m.total();
        return d;
      },
      "Heap bytes the World holds, by part (World::memory_use): spheres, pairs, contacts, solver,\n"
      "warm_start, sweep, per_sphere, services, and their total. Capacities, not sizes.");
  c.def(
      "last_step_stats",
      [](Self self) {
        const StepStats& s = self.get().last_step_stats();
        static const char* kSearch[] = {"auto", "brute", "grid", "sweep", "bvh"};
        py::dict d;
        d["static_contacts"] = s.static_contacts;
        d["sphere_contacts"] = s.sphere_contacts;
        d["colours"] = s.colours;
        d["tile_contacts"] = s.tile_contacts;
        d["shared_contacts"] = s.shared_contacts;
        d["collision_passes"] = s.collision_passes;
        d["depenetration_passes"] = s.depenetration_passes;
        d["pair_search"] = kSearch[static_cast<int>(s.pair_search)];
        d["warm_started"] = s.warm_started;
        d["sweep_fast"] = s.sweep.fast;
        d["sweep_swept"] = s.sweep.swept;
        d["sweep_events"] = s.sweep.events;
        d["sweep_capped"] = s.sweep.capped;
        d["sweep_held"] = s.sweep.held;
        d["sphere_contacts_capped"] = s.sphere_contacts_capped;
        d["pushed_out"] = s.pushed_out;
        d["lifted_out"] = s.lifted_out;
        d["timed_bounces"] = s.timed_bounces;
        d["parallel_loops"] = s.parallel_loops;
        d["crew_stages"] = s.crew_stages;
        d["sleeping"] = s.sleeping;
        d["ready_to_sleep"] = s.ready_to_sleep;
        return d;
      },
      "The last step's counters (StepStats) as a dict.");
  c.def(
      "last_phase_times",
      [](Self self) {
        const PhaseTimes& t = self.get().last_phase_times();
        py::dict d;
        d["reorder"] = t.reorder;
        d["predict"] = t.predict;
        d["detect_terrain"] = t.detect_terrain;
        d["detect_pairs"] = t.detect_pairs;
        d["solve"] = t.solve;
        d["sweep"] = t.sweep;
        d["integrate"] = t.integrate;
        d["depenetrate"] = t.depenetrate;
        d["islands"] = t.islands;
        d["total"] = t.total();
        return d;
      },
      "Wall-clock milliseconds of each phase of the last step, and their total.");
  c.def("__repr__", [](Self self) {
    return "<hail.World: " + std::to_string(self.get().sphere_count()) + " spheres, " +
           std::to_string(self.get().planes().size()) + " planes" + (self.get().terrain() ? ", terrain" : "") + ">";
  });
  (void)m;
}

}  // namespace hail::python
