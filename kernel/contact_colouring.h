#pragma once
// Graph colouring of contacts so that no two contacts of one colour share a sphere: each colour
// can then be solved in parallel with no race, and solving colours in a fixed order makes the
// result independent of the thread count. Greedy, in contact order, so it is deterministic.

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/contact.h"

namespace hail {

/// Contacts of colours 0..kMaxParallelColours-1 are independent within their colour; any
/// contact that finds all of them taken goes to one last colour solved serially.
inline constexpr std::uint32_t kMaxParallelColours = 64;

struct ContactColouring {
  std::vector<std::uint32_t> order;         ///< contact indices grouped by colour, in contact order within one
  std::vector<std::uint32_t> colour_begin;  ///< colour k spans order[colour_begin[k] .. colour_begin[k+1])
  std::vector<std::uint64_t> body_mask;     ///< scratch: colours used per sphere
  std::vector<std::uint8_t> colour_of;      ///< scratch: colour per contact
  [[nodiscard]] std::size_t colour_count() const { return colour_begin.empty() ? 0 : colour_begin.size() - 1; }
  [[nodiscard]] bool is_serial(std::size_t colour) const { return colour == kMaxParallelColours; }
};

/// Colours `contacts` over `sphere_count` spheres. Reuses the colouring's storage.
void colour_contacts(std::span<const Contact> contacts, std::size_t sphere_count, ContactColouring& out);

}  // namespace hail
