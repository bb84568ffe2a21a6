#include "kernel/solver/contact_colouring.h"

#include <algorithm>
#include <bit>
#include <limits>

#include "kernel/solver/slot_divider.h"
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
  for (std::size_t t = 0; t < tile_count(); ++t)
    most = std::max<std::size_t>(most, tile_colour_begin[t + 1] - tile_colour_begin[t]);
  return most + (colour_count() - shared_colour_begin());
}

namespace {

/// The colouring's key of contact c in group `group` (a tile, or tiles for the shared contacts)
/// with colour `colour`: twice the slot, plus 1 for a contact that starts_idle.
std::uint32_t colouring_key(const Contact& c, std::size_t group, std::uint32_t colour,
                            const SolveStartVelocities* velocities) {
  return static_cast<std::uint32_t>((group * kColourSlots + colour) * 2 + (starts_idle(c, velocities) ? 1 : 0));
}

/// Colours in key order, empty ones dropped; counts[key] becomes the key's first position.
void lay_out_colours(ContactColouring& out, std::size_t keys, std::size_t tiles) {
  out.colour_begin.assign(1, 0);
  out.serial.clear();
  out.tile_colour_begin.clear();
  std::uint32_t position = 0;
  for (std::size_t slot = 0; slot < keys / 2; ++slot) {
    if (slot % kColourSlots == 0 && tiles > 0)
      out.tile_colour_begin.push_back(static_cast<std::uint32_t>(out.serial.size()));
    const std::uint32_t count = out.counts[2 * slot] + out.counts[2 * slot + 1];
    out.counts[2 * slot + 1] = position + out.counts[2 * slot];
    out.counts[2 * slot] = position;
    if (count == 0) continue;
    position += count;
    out.colour_begin.push_back(position);
    out.serial.push_back(slot % kColourSlots == kMaxParallelColours ? 1 : 0);
  }
}

}  // namespace

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
    const std::uint32_t colour =
        take_colour(c, tile == tiles && tiles > 0 ? out.shared_mask.data() : out.body_mask.data());
    const std::uint32_t key = colouring_key(c, tile, colour, velocities);
    out.key_of[k] = key;
    ++out.counts[key];
  }
  lay_out_colours(out, keys, tiles);
  resize_geometric(out.order, contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k)
    out.order[out.counts[out.key_of[k]]++] = static_cast<std::uint32_t>(k);
}

std::size_t TiledColouring::begin(std::span<const Contact> contacts, const DetectionBlocks& blocks,
                                  std::size_t sphere_count, ContactColouring& out, std::size_t tile_spheres,
                                  const SolveStartVelocities* velocities) {
  tiles_ = tile_spheres == 0 ? 0 : (sphere_count + tile_spheres - 1) / tile_spheres;
  if (tiles_ == 0) return 0;
  contacts_ = contacts, blocks_ = blocks, out_ = &out, velocities_ = velocities;
  sphere_count_ = sphere_count, tile_spheres_ = tile_spheres;
  const std::size_t keys = (tiles_ + 1) * kColourSlots * 2;
  assign_geometric(out.body_mask, sphere_count, std::uint64_t{0});
  assign_geometric(out.shared_mask, sphere_count, std::uint64_t{0});
  resize_geometric(out.key_of, contacts.size());
  assign_geometric(out.counts, keys, std::uint32_t{0});
  resize_geometric(out.order, contacts.size());
  if (out.tile_contacts.size() < tiles_) out.tile_contacts.resize(tiles_);
  if (out.tile_shared.size() < tiles_) out.tile_shared.resize(tiles_);
  resize_geometric(out.tile_counts, 2 * tiles_);
  return tiles_;
}

void TiledColouring::colour_tile(std::size_t t) {
  ContactColouring& out = *out_;
  const std::size_t lo = t * tile_spheres_, hi = std::min(sphere_count_, lo + tile_spheres_);
  // The blocks that overlap the tile's slots, static ones then pairs: its contacts in contact
  // order. A block that straddles a tile edge is scanned by both tiles, each taking its own.
  struct Range {
    std::size_t first, last;  // blocks
  };
  auto blocks_of = [&](std::span<const std::size_t> offsets, std::size_t block_slots) {
    const std::size_t blocks = offsets.empty() ? 0 : offsets.size() - 1;
    return Range{lo / block_slots, std::min(blocks, (hi - 1) / block_slots + 1)};
  };
  const Range in_static = blocks_of(blocks_.static_offsets, blocks_.static_block_slots);
  const Range in_pairs = blocks_of(blocks_.pair_offsets, blocks_.pair_block_slots);
  // Room for every contact of those blocks, so that the lists are written without a check.
  std::size_t most = 0;
  if (in_static.first < in_static.last)
    most += blocks_.static_offsets[in_static.last] - blocks_.static_offsets[in_static.first];
  if (in_pairs.first < in_pairs.last)
    most += blocks_.pair_offsets[in_pairs.last] - blocks_.pair_offsets[in_pairs.first];
  // Grown, never shrunk (a std::vector zero-fills what it grows by); tile_counts holds the lengths.
  if (out.tile_contacts[t].size() < most) resize_geometric(out.tile_contacts[t], most);
  if (out.tile_shared[t].size() < most) resize_geometric(out.tile_shared[t], most);
  std::uint32_t* const mine = out.tile_contacts[t].data();
  std::uint32_t* const shared = out.tile_shared[t].data();
  std::size_t mine_count = 0, shared_count = 0;
  auto scan = [&](std::span<const std::size_t> offsets, Range r) {
    for (std::size_t b = r.first; b < r.last; ++b)
      for (std::size_t k = offsets[b]; k < offsets[b + 1]; ++k) {
        const Contact& c = contacts_[k];
        if (c.a < lo || c.a >= hi) continue;
        if (c.b != kStaticBody && (c.b < lo || c.b >= hi)) {
          shared[shared_count++] = static_cast<std::uint32_t>(k);
          continue;
        }
        const std::uint32_t colour = take_colour(c, out.body_mask.data());
        const std::uint32_t key = colouring_key(c, t, colour, velocities_);
        out.key_of[k] = key;
        ++out.counts[key];
        mine[mine_count++] = static_cast<std::uint32_t>(k);
      }
  };
  scan(blocks_.static_offsets, in_static);
  scan(blocks_.pair_offsets, in_pairs);
  out.tile_counts[2 * t] = static_cast<std::uint32_t>(mine_count);
  out.tile_counts[2 * t + 1] = static_cast<std::uint32_t>(shared_count);
}

void TiledColouring::colour_shared() {
  ContactColouring& out = *out_;
  // Shared contacts are pairs, and the tiles' rows come in slot order: tile after tile, in
  // contact order.
  for (std::size_t t = 0; t < tiles_; ++t)
    for (const std::uint32_t k : std::span(out.tile_shared[t].data(), out.tile_counts[2 * t + 1])) {
      const Contact& c = contacts_[k];
      const std::uint32_t key = colouring_key(c, tiles_, take_colour(c, out.shared_mask.data()), velocities_);
      out.key_of[k] = key;
      ++out.counts[key];
    }
  lay_out_colours(out, (tiles_ + 1) * kColourSlots * 2, tiles_);
  for (std::size_t t = 0; t < tiles_; ++t)
    for (const std::uint32_t k : std::span(out.tile_shared[t].data(), out.tile_counts[2 * t + 1]))
      out.order[out.counts[out.key_of[k]]++] = k;
}

void TiledColouring::place_tile(std::size_t t) {
  ContactColouring& out = *out_;
  for (const std::uint32_t k : std::span(out.tile_contacts[t].data(), out.tile_counts[2 * t]))
    out.order[out.counts[out.key_of[k]]++] = k;
}

}  // namespace hail
