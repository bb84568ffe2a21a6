// The SIMD kernels' output helpers (declared in kernel/dispatch/kernel_table.h): compiled once,
// at the base level, so that no std::vector growth is compiled with a path's instructions.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "hail/contact.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/dispatch/kernel_table.h"
#include "soa/grow.h"

namespace hail {

// The per-block lists these fill are cleared every step: an insert past capacity would make
// them exactly as long as this step needs (soa/grow.h), so they grow geometrically instead.
void append_pairs(std::vector<SpherePair>& out, const SpherePair* pairs, std::size_t count) {
  reserve_geometric(out, out.size() + count);
  out.insert(out.end(), pairs, pairs + count);
}

void append_slots(std::vector<std::uint32_t>& out, const std::uint32_t* slots, std::size_t count) {
  reserve_geometric(out, out.size() + count);
  out.insert(out.end(), slots, slots + count);
}

void append_contacts(std::vector<Contact>& out, const Contact* contacts, std::size_t count) {
  reserve_geometric(out, out.size() + count);
  out.insert(out.end(), contacts, contacts + count);
}

void append_sorted_row(std::uint32_t i, std::vector<std::uint32_t>& row, std::vector<SpherePair>& out) {
  std::sort(row.begin(), row.end());
  reserve_geometric(out, out.size() + row.size());
  for (std::uint32_t j : row) out.push_back({i, j});
  row.clear();
}

}  // namespace hail
