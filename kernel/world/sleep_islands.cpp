#include "kernel/world/sleep_islands.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "soa/grow.h"

namespace hail {

namespace {
/// Sleepers within this share of (r_a + r_b) of an immovable sphere's surface count as touching
/// it: resting contacts sit within the depenetration's 1% slop, so a tenth is ample.
constexpr float kNearFraction = 0.1f;

/// Handles sorted by index, each once.
void sort_unique(std::vector<SphereId>& ids) {
  std::sort(ids.begin(), ids.end(), [](SphereId a, SphereId b) { return a.index < b.index; });
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

/// |w x n|^2: the square of how fast spin w slides the surface past a contact of normal n, over
/// the radius. Spin about n itself (a twist in place) slides nothing.
[[nodiscard]] float slide2(float wx, float wy, float wz, const Contact& c) {
  const float x = wy * c.nz - wz * c.ny, y = wz * c.nx - wx * c.nz, z = wx * c.ny - wy * c.nx;
  return x * x + y * y + z * z;
}
}  // namespace

std::uint32_t SleepIslands::find(std::uint32_t i) {
  while (parent_[i] != i) {
    parent_[i] = parent_[parent_[i]];  // path halving
    i = parent_[i];
  }
  return i;
}

void SleepIslands::unite(std::uint32_t a, std::uint32_t b) {
  a = find(a), b = find(b);
  // The smaller slot is the root: the partition's roots do not depend on the contact order.
  if (a < b)
    parent_[b] = a;
  else if (b < a)
    parent_[a] = b;
}

void SleepIslands::wake_slot(SphereSoA& s, std::size_t i) {
  s.flags[i] &= ~static_cast<std::uint32_t>(kSphereFlagSleeping);
  s.sleep_timer[i] = 0.0f;
  s.sleep_island[i] = 0;
  woken_.push_back(s.id_at(i));
  woken_slots_.push_back(static_cast<std::uint32_t>(i));
}

bool SleepIslands::wake_labels(SphereSoA& s) {
  if (labels_.empty()) return false;
  std::sort(labels_.begin(), labels_.end());
  labels_.erase(std::unique(labels_.begin(), labels_.end()), labels_.end());
  bool woke = false;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (sphere_sleeps(s, i) && std::binary_search(labels_.begin(), labels_.end(), s.sleep_island[i])) {
      wake_slot(s, i);
      woke = true;
    }
  labels_.clear();
  return woke;
}

bool SleepIslands::wake_touched(SphereSoA& s, std::span<const Contact> contacts) {
  woken_slots_.clear();
  for (const Contact& c : contacts) {
    if (c.b == kStaticBody) continue;
    if (sphere_sleeps(s, c.a) && sphere_moves(s, c.b)) labels_.push_back(s.sleep_island[c.a]);
    if (sphere_sleeps(s, c.b) && sphere_moves(s, c.a)) labels_.push_back(s.sleep_island[c.b]);
  }
  return wake_labels(s);
}

bool SleepIslands::wake_hit(SphereSoA& s, std::span<const Impact> impacts) {
  for (const Impact& hit : impacts) {
    if (sphere_sleeps(s, hit.a)) labels_.push_back(s.sleep_island[hit.a]);
    if (hit.b != kStaticBody && sphere_sleeps(s, hit.b)) labels_.push_back(s.sleep_island[hit.b]);
  }
  return wake_labels(s);
}

void SleepIslands::wake_around(SphereSoA& s, std::size_t slot) {
  if (sphere_sleeps(s, slot)) labels_.push_back(s.sleep_island[slot]);
  if (!(s.inv_mass[slot] > 0.0f)) {
    const float x = s.px[slot], y = s.py[slot], z = s.pz[slot], r = s.radius[slot];
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!sphere_sleeps(s, i)) continue;
      const float dx = s.px[i] - x, dy = s.py[i] - y, dz = s.pz[i] - z;
      const float reach = (1.0f + kNearFraction) * (r + s.radius[i]);
      if (dx * dx + dy * dy + dz * dz <= reach * reach) labels_.push_back(s.sleep_island[i]);
    }
  }
  wake_labels(s);
}

void SleepIslands::wake_all(SphereSoA& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    if (sphere_sleeps(s, i)) wake_slot(s, i);
}

std::size_t SleepIslands::count_sleeping(const SphereSoA& s) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < s.size(); ++i) count += sphere_sleeps(s, i) ? 1 : 0;
  return count;
}

bool SleepIslands::anything_moves(const SphereSoA& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    if (sphere_moves(s, i)) return true;
  return false;
}

void SleepIslands::update(SphereSoA& s, std::span<const Contact> contacts, float dt, const WorldSettings& settings) {
  const std::size_t n = s.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  resize_geometric(parent_, n);
  resize_geometric(spin2_, n);
  resize_geometric(touches_static_, n);
  for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
  std::fill(spin2_.begin(), spin2_.begin() + count, -1.0f);  // no loaded contact: all of the spin counts
  std::fill(touches_static_.begin(), touches_static_.begin() + count, std::uint8_t{0});
  // One pass over the contacts: the islands (movable spheres joined), what touches the ground,
  // a plane or an immovable sphere, and the spin that slides each sphere's loaded contacts.
  for (const Contact& c : contacts) {
    if (c.b == kStaticBody || !(s.inv_mass[c.b] > 0.0f))
      touches_static_[c.a] = 1;
    else if (!(s.inv_mass[c.a] > 0.0f))
      touches_static_[c.b] = 1;
    else
      unite(c.a, c.b);
    if (!(c.normal_impulse > 0.0f)) continue;  // touching without load: it holds the spin to nothing
    spin2_[c.a] = std::max(spin2_[c.a], slide2(s.wx[c.a], s.wy[c.a], s.wz[c.a], c));
    if (c.b != kStaticBody) spin2_[c.b] = std::max(spin2_[c.b], slide2(s.wx[c.b], s.wy[c.b], s.wz[c.b], c));
  }
  // Per island (at its root): the smallest timer, the smallest handle index, and whether it is
  // supported (some sphere of it touches something static).
  const float linear2 = settings.sleep_linear_speed * settings.sleep_linear_speed;
  const float angular2 = settings.sleep_angular_speed * settings.sleep_angular_speed;
  resize_geometric(supported_, n);
  resize_geometric(island_timer_, n);
  resize_geometric(island_label_, n);
  std::fill(supported_.begin(), supported_.begin() + count, std::uint8_t{0});
  std::fill(island_timer_.begin(), island_timer_.begin() + count, std::numeric_limits<float>::infinity());
  std::fill(island_label_.begin(), island_label_.begin() + count, std::numeric_limits<std::uint32_t>::max());
  islands_ = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(s.inv_mass[i] > 0.0f) || sphere_sleeps(s, i)) continue;
    const float v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
    const float w2 = spin2_[i] >= 0.0f ? spin2_[i] : s.wx[i] * s.wx[i] + s.wy[i] * s.wy[i] + s.wz[i] * s.wz[i];
    s.sleep_timer[i] = v2 > linear2 || w2 > angular2 ? 0.0f : s.sleep_timer[i] + dt;
    const std::uint32_t root = find(static_cast<std::uint32_t>(i));
    island_timer_[root] = std::min(island_timer_[root], s.sleep_timer[i]);
    island_label_[root] = std::min(island_label_[root], s.id_at(i).index);
    supported_[root] |= touches_static_[i];
    if (root == i) ++islands_;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(s.inv_mass[i] > 0.0f) || sphere_sleeps(s, i)) continue;
    const std::uint32_t root = find(static_cast<std::uint32_t>(i));
    if (!(island_timer_[root] >= settings.sleep_time) || !supported_[root]) continue;
    s.flags[i] |= kSphereFlagSleeping;
    s.sleep_island[i] = island_label_[root];
    s.vx[i] = s.vy[i] = s.vz[i] = 0.0f;
    s.wx[i] = s.wy[i] = s.wz[i] = 0.0f;
    slept_.push_back(s.id_at(i));
  }
}

void SleepIslands::publish() {
  sort_unique(slept_);
  sort_unique(woken_);
  std::swap(published_slept_, slept_);
  std::swap(published_woken_, woken_);
  slept_.clear();
  woken_.clear();
}

void SleepIslands::clear_events() {
  slept_.clear(), woken_.clear(), published_slept_.clear(), published_woken_.clear();
}

}  // namespace hail
