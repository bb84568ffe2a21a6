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
// order, read the ranges in order. The ranges of a step's contacts are noted while the step
// merges them (layout_static, layout_pairs: the contacts are in cache then, and the merge's
// blocks are by slot), and the impulses are stored after the solve wherever the solver keeps
// its contacts (store_entry takes each contact's detection-order index): copying them back
// into detection order and reading every contact again cost several times as much. Keyed by
// sphere id instead, every lookup was a jump through the ids' order: a cache miss a contact in
// large worlds (figures for both: docs/benchmarks.md, "Figures behind the code's choices").
// A re-sort that moves the spheres to other slots moves their ranges with them
// (remap_slots); each range also remembers its sphere's id, so a range whose slot now holds
// another sphere is never taken for it.

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "hail/contact.h"
#include "hail/sphere_soa.h"
#include "soa/heap_bytes.h"

namespace hail {

class ContactImpulseCache {
 public:
  /// Remembers the impulses of `contacts`, in detection order: the first `static_count` are
  /// static contacts grouped by sphere, the rest sphere pairs grouped by their first sphere.
  /// Allocates only on growth. The steps below, in one call.
  void store(std::span<const Contact> contacts, std::size_t static_count, const SphereSoA& spheres);

  /// store() in steps, so that each runs where its data is at hand and in parallel:
  /// 1. begin_layout (serial): this step's ranges, for the spheres' slots;
  /// 2. layout_static and layout_pairs (blocks of disjoint slots in parallel): where the
  ///    detection-order contacts [begin, end) of slots [first_slot, last_slot) lie, static ones
  ///    grouped by slot, pairs grouped by their first sphere. Every slot must be in one block
  ///    of each kind. Lookups (load) meanwhile still see the last step's.
  /// 3. begin_store (serial): room for `contact_count` impulses; the new ranges replace the
  ///    last step's;
  /// 4. store_entry for every contact, by its detection-order index (in parallel).
  void begin_layout(const SphereSoA& spheres);
  void layout_static(std::span<const Contact> contacts, std::size_t begin, std::size_t end, std::size_t first_slot,
                     std::size_t last_slot, const SphereSoA& spheres);
  void layout_pairs(std::span<const Contact> contacts, std::size_t begin, std::size_t end, std::size_t first_slot,
                    std::size_t last_slot);
  /// With `sleepers` (WorldSettings::sleep on), each sleeping sphere that has no contact this
  /// step (a sleeper's contacts are left out of the step) keeps the entries it last had: they
  /// move to the end of the new entries, after the contact_count of this step. Without them a
  /// woken pile restarted its solve cold and sagged: `hail-bench sleep` part 2, a sphere dropped
  /// on a sleeping 10,000-sphere pile, moved the pile 14 mm RMS against 1.7 mm with sleeping off.
  /// O(spheres) with sleepers; nothing more without.
  /// Forgets the rolling impulses (store_rolling puts this step's back; a cache without any
  /// loads zeros).
  void begin_store(std::size_t contact_count, const SphereSoA* sleepers);
  /// After begin_store and the step's store_entry calls, when rolling resistance ran: each
  /// contact's accumulated rolling impulse (3 floats, by detection-order index, as `rolling`
  /// holds them). Sleepers' carried entries keep theirs. Swaps buffers with `rolling`, which
  /// then holds the last step's (scratch).
  void store_rolling(std::vector<float>& rolling);
  /// Contact c, solved, at index k of its step's detection order (static when k < the step's
  /// static count).
  void store_entry(std::size_t k, const Contact& c, bool is_static, const SphereSoA& spheres) {
    entries_[k] = {is_static ? c.feature : spheres.id_at(c.b).index, c.normal_impulse, c.tx, c.ty, c.tz};
  }
  /// Sets normal_impulse and the friction impulse of contacts[first, last) (detection order, as
  /// for store) from the matching remembered contact, the friction impulse projected onto the
  /// new contact's tangent plane; zero where nothing matches. Disjoint ranges may run in
  /// parallel. `factor` scales what is carried over (WorldSettings::warm_start_factor). With
  /// `rolling` (3 floats a contact, detection order, as contacts), also each contact's rolling
  /// impulse (zero where nothing matches or none was stored). Returns how many matched.
  std::size_t load(std::span<Contact> contacts, std::size_t static_count, std::size_t first, std::size_t last,
                   const SphereSoA& spheres, float factor = 1.0f, float* rolling = nullptr) const;
  /// The spheres were permuted as SphereSoA::permute(order) did: new slot k holds the sphere
  /// of old slot order[k]. Moves each remembered range to its sphere's new slot. Without it,
  /// load() after a permutation matches nothing it should not (ranges are checked against ids),
  /// but misses most of what it could.
  void remap_slots(std::span<const std::uint32_t> order);
  /// Forgets everything (spheres were added or removed: ids may be reused).
  void clear();
  /// Forgets the contacts of the sphere in `slot` alone (it was teleported: what it touched is
  /// no longer where it is), in two steps so that a batch pays one pass: forget(slot) for
  /// each such sphere drops its own range, then drop_forgotten() one pass over the remembered
  /// pairs drops those whose partner was forgotten. O(spheres + contacts); no allocation.
  void forget(std::size_t slot) {
    if (slot < ranges_.size()) ranges_[slot].id = kNoId;
  }
  void drop_forgotten(const SphereSoA& spheres);

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

  /// What the next step reads (snapshots): the remembered impulses, each slot's range of them,
  /// and the entries' rolling impulses (3 floats each, or none).
  [[nodiscard]] std::span<const Entry> entries() const { return entries_; }
  [[nodiscard]] std::span<const Range> ranges() const { return ranges_; }
  [[nodiscard]] std::span<const float> rolling() const { return rolling_; }
  /// Puts back what entries(), ranges() and rolling() returned. The caller has checked that
  /// every range lies within `entries` and that `rolling` is empty or 3 floats an entry (load()
  /// reads them unchecked).
  void assign(std::vector<Entry> entries, std::vector<Range> ranges, std::vector<float> rolling) {
    entries_ = std::move(entries);
    ranges_ = std::move(ranges);
    rolling_ = std::move(rolling);
  }

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(entries_, carried_, ranges_, scratch_, rolling_, carried_rolling_);
  }

 private:
  /// Sets (scratch_[a].*run_begin, scratch_[a].*run_end) of each contacts[begin, end)'s first sphere a to its run.
  void mark_runs(std::span<const Contact> contacts, std::size_t begin, std::size_t end, std::uint32_t Range::*run_begin,
                 std::uint32_t Range::*run_end);
  /// The entry of `partner` in entries_[begin, end), trying entries_[guess] first; null if none.
  [[nodiscard]] const Entry* find(std::uint32_t begin, std::uint32_t end, std::uint32_t guess,
                                  std::uint32_t partner) const;

  std::vector<Entry> entries_, carried_;  // carried_: begin_store's sleepers' entries, on their way
  std::vector<Range> ranges_, scratch_;   // per slot; scratch_: remap_slots, then the next step's layout
  // Rolling resistance's angular impulses, 3 floats an entry of entries_ (empty: none kept, so
  // scenes without rolling resistance pay nothing); carried_rolling_: the sleepers' ones.
  std::vector<float> rolling_, carried_rolling_;
};

}  // namespace hail
