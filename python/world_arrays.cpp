// The World's arrays as numpy arrays: per-sphere views with no copy (read-only, the World their
// base), (n, 3) copies where the SoA keeps x, y and z apart, and the last step's contacts,
// impacts and events as structured arrays (copies: they change with every step).

#include <cstddef>
#include <cstring>

#include "bindings.h"

namespace hail::python {
namespace {

using Self = PyWorld&;

/// A structured numpy array of `count` records copied from `records`, with this dtype.
template <class T>
py::array copy_records(std::span<const T> records, const py::dtype& dtype) {
  if (dtype.itemsize() != static_cast<py::ssize_t>(sizeof(T))) throw std::logic_error("hail: dtype size mismatch");
  py::array out(dtype, py::array::ShapeContainer{static_cast<py::ssize_t>(records.size())});
  if (!records.empty()) std::memcpy(out.mutable_data(), records.data(), records.size_bytes());
  return out;
}

/// A member's byte offset, from an object (offsetof is only conditionally supported on the
/// event records: their Eigen vectors make them non-standard-layout).
template <class T, class M>
std::size_t field_offset(M T::*member) {
  static const T probe{};
  return static_cast<std::size_t>(reinterpret_cast<const char*>(&(probe.*member)) -
                                  reinterpret_cast<const char*>(&probe));
}

py::dtype record_dtype(std::vector<std::pair<const char*, const char*>> fields, std::vector<std::size_t> offsets,
                       std::size_t itemsize) {
  py::list names, formats, offs;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    names.append(fields[k].first);
    formats.append(fields[k].second);
    offs.append(offsets[k]);
  }
  py::dict spec;
  spec["names"] = names;
  spec["formats"] = formats;
  spec["offsets"] = offs;
  spec["itemsize"] = itemsize;
  return py::dtype::from_args(spec);
}

// The dtypes live as long as the process (never destroyed: a Python object released after the
// interpreter has finalised would crash the exit).
// "with" values of TouchEvent / HitEvent: 0 sphere, 1 terrain, 2 plane (hail.CONTACT_WITH).
const py::dtype& touch_dtype() {
  static const py::dtype& d = *new py::dtype(record_dtype({{"a", "<u8"}, {"b", "<u8"}, {"with", "u1"}, {"surface", "<u4"}},
                                          {field_offset(&TouchEvent::a), field_offset(&TouchEvent::b),
                                           field_offset(&TouchEvent::with), field_offset(&TouchEvent::surface)},
                                          sizeof(TouchEvent)));
  return d;
}
const py::dtype& hit_dtype() {
  static const py::dtype& d = *new py::dtype(record_dtype(
      {{"a", "<u8"}, {"b", "<u8"}, {"with", "u1"}, {"surface", "<u4"}, {"approach_speed", "<f4"},
       {"point", "(3,)<f4"}, {"normal", "(3,)<f4"}},
      {field_offset(&HitEvent::a), field_offset(&HitEvent::b), field_offset(&HitEvent::with), field_offset(&HitEvent::surface),
       field_offset(&HitEvent::approach_speed), field_offset(&HitEvent::point), field_offset(&HitEvent::normal)},
      sizeof(HitEvent)));
  return d;
}
const py::dtype& contact_dtype() {
  static const py::dtype& d = *new py::dtype(record_dtype(
      {{"a", "<u4"}, {"b", "<u4"}, {"normal", "(3,)<f4"}, {"gap", "<f4"}, {"restitution", "<f4"},
       {"friction", "<f4"}, {"normal_impulse", "<f4"}, {"friction_impulse", "(3,)<f4"}, {"bounce_impulse", "<f4"},
       {"feature", "<u4"}},
      {field_offset(&Contact::a), field_offset(&Contact::b), field_offset(&Contact::nx), field_offset(&Contact::gap),
       field_offset(&Contact::restitution), field_offset(&Contact::friction), field_offset(&Contact::normal_impulse),
       field_offset(&Contact::tx), field_offset(&Contact::bounce_impulse), field_offset(&Contact::feature)},
      sizeof(Contact)));
  return d;
}
const py::dtype& impact_dtype() {
  static const py::dtype& d = *new py::dtype(record_dtype(
      {{"a", "<u4"}, {"b", "<u4"}, {"feature", "<u4"}, {"time", "<f4"}, {"point", "(3,)<f4"},
       {"normal", "(3,)<f4"}, {"impulse", "<f4"}},
      {field_offset(&Impact::a), field_offset(&Impact::b), field_offset(&Impact::feature), field_offset(&Impact::time),
       field_offset(&Impact::px), field_offset(&Impact::nx), field_offset(&Impact::impulse)},
      sizeof(Impact)));
  return d;
}

py::array handles_copy(std::span<const SphereId> ids) {
  py::array_t<std::uint64_t> out(static_cast<py::ssize_t>(ids.size()));
  for (std::size_t k = 0; k < ids.size(); ++k) out.mutable_at(static_cast<py::ssize_t>(k)) = pack(ids[k]);
  return out;
}

/// (n, 3) float32 copy of three component arrays.
py::array stack3(const AlignedArray<float>& x, const AlignedArray<float>& y, const AlignedArray<float>& z,
                 std::size_t n) {
  py::array_t<float> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  float* o = out.mutable_data();
  for (std::size_t k = 0; k < n; ++k) {
    o[3 * k] = x[k];
    o[3 * k + 1] = y[k];
    o[3 * k + 2] = z[k];
  }
  return out;
}

/// A read-only view property over one SphereSoA array.
template <auto Member>
void view_property(py::class_<PyWorld>& c, const char* name, const char* doc) {
  c.def_property_readonly(
      name,
      [](py::object owner) {
        World& w = owner.cast<PyWorld&>().get();
        const auto& array = w.soa().*Member;
        return read_only_view(array.data(), w.sphere_count(), owner);
      },
      doc);
}

}  // namespace

void bind_world_arrays(py::module_& m, py::class_<PyWorld>& c) {
  m.attr("WITH_SPHERE") = static_cast<int>(ContactWith::Sphere);
  m.attr("WITH_TERRAIN") = static_cast<int>(ContactWith::Terrain);
  m.attr("WITH_PLANE") = static_cast<int>(ContactWith::Plane);
  m.attr("WITH_MESH") = static_cast<int>(ContactWith::Mesh);
  m.attr("STATIC_BODY") = kStaticBody;
  m.attr("FLAG_KINEMATIC") = static_cast<std::uint32_t>(kSphereFlagKinematic);
  m.attr("FLAG_SLEEPING") = static_cast<std::uint32_t>(kSphereFlagSleeping);
  m.attr("touch_event_dtype") = touch_dtype();
  m.attr("hit_event_dtype") = hit_dtype();
  m.attr("contact_dtype") = contact_dtype();
  m.attr("impact_dtype") = impact_dtype();

  // Views, slot order, no copy. Stale after add/remove (growth, the swap into a removed slot),
  // reserve and a restore of more spheres than there is room for; a step keeps them pointing
  // at live memory but may re-sort the slots (docs/python.md, "Arrays and when they go stale").
  view_property<&SphereSoA::px>(c, "px", "x of every centre, m (read-only view, slot order)");
  view_property<&SphereSoA::py>(c, "py", "y of every centre, m (read-only view, slot order)");
  view_property<&SphereSoA::pz>(c, "pz", "z of every centre, m (read-only view, slot order)");
  view_property<&SphereSoA::vx>(c, "vx", "x velocity, m/s (read-only view, slot order)");
  view_property<&SphereSoA::vy>(c, "vy", "y velocity, m/s (read-only view, slot order)");
  view_property<&SphereSoA::vz>(c, "vz", "z velocity, m/s (read-only view, slot order)");
  view_property<&SphereSoA::wx>(c, "wx", "x angular velocity, rad/s (read-only view, slot order)");
  view_property<&SphereSoA::wy>(c, "wy", "y angular velocity, rad/s (read-only view, slot order)");
  view_property<&SphereSoA::wz>(c, "wz", "z angular velocity, rad/s (read-only view, slot order)");
  view_property<&SphereSoA::radius>(c, "radii", "radius, m (read-only view, slot order)");
  view_property<&SphereSoA::inv_mass>(c, "inv_masses", "1 / mass, 1/kg; 0 static or kinematic (read-only view)");
  view_property<&SphereSoA::restitution>(c, "restitutions", "restitution (read-only view, slot order)");
  view_property<&SphereSoA::friction>(c, "frictions", "friction coefficient (read-only view, slot order)");
  view_property<&SphereSoA::gravity_scale>(c, "gravity_scales", "gravity scale (read-only view, slot order)");
  view_property<&SphereSoA::flags>(c, "flags", "flag bits: FLAG_KINEMATIC, FLAG_SLEEPING (read-only view)");
  view_property<&SphereSoA::user_data>(c, "user_data_values", "set_user_data's values (read-only view)");
  view_property<&SphereSoA::collision_category>(c, "categories", "collision category bits (read-only view)");
  view_property<&SphereSoA::collision_mask>(c, "masks", "collision mask bits (read-only view)");
  c.def_property_readonly(
      "handles",
      [](py::object owner) {
        World& w = owner.cast<PyWorld&>().get();
        const std::span<const SphereId> ids = w.handles();
        return read_only_view(reinterpret_cast<const std::uint64_t*>(ids.data()), ids.size(), owner);
      },
      "The handle of every slot, uint64 (read-only view): handles[k] is whose slot k is.");

  // (n, 3) copies: the SoA stores each axis in its own array, which no single view can span.
  c.def_property_readonly(
      "positions",
      [](Self self) {
        const World& w = self.get();
        return stack3(w.soa().px, w.soa().py, w.soa().pz, w.sphere_count());
      },
      "(n, 3) float32 centres, m, slot order (a copy; px, py, pz are views).");
  c.def_property_readonly(
      "velocities",
      [](Self self) {
        const World& w = self.get();
        return stack3(w.soa().vx, w.soa().vy, w.soa().vz, w.sphere_count());
      },
      "(n, 3) float32 velocities, m/s, slot order (a copy; vx, vy, vz are views).");
  c.def_property_readonly(
      "angular_velocities",
      [](Self self) {
        const World& w = self.get();
        return stack3(w.soa().wx, w.soa().wy, w.soa().wz, w.sphere_count());
      },
      "(n, 3) float32 angular velocities, rad/s, slot order (a copy; wx, wy, wz are views).");
  c.def_property_readonly(
      "sleeping",
      [](Self self) {
        const World& w = self.get();
        py::array_t<bool> out(static_cast<py::ssize_t>(w.sphere_count()));
        for (std::size_t k = 0; k < w.sphere_count(); ++k)
          out.mutable_at(static_cast<py::ssize_t>(k)) = (w.soa().flags[k] & kSphereFlagSleeping) != 0;
        return out;
      },
      "bool per slot: asleep (a copy).");

  c.def_property_readonly(
      "last_contacts",
      [](Self self) { return copy_records(self.get().last_contacts(), contact_dtype()); },
      "The last step's contacts, a structured array (hail.contact_dtype; a, b are slots, b is\n"
      "STATIC_BODY for the ground). A copy.");
  c.def_property_readonly(
      "last_impacts", [](Self self) { return copy_records(self.get().last_impacts(), impact_dtype()); },
      "The last step's impacts taken at their exact time (hail.impact_dtype). A copy.");
  c.def_property_readonly(
      "touch_begin_events", [](Self self) { return copy_records(self.get().touch_begin_events(), touch_dtype()); },
      "Touches that began in the last step: structured array (hail.touch_event_dtype) with a, b\n"
      "(handles; b is hail.NO_SPHERE for the ground), with (WITH_SPHERE, WITH_TERRAIN, WITH_PLANE,\n"
      "WITH_MESH) and surface (the plane's or mesh's index). Needs set_events(touch=True). A copy.");
  c.def_property_readonly(
      "touch_end_events", [](Self self) { return copy_records(self.get().touch_end_events(), touch_dtype()); },
      "Touches that ended in the last step (as touch_begin_events). A copy.");
  c.def_property_readonly(
      "hit_events", [](Self self) { return copy_records(self.get().hit_events(), hit_dtype()); },
      "Impacts of the last step faster than hit_speed (hail.hit_event_dtype: a, b, with, surface,\n"
      "approach_speed, point, normal). Needs set_events(hits=True). A copy.");
  c.def_property_readonly(
      "sleep_events", [](Self self) { return handles_copy(self.get().sleep_events()); },
      "Handles of the spheres that fell asleep in the last step (uint64, a copy).");
  c.def_property_readonly(
      "wake_events", [](Self self) { return handles_copy(self.get().wake_events()); },
      "Handles of the spheres woken since the step before the last (uint64, a copy).");
}

}  // namespace hail::python
