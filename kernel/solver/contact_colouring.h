#pragma once
// Graph colouring of contacts so that no two contacts of one colour share a sphere: each colour
// can then be solved in parallel with no race, and solving colours in a fixed order makes the
// result independent of the thread count. Greedy, in contact order, so it is deterministic.
//
// Tiles (optional): the spheres' slots are cut into tiles of `tile_spheres` consecutive slots
// (slots are in Morton order, so a tile is a compact region of space). A contact whose spheres
// are both in one tile (or whose other side is static) is that tile's; the others (across a
// tile edge) are shared. Each tile's contacts are coloured on their own, and the shared
// contacts after them. A pass then runs every tile's colours one after another on one thread,
// tiles in parallel (they share no sphere), and the shared colours last, each in parallel:
// a tile's bodies stay in that core's cache through all its colours, where untiled colours
// each sweep the whole body array (measured in docs/benchmarks.md), and a pass has one parallel stage
// for all tiles instead of one per colour. Without tiles (tile_spheres 0) every contact is
// shared: the plain colouring.

#include <cstdint>
#include <span>
#include <vector>

#include "hail/contact.h"
#include "soa/heap_bytes.h"

namespace hail {

/// The spheres' velocities by slot as the solve starts, and 1 / dt: colour_contacts' guess of
/// which contacts the resting passes leave alone.
struct SolveStartVelocities {
  const float *vx, *vy, *vz;
  float inv_dt;
};

/// A contact that starts the step with no impulse, with a gap its spheres close by less than
/// half in the step (static side at rest): a speculative one that the resting passes most
/// likely leave as it is (resting_idle, kernel/solver/contact_impulse.h). Each colour lists these
/// after its other contacts (each group in contact order), so that they fill SIMD batches of
/// their own, which the passes skip whole (how many, in terrain-rain: docs/benchmarks.md,
/// "Figures behind the code's choices"). Within a parallel colour the order changes no result, as its contacts share no
/// sphere. Without velocities, the gap alone decides.
[[nodiscard]] inline bool starts_idle(const Contact& c, const SolveStartVelocities* v = nullptr) {
  const bool idle = holds_no_impulse(c) & (c.gap > 0.0f);  // & : branch-free, as holds_no_impulse
  if (v == nullptr) return idle;
  const bool moving_b = c.b != kStaticBody;
  const std::uint32_t b = moving_b ? c.b : c.a;  // a valid slot; its velocity is then not used
  const float sb = moving_b ? 1.0f : 0.0f;
  const float vn =
      (sb * v->vx[b] - v->vx[c.a]) * c.nx + (sb * v->vy[b] - v->vy[c.a]) * c.ny + (sb * v->vz[b] - v->vz[c.a]) * c.nz;
  return idle & (vn + 0.5f * c.gap * v->inv_dt >= 0.0f);
}

/// Contacts of colours 0..kMaxParallelColours-1 (of a tile, or of the shared contacts) are
/// independent within their colour; any contact that finds all of them taken goes to one last
/// colour of its tile (or of the shared ones) solved serially.
inline constexpr std::uint32_t kMaxParallelColours = 64;

struct ContactColouring {
  std::vector<std::uint32_t>
      order;  ///< contact indices grouped by colour; within one, those not starts_idle, then those, each in contact order
  std::vector<std::uint32_t> colour_begin;  ///< colour k spans order[colour_begin[k] .. colour_begin[k+1])
  /// Tile t's colours are [tile_colour_begin[t], tile_colour_begin[t+1]); the shared colours
  /// are [shared_colour_begin(), colour_count()). Colours of different tiles share no sphere.
  std::vector<std::uint32_t> tile_colour_begin;
  std::vector<std::uint8_t> serial;        ///< per colour: 1 for an overflow colour (its contacts may share spheres)
  std::vector<std::uint64_t> body_mask;    ///< scratch: colours used per sphere
  std::vector<std::uint64_t> shared_mask;  ///< scratch: shared colours used per sphere
  std::vector<std::uint32_t> key_of;       ///< scratch: (tile or shared) and colour per contact
  std::vector<std::uint32_t> counts;       ///< scratch: contacts per (tile or shared, colour)
  std::vector<std::vector<std::uint32_t>>
      tile_contacts;  ///< scratch (TiledColouring): per tile, its contacts, in contact order
  std::vector<std::vector<std::uint32_t>>
      tile_shared;                         ///< scratch (TiledColouring): per tile, the shared contacts of its rows
  std::vector<std::uint32_t> tile_counts;  ///< scratch (TiledColouring): per tile, the lengths of those two lists
  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(order, colour_begin, tile_colour_begin, serial, body_mask, shared_mask, key_of, counts,
                         tile_contacts, tile_shared, tile_counts);
  }
  [[nodiscard]] std::size_t colour_count() const { return colour_begin.empty() ? 0 : colour_begin.size() - 1; }
  [[nodiscard]] std::size_t tile_count() const { return tile_colour_begin.empty() ? 0 : tile_colour_begin.size() - 1; }
  [[nodiscard]] std::size_t shared_colour_begin() const {
    return tile_colour_begin.empty() ? 0 : tile_colour_begin.back();
  }
  [[nodiscard]] bool is_serial(std::size_t colour) const { return serial[colour] != 0; }
  /// Colours one after another on a pass's critical path: the most colours of any tile, then
  /// the shared colours.
  [[nodiscard]] std::size_t sequential_colours() const;
};

/// Colours `contacts` over `sphere_count` spheres, in tiles of `tile_spheres` slots (0: no
/// tiles), each colour's starts_idle(c, velocities) contacts last. Reuses the colouring's storage.
void colour_contacts(std::span<const Contact> contacts, std::size_t sphere_count, ContactColouring& out,
                     std::size_t tile_spheres = 0, const SolveStartVelocities* velocities = nullptr);

/// The contacts as the step's detection makes them (StepPipeline::merge_contacts): blocks of
/// static contacts, block b holding those of slots [b * static_block_slots, ...), then blocks of
/// sphere pairs, block b those whose first sphere is in [b * pair_block_slots, ...); offsets[b]
/// to offsets[b + 1] are a block's contacts (offsets: one more entry than blocks).
struct DetectionBlocks {
  std::span<const std::size_t> static_offsets, pair_offsets;
  std::size_t static_block_slots = 1, pair_block_slots = 1;
};

/// colour_contacts (with tiles) in parts, so that the tiles are coloured in parallel: a tile's
/// contacts share no sphere with another tile's, and its colouring only depends on them, in
/// contact order. The same colouring bit for bit:
///   begin (serial); colour_tile(t) for every tile (in parallel); colour_shared (serial);
///   place_tile(t) for every tile (in parallel).
/// Each tile finds its contacts in the detection blocks that overlap its slots, so no pass
/// groups them first. On one thread colour_contacts is faster (this one also lists each tile's
/// contacts, to place them); this one is for two or more.
class TiledColouring {
 public:
  /// Returns the number of tiles (0 when tile_spheres is 0: use colour_contacts).
  std::size_t begin(std::span<const Contact> contacts, const DetectionBlocks& blocks, std::size_t sphere_count,
                    ContactColouring& out, std::size_t tile_spheres, const SolveStartVelocities* velocities);
  void colour_tile(std::size_t tile);
  void colour_shared();
  void place_tile(std::size_t tile);

 private:
  std::span<const Contact> contacts_;
  DetectionBlocks blocks_;
  ContactColouring* out_ = nullptr;
  const SolveStartVelocities* velocities_ = nullptr;
  std::size_t sphere_count_ = 0, tile_spheres_ = 0, tiles_ = 0;
};

}  // namespace hail
