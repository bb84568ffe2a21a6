#include "kernel/contact_cache.h"

#include <algorithm>

#include "soa/grow.h"

namespace hail {

void ContactImpulseCache::clear() {
  entries_.clear();
  ranges_.clear();
}

void ContactImpulseCache::prepare(std::size_t contact_count, const SphereSoA& s) {
  resize_geometric(ranges_, s.size());
  for (std::size_t slot = 0; slot < s.size(); ++slot) ranges_[slot] = Range{s.id_at(slot).index};
  resize_geometric(entries_, contact_count);
}

void ContactImpulseCache::store_range(std::span<const Contact> contacts, std::size_t static_count, std::size_t first,
                                      std::size_t last, const SphereSoA& s) {
  for (std::size_t k = first; k < last; ++k) {
    const Contact& c = contacts[k];
    const bool is_static = k < static_count;
    entries_[k] = {is_static ? c.feature : s.id_at(c.b).index, c.normal_impulse, c.tx, c.ty, c.tz};
    // Runs of one first sphere are contiguous within a section: its first contact writes the
    // range's begin, its last the end, so no two contacts write the same field.
    const std::size_t section_begin = is_static ? 0 : static_count, section_end = is_static ? static_count : contacts.size();
    Range& r = ranges_[c.a];
    std::uint32_t& begin = is_static ? r.static_begin : r.pair_begin;
    std::uint32_t& end = is_static ? r.static_end : r.pair_end;
    if (k == section_begin || contacts[k - 1].a != c.a) begin = static_cast<std::uint32_t>(k);
    if (k + 1 == section_end || contacts[k + 1].a != c.a) end = static_cast<std::uint32_t>(k + 1);
  }
}

void ContactImpulseCache::store(std::span<const Contact> contacts, std::size_t static_count, const SphereSoA& s) {
  prepare(contacts.size(), s);
  store_range(contacts, static_count, 0, contacts.size(), s);
}

void ContactImpulseCache::remap_slots(std::span<const std::uint32_t> order) {
  if (ranges_.empty()) return;  // nothing remembered (cleared, or warm starting off)
  resize_geometric(scratch_, order.size());
  for (std::size_t k = 0; k < order.size(); ++k) scratch_[k] = order[k] < ranges_.size() ? ranges_[order[k]] : Range{};
  std::swap(ranges_, scratch_);
}

const ContactImpulseCache::Entry* ContactImpulseCache::find(std::uint32_t begin, std::uint32_t end,
                                                            std::uint32_t partner) const {
  for (std::uint32_t k = begin; k < end; ++k)
    if (entries_[k].partner == partner) return &entries_[k];
  return nullptr;
}

std::size_t ContactImpulseCache::load(std::span<Contact> contacts, std::size_t static_count, std::size_t first,
                                      std::size_t last, const SphereSoA& s, float factor) const {
  // The range of `slot` if it still belongs to the sphere it was stored for, else none.
  auto range_of = [&](std::uint32_t slot, std::uint32_t id) -> const Range* {
    return slot < ranges_.size() && ranges_[slot].id == id ? &ranges_[slot] : nullptr;
  };
  std::size_t matched = 0;
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = contacts[k];
    const std::uint32_t a = s.id_at(c.a).index;
    const Range* ra = range_of(c.a, a);
    const Entry* e = nullptr;
    if (k < static_count) {
      if (ra) e = find(ra->static_begin, ra->static_end, c.feature);
    } else {
      const std::uint32_t b = s.id_at(c.b).index;
      if (ra) e = find(ra->pair_begin, ra->pair_end, b);
      if (!e) {  // the re-sort may have swapped which sphere comes first
        if (const Range* rb = range_of(c.b, b)) e = find(rb->pair_begin, rb->pair_end, a);
      }
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
