#pragma once
// Touch and hit events: what a game asks after each step ("which spheres started or stopped
// touching what", "what hit what, how hard") as three arrays, not per-contact callbacks
// (World::set_events, World::touch_begin_events, touch_end_events, hit_events). Box2D v3's
// b2World_GetContactEvents is the model: the step fills the arrays, the game walks them.
//
// Spheres are named by handle (SphereId): dense slots move with the Morton re-sort. Each array
// is sorted by its keys (sphere pairs by their two handle indices, then ground contacts by the
// sphere's handle index and the surface), so it is bitwise the same for any thread count.
// The rules (what touching means, what counts as a hit) are written at
// World::set_events (include/hail/world.h); the state is kernel/world/contact_events.h.

#include <cstdint>

#include "hail/sphere_soa.h"
#include "hail/vec3.h"

namespace hail {

/// What the sphere of an event touches or hits.
enum class ContactWith : std::uint8_t {
  Sphere,   ///< another sphere: TouchEvent::b / HitEvent::b
  Terrain,  ///< the World's terrain
  Plane,    ///< a plane: the event's `surface` is its index in World::planes()
  Mesh,     ///< a mesh: the event's `surface` is its index (World::add_mesh's result)
};

/// Off by default: a World that never calls set_events pays nothing for them (no pass, no
/// memory). Touch and hits are separate: a game that only plays sounds wants hits alone.
struct EventSettings {
  bool touch = false;      ///< touch_begin_events / touch_end_events after each step
  bool hits = false;       ///< hit_events after each step
  float hit_speed = 1.0f;  ///< m/s, finite and >= 0: an impact is a hit when it closes faster than this
};

/// Two spheres, or a sphere and the ground, began or stopped touching in the last step.
struct TouchEvent {
  SphereId a{};  ///< the sphere; of a pair, the one with the lower handle index
  SphereId b{};  ///< with == Sphere: the other sphere (higher handle index); else SphereId{} (no sphere)
  ContactWith with = ContactWith::Sphere;
  std::uint32_t surface = 0;  ///< with == Plane or Mesh: the plane's or mesh's index; else 0
};

/// An impact in the last step that closed faster than EventSettings::hit_speed.
struct HitEvent {
  SphereId a{};  ///< the sphere; of a pair, the one with the lower handle index
  SphereId b{};  ///< with == Sphere: the other sphere; else SphereId{}
  ContactWith with = ContactWith::Sphere;
  /// with == Plane or Mesh: the plane's or mesh's index; with == Terrain: the triangle
  /// (Terrain::triangles() order, as Contact::feature); else 0.
  std::uint32_t surface = 0;
  /// m/s, > 0: the speed at which the surfaces approached along the normal just before the
  /// impact, (v_a - v_b) . normal.
  float approach_speed = 0.0f;
  Vec3 point{0.0f, 0.0f, 0.0f};   ///< m: on a's surface towards b (see World::set_events)
  Vec3 normal{0.0f, 1.0f, 0.0f};  ///< unit, from a towards b (into the ground)
};

}  // namespace hail
