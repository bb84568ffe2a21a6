#pragma once
// Warm starting: each step's contacts begin with the impulses the same contact ended the last
// step with, so a pile starts its resting passes already holding its weight instead of
// rebuilding it from zero every step (Catto, "Iterative Dynamics with Temporal Coherence",
// 2005). A contact is "the same" when it joins the same two spheres (stable SphereId indices,
// so the Morton re-sort does not lose it) or the same sphere and static feature (terrain
// triangle or plane, Contact::feature).
//
// The cache keeps, per slot, the range of its sphere's last-step contacts (static ones and pairs
// it was first in); a lookup scans that short range. Contacts are stored in detection order,
// which groups them by slot, so nothing is sorted, and the next step's lookups, also in slot
// order, read the ranges in order. Keyed by sphere id instead, every lookup was a jump through
// the ids' order: a cache miss a contact from 64k spheres on (34% of the lookup's samples,
// perf). A re-sort that moves the spheres to other slots moves their ranges with them
// (remap_slots); each range also remembers its sphere's id, so a range whose slot now holds
// another sphere is never taken for it.

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/contact.h"
#include "soa/sphere_soa.h"

namespace hail {

class ContactImpulseCache {
 public:
  /// Remembers the impulses of `contacts`, in detection order: the first `static_count` are
  /// static contacts grouped by sphere, the rest sphere pairs grouped by their first sphere.
  /// Allocates only on growth.
  void store(std::span<const Contact> contacts, std::size_t static_count, const SphereSoA& spheres);
  /// store() in two parts, so that the copying can run in parallel: prepare() sizes and clears
  /// (serial), store_range() fills contacts[first, last) (disjoint ranges in parallel; each
  /// sphere's range is written by the contacts at its ends only).
  void prepare(std::size_t contact_count, const SphereSoA& spheres);
  void store_range(std::span<const Contact> contacts, std::size_t static_count, std::size_t first, std::size_t last,
                   const SphereSoA& spheres);
  /// Sets normal_impulse and the friction impulse of contacts[first, last) (detection order, as
  /// for store) from the matching remembered contact, the friction impulse projected onto the
  /// new contact's tangent plane; zero where nothing matches. Disjoint ranges may run in
  /// parallel. `factor` scales what is carried over (WorldSettings::warm_start_factor). Returns
  /// how many matched.
  std::size_t load(std::span<Contact> contacts, std::size_t static_count, std::size_t first, std::size_t last,
                   const SphereSoA& spheres, float factor = 1.0f) const;
  /// The spheres were permuted as SphereSoA::permute(order) did: new slot k holds the sphere
  /// of old slot order[k]. Moves each remembered range to its sphere's new slot. Without it,
  /// load() after a permutation matches nothing it should not (ranges are checked against ids),
  /// but misses most of what it could.
  void remap_slots(std::span<const std::uint32_t> order);
  /// Forgets everything (spheres were added or removed: ids may be reused).
  void clear();

 private:
  struct Entry {
    std::uint32_t partner;  // the other sphere's id index, or the static feature
    float normal_impulse, tx, ty, tz;
  };
  /// A slot's contacts: entries_[begin, end) of its static contacts and of its pairs, and the
  /// id index of the sphere that had the slot when they were stored.
  struct Range {
    std::uint32_t id = kNoId;
    std::uint32_t static_begin = 0, static_end = 0, pair_begin = 0, pair_end = 0;
  };
  static constexpr std::uint32_t kNoId = 0xFFFFFFFFu;
  [[nodiscard]] const Entry* find(std::uint32_t begin, std::uint32_t end, std::uint32_t partner) const;

  std::vector<Entry> entries_;
  std::vector<Range> ranges_, scratch_;  // per slot; scratch_: remap_slots
};

}  // namespace hail
