#include "kernel/contact_colouring.h"

#include <algorithm>
#include <bit>
#include <limits>

#include "kernel/slot_divider.h"
#include "soa/grow.h"

namespace hail {

namespace {

constexpr std::uint32_t kColourSlots = kMaxParallelColours + 1;  // the parallel colours, then the serial one

/// The greedy rule: the lowest colour neither sphere has yet (kMaxParallelColours when all
/// are taken: the serial colour, which marks nothing).
std::uint32_t take_colour(const Contact& c, std::uint64_t* mask) {
  std::uint64_t used = mask[c.a];
  if (c.b != kStaticBody) used |= mask[c.b];
  if (~used == 0) return kMaxParallelColours;
  const auto colour = static_cast<std::uint32_t>(std::countr_zero(~used));
  mask[c.a] |= std::uint64_t{1} << colour;
  if (c.b != kStaticBody) mask[c.b] |= std::uint64_t{1} << colour;
  return colour;
}

}  // namespace

std::size_t ContactColouring::sequential_colours() const {
  std::size_t most = 0;
  for (std::size_t t = 0; t < tile_count(); ++t) most = std::max<std::size_t>(most, tile_colour_begin[t + 1] - tile_colour_begin[t]);
  return most + (colour_count() - shared_colour_begin());
}

void colour_contacts(std::span<const Contact> contacts, std::size_t sphere_count, ContactColouring& out,
                     std::size_t tile_spheres, const SolveStartVelocities* velocities) {
  const std::size_t tiles = tile_spheres == 0 ? 0 : (sphere_count + tile_spheres - 1) / tile_spheres;
  // Keys: tile t's colour c is t * kColourSlots + c; the shared colour c is tiles * kColourSlots + c;
  // twice that, plus 1 for a contact that starts_idle: those go after the others of their colour.
  const std::size_t keys = (tiles + 1) * kColourSlots * 2;
  assign_geometric(out.body_mask, sphere_count, std::uint64_t{0});
  if (tiles > 0) assign_geometric(out.shared_mask, sphere_count, std::uint64_t{0});
  resize_geometric(out.key_of, contacts.size());
  assign_geometric(out.counts, keys, std::uint32_t{0});
  // Slots are uint32, so a tile wider than that holds them all: the largest divisor does too.
  const SlotDivider tile_of(static_cast<std::uint32_t>(
      std::min<std::size_t>(std::max<std::size_t>(tile_spheres, 1), std::numeric_limits<std::uint32_t>::max())));
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    std::size_t tile = tiles;  // shared
    if (tiles > 0) {
      const std::uint32_t ta = tile_of(c.a);
      if (c.b == kStaticBody || tile_of(c.b) == ta) tile = ta;
    }
    const std::uint32_t colour = take_colour(c, tile == tiles && tiles > 0 ? out.shared_mask.data() : out.body_mask.data());
    const auto key = static_cast<std::uint32_t>((tile * kColourSlots + colour) * 2 + (starts_idle(c, velocities) ? 1 : 0));
    out.key_of[k] = key;
    ++out.counts[key];
  }
  // Colours in key order, empty ones dropped; counts[key] becomes the key's first position.
  out.colour_begin.assign(1, 0);
  out.serial.clear();
  out.tile_colour_begin.clear();
  std::uint32_t position = 0;
  for (std::size_t slot = 0; slot < keys / 2; ++slot) {
    if (slot % kColourSlots == 0 && tiles > 0) out.tile_colour_begin.push_back(static_cast<std::uint32_t>(out.serial.size()));
    const std::uint32_t count = out.counts[2 * slot] + out.counts[2 * slot + 1];
    out.counts[2 * slot + 1] = position + out.counts[2 * slot];
    out.counts[2 * slot] = position;
    if (count == 0) continue;
    position += count;
    out.colour_begin.push_back(position);
    out.serial.push_back(slot % kColourSlots == kMaxParallelColours ? 1 : 0);
  }
  resize_geometric(out.order, contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k) out.order[out.counts[out.key_of[k]]++] = static_cast<std::uint32_t>(k);
}

}  // namespace hail
