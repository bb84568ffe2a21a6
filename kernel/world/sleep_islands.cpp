#include "kernel/world/sleep_islands.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "jobs/parallel_blocks.h"
#include "soa/grow.h"

namespace hail {

namespace {
/// Sleepers within this share of (r_a + r_b) of an immovable sphere's surface count as touching
/// it: resting contacts sit within the depenetration's 1% slop, so a tenth is ample.
constexpr float kNearFraction = 0.1f;

/// Handles sorted by index, each once.
/// Blocks of the parallel passes. Their size changes no result (every update is order-free), only
/// how the work is handed out.
constexpr std::size_t kIslandSphereBlock = 2048;
constexpr std::size_t kIslandContactBlock = 4096;

/// What update() knows of a slot before it reads the contacts (sphere_class_, written by the
/// slot's own block only).
constexpr std::uint8_t kMovable = 1;      // inv_mass > 0: a contact with it joins islands
constexpr std::uint8_t kCandidate = 2;    // awake, slow, and its timer reaches sleep_time this substep if its
                                          // spin allows: only islands of candidates can sleep
constexpr std::uint8_t kNeedsSlides = 4;  // slow, and spinning faster than sleep_angular_speed: whether its
                                          // timer runs depends on the slide of its loaded contacts

/// What the contacts tell of a slot (contact_flags_, atomic ORs).
constexpr std::uint8_t kTouchesStatic = 1;  // a candidate touches the terrain, a plane or an immovable sphere
constexpr std::uint8_t kLoaded = 2;         // a contact with normal impulse > 0: spin2_ holds its largest slide
constexpr std::uint8_t kHeldAwake = 4;      // a candidate touches a movable sphere that is no candidate
constexpr std::uint8_t kSleptNow = 8;       // put to sleep by this update

/// What an island's spheres tell its root (root_flags_, atomic ORs).
constexpr std::uint8_t kSupported = 1;  // some sphere of it touches something static
constexpr std::uint8_t kBlocked = 2;    // some sphere of it is held awake, or its timer is short

/// Spins within this share of sleep_angular_speed (squared) decide a timer without the contacts:
/// the slide of a contact, |w x n|, is at most |w| for a unit n, and float rounding of the
/// cross product and of n's length moves it by a few ulps, far less than this.
constexpr float kSlideMargin = 1.0f - 1e-4f;

/// A float as an unsigned integer of the same order (negative ones too), so that the atomic
/// maximum below can compare slides as integers.
[[nodiscard]] constexpr std::uint32_t ordered_bits(float x) {
  const auto bits = std::bit_cast<std::uint32_t>(x);
  return (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
}
[[nodiscard]] constexpr float from_ordered_bits(std::uint32_t bits) {
  return std::bit_cast<float>((bits & 0x80000000u) != 0 ? bits & 0x7FFFFFFFu : ~bits);
}
static_assert(from_ordered_bits(ordered_bits(-2.5f)) == -2.5f && ordered_bits(-1.0f) < ordered_bits(0.0f) &&
              ordered_bits(0.5f) < ordered_bits(std::numeric_limits<float>::infinity()));

// Order-free atomic updates: a maximum, a minimum, an OR. Whatever order the threads apply
// them in, the result is the same. Each reads first and writes only when it changes the value:
// a locked write stalls the memory reads around it, and an island's root is read by every
// sphere of the island but changed by few.
void store_max(std::uint32_t& x, std::uint32_t value) {
  std::atomic_ref<std::uint32_t> ref(x);
  std::uint32_t seen = ref.load(std::memory_order_relaxed);
  while (value > seen && !ref.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

void store_min(std::uint32_t& x, std::uint32_t value) {
  std::atomic_ref<std::uint32_t> ref(x);
  std::uint32_t seen = ref.load(std::memory_order_relaxed);
  while (value < seen && !ref.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

void set_bits(std::uint8_t& x, std::uint8_t bits) {
  std::atomic_ref<std::uint8_t> ref(x);
  if ((ref.load(std::memory_order_relaxed) & bits) != bits) ref.fetch_or(bits, std::memory_order_relaxed);
}

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

// The union-find is shared by the threads of update(): every read and write of parent_ is
// atomic. A parent always has a smaller slot than its child (roots link under smaller roots),
// so the trees have no cycles whatever the threads interleave, and the root of an island is
// its smallest slot however its contacts were split between threads.
std::uint32_t SleepIslands::find(std::uint32_t i) {
  for (;;) {
    const std::uint32_t p = std::atomic_ref<std::uint32_t>(parent_[i]).load(std::memory_order_relaxed);
    if (p == i) return i;
    const std::uint32_t grandparent = std::atomic_ref<std::uint32_t>(parent_[p]).load(std::memory_order_relaxed);
    // Path halving. A non-root never becomes a root again, and grandparent is an ancestor of i
    // even if another thread has since linked i higher up: the store shortens, never breaks.
    if (grandparent != p) std::atomic_ref<std::uint32_t>(parent_[i]).store(grandparent, std::memory_order_relaxed);
    i = grandparent;
  }
}

void SleepIslands::unite(std::uint32_t a, std::uint32_t b) {
  for (;;) {
    a = find(a), b = find(b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    // The larger root goes under the smaller, if it is still a root; else look again.
    std::uint32_t expected = b;
    if (std::atomic_ref<std::uint32_t>(parent_[b]).compare_exchange_strong(expected, a, std::memory_order_relaxed))
      return;
  }
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
  // Nothing sleeps (a falling rain, a pile still moving): no contact can wake anything, and a
  // scan of the flags is a sixteenth of the memory of one of the contacts.
  if (!any_sleeping(s)) return false;
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
  std::size_t count = 0;  // branch-free: the compiler vectorises it
  for (std::size_t i = 0; i < s.size(); ++i) count += (s.flags[i] >> 1) & 1u;
  static_assert(kSphereFlagSleeping == 1u << 1);
  return count;
}

bool SleepIslands::any_sleeping(const SphereSoA& s) {
  constexpr std::size_t kChunk = 1024;  // branch-free within a chunk (vectorised), an exit after each
  for (std::size_t first = 0; first < s.size(); first += kChunk) {
    std::uint32_t any = 0;
    for (std::size_t i = first, last = std::min(s.size(), first + kChunk); i < last; ++i) any |= s.flags[i];
    if ((any & kSphereFlagSleeping) != 0) return true;
  }
  return false;
}

bool SleepIslands::anything_moves(const SphereSoA& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    if (sphere_moves(s, i)) return true;
  return false;
}

void SleepIslands::update(SphereSoA& s, std::span<const Contact> contacts, float dt, const WorldSettings& settings) {
  const std::size_t n = s.size();
  resize_geometric(parent_, n);
  resize_geometric(spin2_, n);
  resize_geometric(sphere_class_, n);
  resize_geometric(contact_flags_, n);
  resize_geometric(root_flags_, n);
  resize_geometric(island_label_, n);
  const std::size_t sphere_blocks = block_count(n, kIslandSphereBlock);
  resize_geometric(block_counts_, sphere_blocks);
  const float linear2 = settings.sleep_linear_speed * settings.sleep_linear_speed;
  const float angular2 = settings.sleep_angular_speed * settings.sleep_angular_speed;
  const auto total = [&] {
    BlockCounts sum;
    for (std::size_t b = 0; b < sphere_blocks; ++b) {
      sum.candidates += block_counts_[b].candidates, sum.needs_slides += block_counts_[b].needs_slides;
      sum.ready += block_counts_[b].ready, sum.slept += block_counts_[b].slept;
    }
    return sum;
  };

  // 1. Spheres: each one's class, and its timer where the contacts cannot change it. A sphere
  // faster than sleep_linear_speed restarts its timer and holds its island awake; one slow and
  // spinning slower than sleep_angular_speed counts dt on. Only the slots the later passes read
  // (candidates and the spinning) start their island data empty: the others cost no write.
  for_each_block(n, kIslandSphereBlock, [&](std::size_t block, std::size_t first, std::size_t last) {
    BlockCounts counts;
    for (std::size_t i = first; i < last; ++i) {
      std::uint8_t cls = s.inv_mass[i] > 0.0f ? kMovable : 0;
      if (cls != 0 && !sphere_sleeps(s, i)) {
        const float v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
        const float w2 = s.wx[i] * s.wx[i] + s.wy[i] * s.wy[i] + s.wz[i] * s.wz[i];
        if (v2 > linear2) {
          if (s.sleep_timer[i] != 0.0f) s.sleep_timer[i] = 0.0f;  // most are 0 already: no write
        } else if (w2 <= angular2 * kSlideMargin) {
          s.sleep_timer[i] += dt;
          if (s.sleep_timer[i] >= settings.sleep_time) cls |= kCandidate;
        } else {  // the contacts decide (step 3); a candidate if they let the timer run
          cls |= kNeedsSlides;
          if (s.sleep_timer[i] + dt >= settings.sleep_time) cls |= kCandidate;
        }
      }
      sphere_class_[i] = cls;
      if ((cls & (kCandidate | kNeedsSlides)) != 0) {
        parent_[i] = static_cast<std::uint32_t>(i);
        spin2_[i] = ordered_bits(0.0f);
        contact_flags_[i] = root_flags_[i] = 0;
        island_label_[i] = std::numeric_limits<std::uint32_t>::max();
      }
      counts.candidates += (cls & kCandidate) != 0 ? 1 : 0;
      counts.needs_slides += (cls & kNeedsSlides) != 0 ? 1 : 0;
    }
    block_counts_[block] = counts;
  });
  const BlockCounts classes = total();
  ready_to_sleep_ = 0;
  if (classes.candidates == 0 && classes.needs_slides == 0) return;  // nothing can sleep: no contact matters

  // 2. Contacts: islands of candidates, what they touch, and the slides of the spinning. An
  // island can sleep only if every sphere of it is a candidate, so a contact between a
  // candidate and any other movable sphere holds the candidate's island awake, and islands
  // need joining among candidates only: a step where few spheres are at rest pays little more
  // than this pass's read of the contacts.
  for_each_block(contacts.size(), kIslandContactBlock, [&](std::size_t, std::size_t first, std::size_t last) {
    for (const Contact& c : contacts.subspan(first, last - first)) {
      const std::uint8_t ca = sphere_class_[c.a];
      const std::uint8_t cb = c.b == kStaticBody ? 0 : sphere_class_[c.b];
      if ((ca | cb) & (kCandidate | kNeedsSlides)) {
        if ((cb & kMovable) == 0) {
          if ((ca & kCandidate) != 0) set_bits(contact_flags_[c.a], kTouchesStatic);
        } else if ((ca & kMovable) == 0) {
          if ((cb & kCandidate) != 0) set_bits(contact_flags_[c.b], kTouchesStatic);
        } else if ((ca & cb & kCandidate) != 0) {
          unite(c.a, c.b);
        } else if ((ca & kCandidate) != 0) {
          set_bits(contact_flags_[c.a], kHeldAwake);
        } else if ((cb & kCandidate) != 0) {
          set_bits(contact_flags_[c.b], kHeldAwake);
        }
        if (!(c.normal_impulse > 0.0f)) continue;  // touching without load: it holds the spin to nothing
        if ((ca & kNeedsSlides) != 0) {
          set_bits(contact_flags_[c.a], kLoaded);
          store_max(spin2_[c.a], ordered_bits(slide2(s.wx[c.a], s.wy[c.a], s.wz[c.a], c)));
        }
        if ((cb & kNeedsSlides) != 0) {
          set_bits(contact_flags_[c.b], kLoaded);
          store_max(spin2_[c.b], ordered_bits(slide2(s.wx[c.b], s.wy[c.b], s.wz[c.b], c)));
        }
      }
    }
  });

  // 3. Spheres: the spinning ones' timers; per island (at its root), the smallest handle index,
  // whether it is supported, and whether a sphere of it blocks its sleep.
  for_each_block(n, kIslandSphereBlock, [&](std::size_t block, std::size_t first, std::size_t last) {
    std::size_t ready = 0;
    for (std::size_t i = first; i < last; ++i) {
      const std::uint8_t cls = sphere_class_[i];
      if ((cls & kNeedsSlides) != 0) {
        const float w2 = (contact_flags_[i] & kLoaded) != 0 ? from_ordered_bits(spin2_[i])
                                                            : s.wx[i] * s.wx[i] + s.wy[i] * s.wy[i] + s.wz[i] * s.wz[i];
        s.sleep_timer[i] = w2 > angular2 ? 0.0f : s.sleep_timer[i] + dt;
      }
      if ((cls & kCandidate) == 0) continue;
      const bool rested = !(s.sleep_timer[i] < settings.sleep_time);
      ready += rested ? 1 : 0;
      const std::uint32_t root = find(static_cast<std::uint32_t>(i));
      store_min(island_label_[root], s.id_at(i).index);
      const std::uint8_t flags = contact_flags_[i];
      set_bits(root_flags_[root], static_cast<std::uint8_t>(((flags & kTouchesStatic) != 0 ? kSupported : 0) |
                                                            ((flags & kHeldAwake) != 0 || !rested ? kBlocked : 0)));
    }
    block_counts_[block].ready = ready;
  });
  ready_to_sleep_ = total().ready;
  if (classes.candidates == 0) return;  // only spinning spheres' timers: no island to put to sleep

  // 4. The islands at rest long enough go to sleep. Each sphere reads its root, written by nobody now.
  for_each_block(n, kIslandSphereBlock, [&](std::size_t block, std::size_t first, std::size_t last) {
    std::size_t slept = 0;
    for (std::size_t i = first; i < last; ++i) {
      if ((sphere_class_[i] & kCandidate) == 0) continue;
      const std::uint32_t root = find(static_cast<std::uint32_t>(i));
      if (root_flags_[root] != kSupported) continue;  // blocked, or in free flight
      s.flags[i] |= kSphereFlagSleeping;
      s.sleep_island[i] = island_label_[root];
      s.vx[i] = s.vy[i] = s.vz[i] = 0.0f;
      s.wx[i] = s.wy[i] = s.wz[i] = 0.0f;
      contact_flags_[i] |= kSleptNow;
      ++slept;
    }
    block_counts_[block].slept = slept;
  });
  // The events, in slot order, only in a substep that put something to sleep.
  if (total().slept > 0)
    for (std::size_t i = 0; i < n; ++i)
      if ((sphere_class_[i] & kCandidate) != 0 && (contact_flags_[i] & kSleptNow) != 0) slept_.push_back(s.id_at(i));
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
