#include "kernel/contact_colouring.h"

#include <bit>

#include "soa/grow.h"

namespace hail {

void colour_contacts(std::span<const Contact> contacts, std::size_t sphere_count, ContactColouring& out) {
  assign_geometric(out.body_mask, sphere_count, std::uint64_t{0});
  resize_geometric(out.colour_of, contacts.size());
  std::uint32_t counts[kMaxParallelColours + 1] = {};
  std::uint32_t used_colours = 0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    std::uint64_t used = out.body_mask[c.a];
    if (c.b != kStaticBody) used |= out.body_mask[c.b];
    const std::uint32_t colour = ~used == 0 ? kMaxParallelColours : static_cast<std::uint32_t>(std::countr_zero(~used));
    if (colour < kMaxParallelColours) {
      out.body_mask[c.a] |= std::uint64_t{1} << colour;
      if (c.b != kStaticBody) out.body_mask[c.b] |= std::uint64_t{1} << colour;
    }
    out.colour_of[k] = static_cast<std::uint8_t>(colour);
    ++counts[colour];
    if (colour + 1 > used_colours) used_colours = colour + 1;
  }
  assign_geometric(out.colour_begin, used_colours + 1, std::uint32_t{0});
  for (std::uint32_t k = 0; k < used_colours; ++k) out.colour_begin[k + 1] = out.colour_begin[k] + counts[k];
  resize_geometric(out.order, contacts.size());
  std::vector<std::uint32_t>& begin = out.colour_begin;
  std::uint32_t cursor[kMaxParallelColours + 1];
  for (std::uint32_t k = 0; k < used_colours; ++k) cursor[k] = begin[k];
  for (std::size_t k = 0; k < contacts.size(); ++k) out.order[cursor[out.colour_of[k]]++] = static_cast<std::uint32_t>(k);
}

}  // namespace hail
