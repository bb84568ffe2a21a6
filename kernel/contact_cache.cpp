#include "kernel/contact_cache.h"

#include <algorithm>

#include "soa/grow.h"

namespace hail {

void ContactImpulseCache::clear() {
  entries_.clear();
  static_range_.clear();
  pair_range_.clear();
}

void ContactImpulseCache::prepare(std::size_t contact_count, const SphereSoA& s) {
  std::uint32_t ids = 0;
  for (std::size_t slot = 0; slot < s.size(); ++slot) ids = std::max(ids, s.id_at(slot).index + 1);
  assign_geometric(static_range_, ids, Range{});
  assign_geometric(pair_range_, ids, Range{});
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
    Range& r = (is_static ? static_range_ : pair_range_)[s.id_at(c.a).index];
    if (k == section_begin || contacts[k - 1].a != c.a) r.begin = static_cast<std::uint32_t>(k);
    if (k + 1 == section_end || contacts[k + 1].a != c.a) r.end = static_cast<std::uint32_t>(k + 1);
  }
}

void ContactImpulseCache::store(std::span<const Contact> contacts, std::size_t static_count, const SphereSoA& s) {
  prepare(contacts.size(), s);
  store_range(contacts, static_count, 0, contacts.size(), s);
}

const ContactImpulseCache::Entry* ContactImpulseCache::find(const std::vector<Range>& ranges, std::uint32_t owner,
                                                            std::uint32_t partner) const {
  if (owner >= ranges.size()) return nullptr;
  for (std::uint32_t k = ranges[owner].begin; k < ranges[owner].end; ++k)
    if (entries_[k].partner == partner) return &entries_[k];
  return nullptr;
}

std::size_t ContactImpulseCache::load(std::span<Contact> contacts, std::size_t static_count, std::size_t first,
                                      std::size_t last, const SphereSoA& s, float factor) const {
  std::size_t matched = 0;
  for (std::size_t k = first; k < last; ++k) {
    Contact& c = contacts[k];
    const std::uint32_t a = s.id_at(c.a).index;
    const Entry* e = nullptr;
    if (k < static_count) {
      e = find(static_range_, a, c.feature);
    } else {
      const std::uint32_t b = s.id_at(c.b).index;
      e = find(pair_range_, a, b);  // the re-sort may have swapped which sphere comes first
      if (!e) e = find(pair_range_, b, a);
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
