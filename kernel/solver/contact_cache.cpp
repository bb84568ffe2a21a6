#include "kernel/solver/contact_cache.h"

#include <algorithm>

#include "soa/grow.h"

namespace hail {

void ContactImpulseCache::clear() {
  entries_.clear();
  ranges_.clear();
  carried_.clear();
  rolling_.clear();
}

void ContactImpulseCache::drop_forgotten(const SphereSoA& s) {
  // A pair is remembered in its first sphere's range only: a forgotten sphere's own range no
  // longer matches its id (forget), and here its partners' entries that name it lose their
  // partner, so load() matches neither.
  for (const Range& r : ranges_) {
    if (r.id == kNoId) continue;
    for (std::uint32_t k = r.pair_begin; k < r.pair_end; ++k) {
      const std::int64_t partner = s.slot_of_index(entries_[k].partner);
      const bool forgotten =
          partner >= 0 && (static_cast<std::size_t>(partner) >= ranges_.size() || ranges_[partner].id == kNoId);
      if (forgotten) entries_[k].partner = kNoId;
    }
  }
}

void ContactImpulseCache::begin_layout(const SphereSoA& s) { resize_geometric(scratch_, s.size()); }

void ContactImpulseCache::layout_static(std::span<const Contact> contacts, std::size_t begin, std::size_t end,
                                        std::size_t first_slot, std::size_t last_slot, const SphereSoA& s) {
  for (std::size_t slot = first_slot; slot < last_slot; ++slot) {
    Range& r = scratch_[slot];
    r.id = s.id_at(slot).index;
    r.static_begin = r.static_end = 0;
  }
  mark_runs(contacts, begin, end, &Range::static_begin, &Range::static_end);
}

void ContactImpulseCache::layout_pairs(std::span<const Contact> contacts, std::size_t begin, std::size_t end,
                                       std::size_t first_slot, std::size_t last_slot) {
  for (std::size_t slot = first_slot; slot < last_slot; ++slot) scratch_[slot].pair_begin = scratch_[slot].pair_end = 0;
  mark_runs(contacts, begin, end, &Range::pair_begin, &Range::pair_end);
}

// Runs of one first sphere are contiguous within a block. Each contact writes its run's begin
// and its own end into the sphere's range, without a branch (runs are 1 to 4 contacts long, and
// a branch on their ends mispredicts); a sphere with two runs in one block (plane, then
// terrain contacts) keeps the last.
void ContactImpulseCache::mark_runs(std::span<const Contact> contacts, std::size_t begin, std::size_t end,
                                    std::uint32_t Range::*run_begin, std::uint32_t Range::*run_end) {
  std::uint32_t previous = kNoId, first = 0;
  for (std::size_t k = begin; k < end; ++k) {
    const std::uint32_t a = contacts[k].a;
    first = a != previous ? static_cast<std::uint32_t>(k) : first;
    previous = a;
    scratch_[a].*run_begin = first;
    scratch_[a].*run_end = static_cast<std::uint32_t>(k + 1);
  }
}

void ContactImpulseCache::begin_store(std::size_t contact_count, const SphereSoA* sleepers) {
  std::swap(ranges_, scratch_);  // ranges_: this step's; scratch_: the last step's
  carried_.clear();
  carried_rolling_.clear();
  if (sleepers == nullptr) {
    resize_geometric(entries_, contact_count);
    rolling_.clear();
    return;
  }
  // A sleeper's contacts are left out of the step, so it has none of this step's: its last
  // ranges move to the end of the new entries, before store_entry overwrites the old ones.
  const bool rolling = !rolling_.empty();
  const std::size_t slots = std::min(ranges_.size(), scratch_.size());
  const auto count = static_cast<std::uint32_t>(contact_count);
  for (std::size_t slot = 0; slot < slots; ++slot) {
    if ((sleepers->flags[slot] & kSphereFlagSleeping) == 0) continue;
    Range& now = ranges_[slot];
    const Range& before = scratch_[slot];
    if (before.id != now.id || now.static_end != now.static_begin || now.pair_end != now.pair_begin) continue;
    const auto carry = [&](std::uint32_t begin, std::uint32_t end, std::uint32_t& new_begin, std::uint32_t& new_end) {
      new_begin = count + static_cast<std::uint32_t>(carried_.size());
      carried_.insert(carried_.end(), entries_.begin() + begin, entries_.begin() + end);
      if (rolling) carried_rolling_.insert(carried_rolling_.end(), rolling_.begin() + 3 * begin, rolling_.begin() + 3 * end);
      new_end = count + static_cast<std::uint32_t>(carried_.size());
    };
    carry(before.static_begin, before.static_end, now.static_begin, now.static_end);
    carry(before.pair_begin, before.pair_end, now.pair_begin, now.pair_end);
  }
  resize_geometric(entries_, contact_count + carried_.size());
  std::copy(carried_.begin(), carried_.end(), entries_.begin() + static_cast<std::ptrdiff_t>(contact_count));
  rolling_.clear();
}

void ContactImpulseCache::store_rolling(std::vector<float>& rolling) {
  // Carried entries that had none (rolling resistance was off when they were stored) get zeros.
  const std::size_t count = entries_.size() - carried_.size();
  resize_geometric(rolling, 3 * entries_.size());
  std::fill(rolling.begin() + static_cast<std::ptrdiff_t>(3 * count), rolling.end(), 0.0f);
  if (carried_rolling_.size() == 3 * carried_.size())
    std::copy(carried_rolling_.begin(), carried_rolling_.end(), rolling.begin() + static_cast<std::ptrdiff_t>(3 * count));
  std::swap(rolling_, rolling);
}

void ContactImpulseCache::store(std::span<const Contact> contacts, std::size_t static_count, const SphereSoA& s) {
  begin_layout(s);
  layout_static(contacts, 0, static_count, 0, s.size(), s);
  layout_pairs(contacts, static_count, contacts.size(), 0, s.size());
  begin_store(contacts.size(), nullptr);
  for (std::size_t k = 0; k < contacts.size(); ++k) store_entry(k, contacts[k], k < static_count, s);
}

void ContactImpulseCache::remap_slots(std::span<const std::uint32_t> order) {
  if (ranges_.empty()) return;  // nothing remembered (cleared, or warm starting off)
  resize_geometric(scratch_, order.size());
  for (std::size_t k = 0; k < order.size(); ++k) scratch_[k] = order[k] < ranges_.size() ? ranges_[order[k]] : Range{};
  std::swap(ranges_, scratch_);
}

const ContactImpulseCache::Entry* ContactImpulseCache::find(std::uint32_t begin, std::uint32_t end, std::uint32_t guess,
                                                            std::uint32_t partner) const {
  if (guess < end && entries_[guess].partner == partner) return &entries_[guess];
  for (std::uint32_t k = begin; k < end; ++k)
    if (entries_[k].partner == partner) return &entries_[k];
  return nullptr;
}

std::size_t ContactImpulseCache::load(std::span<Contact> contacts, std::size_t static_count, std::size_t first,
                                      std::size_t last, const SphereSoA& s, float factor, float* rolling) const {
  // The range of `slot` if it still belongs to the sphere it was stored for, else none.
  auto range_of = [&](std::uint32_t slot, std::uint32_t id) -> const Range* {
    return slot < ranges_.size() && ranges_[slot].id == id ? &ranges_[slot] : nullptr;
  };
  std::size_t matched = 0;
  // A sphere's contacts come in runs; the j-th of a run is most often the j-th of its stored
  // range (the same contacts as last step, found in the same order), so that entry is tried
  // first: the scan's exit, a branch on 1 to 4 entries, mispredicted about once a contact.
  // Partners are unique within a range, so the guess finds what the scan would.
  std::uint32_t run_slot = kNoId, a = kNoId;
  std::size_t run_begin = first;
  const Range* ra = nullptr;
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = contacts[k];
    if (c.a != run_slot) {
      run_slot = c.a, run_begin = k;
      a = s.id_at(c.a).index;
      ra = range_of(c.a, a);
    }
    const auto j = static_cast<std::uint32_t>(k - run_begin);
    const Entry* e = nullptr;
    if (k < static_count) {
      if (ra) e = find(ra->static_begin, ra->static_end, ra->static_begin + j, c.feature);
    } else {
      const std::uint32_t b = s.id_at(c.b).index;
      if (ra) e = find(ra->pair_begin, ra->pair_end, ra->pair_begin + j, b);
      if (!e) {  // the re-sort may have swapped which sphere comes first
        if (const Range* rb = range_of(c.b, b)) e = find(rb->pair_begin, rb->pair_end, rb->pair_begin, a);
      }
    }
    if (rolling) {
      float* r = rolling + 3 * k;
      const bool kept = e && !rolling_.empty();
      const float* from = kept ? rolling_.data() + 3 * static_cast<std::size_t>(e - entries_.data()) : nullptr;
      for (int d = 0; d < 3; ++d) r[d] = kept ? factor * from[d] : 0.0f;
    }
    if (!e) {
      c.normal_impulse = 0.0f, c.tx = c.ty = c.tz = 0.0f;
      continue;
    }
    ++matched;
    c.normal_impulse = factor * e->normal_impulse;
    // Only the part of the old friction impulse that lies in the new tangent plane.
    const float along = e->tx * c.nx + e->ty * c.ny + e->tz * c.nz;
    c.tx = factor * (e->tx - along * c.nx);
    c.ty = factor * (e->ty - along * c.ny);
    c.tz = factor * (e->tz - along * c.nz);
  }
  return matched;
}

}  // namespace hail
