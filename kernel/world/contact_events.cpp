// ContactEventTracker: touch and hit events from each substep's contacts and impacts
// (kernel/world/contact_events.h has the rules).

#include "kernel/world/contact_events.h"

#include <algorithm>

#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/world/sleep_islands.h"
#include "soa/grow.h"

namespace hail {

namespace {

constexpr std::uint32_t kTerrainSurface = 0;  // TouchKey ground surface; plane k is 1 + k
constexpr std::uint32_t kMeshSurface = 0x80000000u;  // or'd with the mesh's index

TouchKey pair_key(SphereId x, SphereId y) {
  if (y.index < x.index) std::swap(x, y);
  return {(std::uint64_t{x.index} << 32) | y.index, (std::uint64_t{x.generation} << 32) | y.generation};
}

TouchKey ground_key(SphereId x, std::uint32_t surface) {
  return {(std::uint64_t{x.index} << 32) | surface, x.generation};
}

SphereId first_of(const TouchKey& k) {
  return {static_cast<std::uint32_t>(k.key >> 32), static_cast<std::uint32_t>(k.generations >> 32)};
}
SphereId second_of(const TouchKey& k) {
  return {static_cast<std::uint32_t>(k.key), static_cast<std::uint32_t>(k.generations)};
}

TouchEvent pair_event(const TouchKey& k) { return {.a = first_of(k), .b = second_of(k)}; }

TouchEvent ground_event(const TouchKey& k) {
  const auto surface = static_cast<std::uint32_t>(k.key);
  const ContactWith with = surface == kTerrainSurface ? ContactWith::Terrain
                           : (surface & kMeshSurface) ? ContactWith::Mesh
                                                      : ContactWith::Plane;
  const std::uint32_t index = with == ContactWith::Terrain ? 0u
                              : with == ContactWith::Mesh  ? surface & ~kMeshSurface
                                                           : surface - 1u;
  return {.a = {static_cast<std::uint32_t>(k.key >> 32), static_cast<std::uint32_t>(k.generations)},
          .with = with,
          .surface = index};
}

/// Whether a contact, after its substep's solve, counts as touching (the rule in the header).
bool touching(const Contact& c) { return !holds_no_impulse(c) || c.bounce_impulse > 0.0f || c.gap <= 0.0f; }

bool strictly_increasing(std::span<const TouchKey> keys) {
  return std::adjacent_find(keys.begin(), keys.end(), [](const TouchKey& x, const TouchKey& y) { return !(x < y); }) ==
         keys.end();
}

}  // namespace

void ContactEventTracker::configure(const EventSettings& settings) {
  if (!settings.touch) {
    previous_pairs_.clear();
    previous_ground_.clear();
    begin_events_.clear();
    end_events_.clear();
  }
  if (!settings.hits) {
    hit_records_.clear();
    hit_events_.clear();
  }
  settings_ = settings;
}

void ContactEventTracker::begin_step() {
  current_pairs_.clear();
  current_ground_.clear();
  begin_events_.clear();
  end_events_.clear();
  hit_records_.clear();
  hit_events_.clear();
}

void ContactEventTracker::remember_solve_start(const SphereSoA& s, const float* gravity_dt) {
  const std::size_t n = s.size();
  auto keep = [&](std::vector<float>& out, const AlignedArray<float>& in) {
    resize_geometric(out, n);
    std::copy(in.data(), in.data() + n, out.begin());
  };
  keep(start_px_, s.px), keep(start_py_, s.py), keep(start_pz_, s.pz);
  keep(start_vx_, s.vx), keep(start_vy_, s.vy), keep(start_vz_, s.vz);
  if (!gravity_dt) return;
  for (std::size_t i = 0; i < n; ++i) {
    const float scale = s.inv_mass[i] > 0.0f ? s.gravity_scale[i] : 0.0f;  // as predict added it
    start_vx_[i] -= gravity_dt[0] * scale, start_vy_[i] -= gravity_dt[1] * scale, start_vz_[i] -= gravity_dt[2] * scale;
  }
}

std::uint32_t ContactEventTracker::surface_code(std::uint32_t feature) const {
  if (feature & kPlaneFeature) return 1u + (feature & ~kPlaneFeature);
  if ((feature & kMeshFeature) && meshes_) return kMeshSurface | meshes_->mesh_of(feature);
  return kTerrainSurface;
}

void ContactEventTracker::add_touch(const SphereSoA& s, std::uint32_t a, std::uint32_t b, std::uint32_t feature) {
  if (b != kStaticBody)
    current_pairs_.push_back(pair_key(s.id_at(a), s.id_at(b)));
  else
    current_ground_.push_back(ground_key(s.id_at(a), surface_code(feature)));
}

void ContactEventTracker::collect_substep(const SphereSoA& s, std::span<const Contact> contacts,
                                          std::span<const Impact> impacts, const EventSurfaces& surfaces) {
  meshes_ = surfaces.meshes;
  if (settings_.touch) {
    reserve_geometric(current_pairs_, current_pairs_.size() + contacts.size() + impacts.size());
    reserve_geometric(current_ground_, current_ground_.size() + contacts.size() + impacts.size());
    for (const Contact& c : contacts)
      if (touching(c)) add_touch(s, c.a, c.b, c.feature);
    for (const Impact& i : impacts) add_touch(s, i.a, i.b, i.feature);
  }
  if (settings_.hits) {
    contact_hits(s, contacts);
    impact_hits(s, impacts, surfaces);
  }
}

void ContactEventTracker::add_hit(const SphereSoA& s, std::uint32_t a, std::uint32_t b, std::uint32_t feature,
                                  float speed, const Vec3& point, const Vec3& normal) {
  HitRecord r;
  r.sequence = static_cast<std::uint32_t>(hit_records_.size());
  r.event.approach_speed = speed;
  r.event.point = point;
  r.event.normal = normal;
  SphereId first = s.id_at(a);
  if (b != kStaticBody) {
    SphereId second = s.id_at(b);
    if (second.index < first.index) {  // a is the lower handle index: the normal turns with it
      std::swap(first, second);
      r.event.normal = -normal;
    }
    r.key = pair_key(first, second).key;
    r.event.b = second;
  } else {
    r.kind = 1;
    r.key = ground_key(first, surface_code(feature)).key;
    const std::uint32_t surface = surface_code(feature);
    r.event.with = (feature & kPlaneFeature)  ? ContactWith::Plane
                   : (surface & kMeshSurface) ? ContactWith::Mesh
                                              : ContactWith::Terrain;
    r.event.surface = r.event.with == ContactWith::Mesh ? surface & ~kMeshSurface : feature & ~kPlaneFeature;
  }
  r.event.a = first;
  reserve_geometric(hit_records_, hit_records_.size() + 1);
  hit_records_.push_back(r);
}

/// A contact the collision passes bounced (bounce_impulse > 0), closing before the solve faster
/// than hit_speed. The point: a's centre at the start of the solve plus the normal times its
/// radius and the gap (on the ground), or half the gap (between two spheres).
void ContactEventTracker::contact_hits(const SphereSoA& s, std::span<const Contact> contacts) {
  for (const Contact& c : contacts) {
    if (!(c.bounce_impulse > 0.0f)) continue;
    const bool pair = c.b != kStaticBody;
    float vx = start_vx_[c.a], vy = start_vy_[c.a], vz = start_vz_[c.a];
    if (pair) vx -= start_vx_[c.b], vy -= start_vy_[c.b], vz -= start_vz_[c.b];
    const float speed = vx * c.nx + vy * c.ny + vz * c.nz;
    if (!(speed > settings_.hit_speed)) continue;
    const float reach = s.radius[c.a] + (pair ? 0.5f * c.gap : c.gap);
    const Vec3 normal(c.nx, c.ny, c.nz);
    const Vec3 point(start_px_[c.a] + c.nx * reach, start_py_[c.a] + c.ny * reach, start_pz_[c.a] + c.nz * reach);
    add_hit(s, c.a, c.b, c.feature, speed, point, normal);
  }
}

/// An impact's approach speed from its impulse, undoing solve_impact (kernel/solver/
/// contact_impulse.h): j = (1 + e) v / (1/m_a + 1/m_b), with e = 0 when v was no faster than the
/// restitution threshold. v = j k / (1 + e) is above the threshold exactly when e was used
/// (else it is j k). Exact but for rounding: within a few ulps of the speed solve_impact saw.
void ContactEventTracker::impact_hits(const SphereSoA& s, std::span<const Impact> impacts,
                                      const EventSurfaces& surfaces) {
  for (const Impact& i : impacts) {
    const bool pair = i.b != kStaticBody;
    float other_restitution = surfaces.terrain_restitution, k = s.inv_mass[i.a];
    if (pair) {
      other_restitution = s.restitution[i.b];
      k += s.inv_mass[i.b];
    } else if (i.feature & kPlaneFeature) {
      other_restitution = surfaces.planes[i.feature & ~kPlaneFeature].restitution;
    } else if ((i.feature & kMeshFeature) && surfaces.meshes) {
      other_restitution = (*surfaces.meshes)[surfaces.meshes->mesh_of(i.feature)].restitution;
    }
    const float e = combine_restitution(s.restitution[i.a], other_restitution);
    const float stopped = i.impulse * k, bounced = stopped / (1.0f + e);
    const float speed = bounced > surfaces.restitution_threshold ? bounced : stopped;
    if (!(speed > settings_.hit_speed)) continue;
    add_hit(s, i.a, i.b, i.feature, speed, Vec3(i.px, i.py, i.pz), Vec3(i.nx, i.ny, i.nz));
  }
}

void ContactEventTracker::merge_touches(std::vector<TouchKey>& current, std::vector<TouchKey>& previous, bool pairs) {
  std::sort(current.begin(), current.end());
  current.erase(std::unique(current.begin(), current.end()), current.end());
  reserve_geometric(begin_events_, begin_events_.size() + current.size());
  reserve_geometric(end_events_, end_events_.size() + previous.size());
  auto event = [&](const TouchKey& k) { return pairs ? pair_event(k) : ground_event(k); };
  auto now = current.begin(), before = previous.begin();
  while (now != current.end() || before != previous.end()) {
    if (before == previous.end() || (now != current.end() && *now < *before)) {
      begin_events_.push_back(event(*now++));
    } else if (now == current.end() || *before < *now) {
      end_events_.push_back(event(*before++));
    } else {
      ++now, ++before;
    }
  }
  std::swap(current, previous);
}

void ContactEventTracker::keep_sleepers_touching(const SphereSoA& s) {
  if (!settings_.touch) return;
  for (const TouchKey& k : previous_pairs_) {
    const std::int64_t a = s.slot_of(first_of(k)), b = s.slot_of(second_of(k));
    if (a >= 0 && b >= 0 && sleeping_contact(s, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)))
      current_pairs_.push_back(k);
  }
  for (const TouchKey& k : previous_ground_) {
    const std::int64_t a = s.slot_of(ground_event(k).a);
    if (a >= 0 && sphere_sleeps(s, static_cast<std::size_t>(a))) current_ground_.push_back(k);
  }
}

void ContactEventTracker::finish_step() {
  if (settings_.touch) {
    merge_touches(current_pairs_, previous_pairs_, true);
    merge_touches(current_ground_, previous_ground_, false);
  }
  if (settings_.hits) {
    std::sort(hit_records_.begin(), hit_records_.end(), [](const HitRecord& x, const HitRecord& y) {
      if (x.kind != y.kind) return x.kind < y.kind;
      if (x.key != y.key) return x.key < y.key;
      return x.sequence < y.sequence;
    });
    resize_geometric(hit_events_, hit_records_.size());
    for (std::size_t k = 0; k < hit_records_.size(); ++k) hit_events_[k] = hit_records_[k].event;
  }
}

void ContactEventTracker::finish_idle_step(const SphereSoA& s) {
  begin_step();
  if (!settings_.touch) return;
  auto alive = [&](std::vector<TouchKey>& previous, std::vector<TouchKey>& current, bool pairs) {
    reserve_geometric(current, previous.size());
    for (const TouchKey& k : previous) {
      const bool live = pairs ? s.contains(first_of(k)) && s.contains(second_of(k)) : s.contains(ground_event(k).a);
      if (live) current.push_back(k);
    }
  };
  alive(previous_pairs_, current_pairs_, true);
  alive(previous_ground_, current_ground_, false);
  merge_touches(current_pairs_, previous_pairs_, true);
  merge_touches(current_ground_, previous_ground_, false);
}

bool ContactEventTracker::restore_touching(std::span<const TouchKey> pairs, std::span<const TouchKey> ground) {
  if (!strictly_increasing(pairs) || !strictly_increasing(ground)) return false;
  begin_step();
  previous_pairs_.assign(pairs.begin(), pairs.end());
  previous_ground_.assign(ground.begin(), ground.end());
  return true;
}

}  // namespace hail
