// The contact colouring (kernel/solver/contact_colouring.h), with and without solver tiles: every
// contact in exactly one colour; no two contacts of a parallel colour share a sphere; a tile's
// colours hold only contacts within the tile, the shared colours only contacts across tiles;
// within a colour, the contacts that start idle last;
// the overflow colour past kMaxParallelColours; without tiles, the plain greedy colouring.

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "catch.h"
#include "kernel/solver/contact_colouring.h"
#include "kernel/solver/slot_divider.h"

using namespace hail;

namespace {

/// Contacts over `spheres` spheres: mostly between near slots (as Morton order makes them),
/// some between far ones, 25% static.
std::vector<Contact> random_contacts(std::size_t spheres, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> slot(0, static_cast<std::uint32_t>(spheres - 1));
  std::uniform_int_distribution<int> near(-40, 40);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Contact> contacts;
  while (contacts.size() < count) {
    Contact c;
    c.a = slot(rng);
    const float kind = unit(rng);
    if (kind < 0.25f) {
      c.b = kStaticBody;
    } else if (kind < 0.9f) {
      const long b = static_cast<long>(c.a) + near(rng);
      if (b < 0 || b >= static_cast<long>(spheres) || b == static_cast<long>(c.a)) continue;
      c.b = static_cast<std::uint32_t>(b);
    } else {
      c.b = slot(rng);
      if (c.b == c.a) continue;
    }
    // A third speculative with no impulse (starts_idle), a third pressing, a third touching.
    const float state = unit(rng);
    c.gap = state < 0.34f ? 0.01f : 0.0f;
    c.normal_impulse = state > 0.67f ? 0.5f : 0.0f;
    contacts.push_back(c);
  }
  return contacts;
}

/// Checks the colouring's invariants; returns the number of shared contacts.
std::size_t check_colouring(std::span<const Contact> contacts, const ContactColouring& col, std::size_t tile_spheres) {
  REQUIRE(col.colour_begin.front() == 0);
  REQUIRE(col.colour_begin.back() == contacts.size());
  REQUIRE(col.serial.size() == col.colour_count());
  // Every contact exactly once; within each colour the contacts that start idle after the
  // others, each group in contact order.
  std::vector<int> seen(contacts.size(), 0);
  for (std::uint32_t k : col.order) ++seen[k];
  CHECK(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
  for (std::size_t colour = 0; colour < col.colour_count(); ++colour)
    for (std::uint32_t k = col.colour_begin[colour] + 1; k < col.colour_begin[colour + 1]; ++k) {
      const bool before = starts_idle(contacts[col.order[k - 1]]), now = starts_idle(contacts[col.order[k]]);
      CHECK(before <= now);
      if (before == now) CHECK(col.order[k - 1] < col.order[k]);
    }
  // No shared sphere within a parallel colour; no empty colour.
  for (std::size_t colour = 0; colour < col.colour_count(); ++colour) {
    CHECK(col.colour_begin[colour] < col.colour_begin[colour + 1]);
    if (col.is_serial(colour)) continue;
    std::set<std::uint32_t> spheres;
    for (std::uint32_t k = col.colour_begin[colour]; k < col.colour_begin[colour + 1]; ++k) {
      const Contact& c = contacts[col.order[k]];
      CHECK(spheres.insert(c.a).second);
      if (c.b != kStaticBody) CHECK(spheres.insert(c.b).second);
    }
  }
  if (tile_spheres == 0) {
    CHECK(col.tile_count() == 0);
    CHECK(col.shared_colour_begin() == 0);
    return contacts.size();
  }
  // Tile t's colours: contacts with a in tile t and b in it or static. Shared: the others.
  for (std::size_t t = 0; t < col.tile_count(); ++t)
    for (std::size_t colour = col.tile_colour_begin[t]; colour < col.tile_colour_begin[t + 1]; ++colour)
      for (std::uint32_t k = col.colour_begin[colour]; k < col.colour_begin[colour + 1]; ++k) {
        const Contact& c = contacts[col.order[k]];
        CHECK(c.a / tile_spheres == t);
        CHECK((c.b == kStaticBody || c.b / tile_spheres == t));
      }
  for (std::size_t colour = col.shared_colour_begin(); colour < col.colour_count(); ++colour)
    for (std::uint32_t k = col.colour_begin[colour]; k < col.colour_begin[colour + 1]; ++k) {
      const Contact& c = contacts[col.order[k]];
      CHECK(c.b != kStaticBody);
      CHECK(c.a / tile_spheres != c.b / tile_spheres);
    }
  return contacts.size() - col.colour_begin[col.shared_colour_begin()];
}

}  // namespace

TEST_CASE("Tiled contact colouring keeps every contact once, colours independent, tiles apart", "[solver][colouring]") {
  const std::size_t spheres = 5000;
  const std::vector<Contact> contacts = random_contacts(spheres, 12000, 17);
  ContactColouring col;
  for (std::size_t tile : {std::size_t{0}, std::size_t{64}, std::size_t{1000}, std::size_t{4096}, std::size_t{8192}}) {
    INFO("tile spheres " << tile);
    colour_contacts(contacts, spheres, col, tile);  // reused storage: the previous run must not leak in
    const std::size_t shared = check_colouring(contacts, col, tile);
    CHECK(col.tile_count() == (tile == 0 ? 0 : (spheres + tile - 1) / tile));
    if (tile == 64) CHECK(shared > 1000);  // the test covers both kinds
    if (tile == 1000) CHECK((shared > 0 && shared < contacts.size() / 2));
    if (tile == 8192) CHECK(shared == 0);  // one tile holds every sphere
    // The critical path: the largest tile's colours, then the shared ones.
    std::size_t most = 0;
    for (std::size_t t = 0; t < col.tile_count(); ++t)
      most = std::max<std::size_t>(most, col.tile_colour_begin[t + 1] - col.tile_colour_begin[t]);
    CHECK(col.sequential_colours() == most + col.colour_count() - col.shared_colour_begin());
  }
}

TEST_CASE("One tile holding every sphere colours exactly as no tiles", "[solver][colouring]") {
  const std::vector<Contact> contacts = random_contacts(3000, 7000, 5);
  ContactColouring plain, one_tile;
  colour_contacts(contacts, 3000, plain, 0);
  colour_contacts(contacts, 3000, one_tile, 4096);
  CHECK(plain.order == one_tile.order);
  CHECK(plain.colour_begin == one_tile.colour_begin);
  CHECK(plain.serial == one_tile.serial);
  REQUIRE(one_tile.tile_count() == 1);
  CHECK(one_tile.tile_colour_begin[1] == one_tile.colour_count());
}

TEST_CASE("A sphere with more contacts than parallel colours overflows into a serial colour of its tile",
          "[solver][colouring]") {
  // Sphere 10 touches 70 others of its tile (0..127) and 70 of the next tile: 64 parallel
  // colours and one serial colour each, in the tile and among the shared contacts.
  std::vector<Contact> contacts;
  for (std::uint32_t k = 0; k < 70; ++k) contacts.push_back(Contact{.a = 10, .b = k < 10 ? k : k + 1});
  for (std::uint32_t k = 0; k < 70; ++k) contacts.push_back(Contact{.a = 10, .b = 128 + k});
  contacts.push_back(Contact{.a = 200, .b = kStaticBody});
  ContactColouring col;
  colour_contacts(contacts, 256, col, 128);
  check_colouring(contacts, col, 128);
  REQUIRE(col.tile_count() == 2);
  const std::size_t tile0 = col.tile_colour_begin[1] - col.tile_colour_begin[0];
  CHECK(tile0 == kMaxParallelColours + 1);
  CHECK(col.is_serial(col.tile_colour_begin[1] - 1));
  CHECK(col.colour_begin[col.tile_colour_begin[1]] - col.colour_begin[col.tile_colour_begin[1] - 1] == 70 - 64);
  CHECK(col.tile_colour_begin[2] - col.tile_colour_begin[1] == 1);  // sphere 200's ground contact
  CHECK(col.colour_count() - col.shared_colour_begin() == kMaxParallelColours + 1);
  CHECK(col.is_serial(col.colour_count() - 1));
  CHECK(std::count(col.serial.begin(), col.serial.end(), 1) == 2);
}

TEST_CASE("SlotDivider divides every slot exactly as the division does", "[colouring]") {
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::uint32_t> any_slot;
  for (const std::uint32_t d : {1u, 2u, 3u, 5u, 7u, 64u, 100u, 641u, 2047u, 2048u, 2049u, 65535u, 1u << 20,
                                (1u << 31) - 1u, 1u << 31, 0xFFFFFFFFu}) {
    INFO("d = " << d);
    const hail::SlotDivider divide(d);
    std::size_t wrong = 0;
    auto check = [&](std::uint32_t slot) { wrong += divide(slot) != slot / d; };
    for (std::uint32_t slot = 0; slot < 20000; ++slot) check(slot);
    // Around the multiples of d, at the top of the fast range and above it.
    for (std::uint64_t q = 1; q < 64; ++q)
      for (std::int64_t e = -2; e <= 2; ++e) {
        const std::int64_t slot = static_cast<std::int64_t>(q * d) + e;
        if (slot >= 0 && slot <= 0xFFFFFFFFll) check(static_cast<std::uint32_t>(slot));
      }
    for (std::uint32_t slot : {(1u << 31) - 3u, (1u << 31) - 2u, (1u << 31) - 1u, 1u << 31, 0xFFFFFFFEu, 0xFFFFFFFFu})
      check(slot);
    for (int k = 0; k < 100000; ++k) check(any_slot(rng) >> (k % 2));  // half of them below 2^31
    CHECK(wrong == 0);
  }
}

TEST_CASE("Speculative contacts closing by less than half their gap go last in their colour", "[solver][colouring]") {
  // Spheres 0..5 on the x axis, contacts (0,1), (2,3), (4,5) and 1 on the ground: one colour.
  const float vx[7] = {0.0f, 0.0f, 1.0f, -1.0f, 0.1f, 0.0f, 0.0f}, vy[7] = {0, 0, 0, 0, 0, 0, -0.2f}, vz[7] = {};
  const SolveStartVelocities velocities{vx, vy, vz, 60.0f};
  auto contact = [](std::uint32_t a, std::uint32_t b, float gap, float impulse) {
    Contact c{.a = a, .b = b};
    // n points from a to b: down into the ground for a static contact
    c.nx = b == kStaticBody ? 0.0f : 1.0f, c.ny = b == kStaticBody ? -1.0f : 0.0f, c.nz = 0.0f;
    c.gap = gap, c.normal_impulse = impulse;
    return c;
  };
  const std::vector<Contact> contacts = {
      contact(0, 1, 0.02f, 0.3f),             // pressing (carried-over impulse): first
      contact(2, 3, 0.02f, 0.0f),             // closing at 2 m/s, more than half of 0.02 m in 1/60 s: first
      contact(4, 5, 0.02f, 0.0f),             // closing at 0.1 m/s: idle, last
      contact(6, kStaticBody, 0.01f, 0.0f)};  // falling at 0.2 m/s onto the ground, below half of 0.6: idle
  CHECK_FALSE(starts_idle(contacts[0], &velocities));
  CHECK_FALSE(starts_idle(contacts[1], &velocities));
  CHECK(starts_idle(contacts[1]));  // without velocities the gap alone decides
  CHECK(starts_idle(contacts[2], &velocities));
  CHECK(starts_idle(contacts[3], &velocities));
  ContactColouring col;
  colour_contacts(contacts, 7, col, 0, &velocities);
  REQUIRE(col.colour_count() == 1);
  CHECK(col.order == std::vector<std::uint32_t>{0, 1, 2, 3});
  // A faster fall onto the ground (1 m/s, more than half of 0.6) is not idle.
  const float faster[7] = {0, 0, 0, 0, 0, 0, -1.0f};
  const SolveStartVelocities falling{vx, faster, vz, 60.0f};
  CHECK_FALSE(starts_idle(contacts[3], &falling));
}

namespace {

/// Contacts in detection order as the step makes them, with the block offsets: static blocks
/// of `static_block` slots (each block's "plane" contacts for its spheres, then its "terrain"
/// contacts: not in slot order within the block), then blocks of pairs (a, b > a) by rows of
/// `pair_block` slots, rows ascending.
struct Detected {
  std::vector<Contact> contacts;
  std::vector<std::size_t> static_offsets, pair_offsets;
};
Detected detected_contacts(std::size_t spheres, std::size_t static_block, std::size_t pair_block, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<int> near(1, 60);
  Detected d;
  auto state = [&](Contact& c) {
    const float s = unit(rng);
    c.gap = s < 0.34f ? 0.01f : 0.0f;
    c.normal_impulse = s > 0.67f ? 0.5f : 0.0f;
  };
  d.static_offsets.push_back(0);
  for (std::size_t first = 0; first < spheres; first += static_block) {
    const std::size_t last = std::min(spheres, first + static_block);
    for (int kind = 0; kind < 2; ++kind)
      for (std::size_t a = first; a < last; ++a)
        if (unit(rng) < 0.4f) {
          Contact c{.a = static_cast<std::uint32_t>(a), .b = kStaticBody};
          state(c);
          d.contacts.push_back(c);
        }
    d.static_offsets.push_back(d.contacts.size());
  }
  d.pair_offsets.push_back(d.contacts.size());
  for (std::size_t first = 0; first < spheres; first += pair_block) {
    for (std::size_t a = first; a < std::min(spheres, first + pair_block); ++a) {
      std::set<std::size_t> partners;
      const int count = static_cast<int>(4.0f * unit(rng));
      for (int m = 0; m < count; ++m) {
        const std::size_t b = a + static_cast<std::size_t>(unit(rng) < 0.9f ? near(rng) : 1 + near(rng) * 20);
        if (b < spheres) partners.insert(b);
      }
      if (a == 7)
        for (std::size_t b = 8; b < std::min(spheres, std::size_t{90}); ++b) partners.insert(b);  // overflows
      for (std::size_t b : partners) {
        Contact c{.a = static_cast<std::uint32_t>(a), .b = static_cast<std::uint32_t>(b)};
        state(c);
        d.contacts.push_back(c);
      }
    }
    d.pair_offsets.push_back(d.contacts.size());
  }
  return d;
}

}  // namespace

TEST_CASE("Tiles coloured in parallel (TiledColouring) give colour_contacts' colouring bit for bit",
          "[solver][colouring]") {
  for (const std::size_t spheres : {std::size_t{300}, std::size_t{5000}})
    for (const std::size_t tile : {std::size_t{100}, std::size_t{256}, std::size_t{2048}, std::size_t{8192}}) {
      INFO(spheres << " spheres, tiles of " << tile);
      const Detected d = detected_contacts(spheres, 256, 64, static_cast<std::uint32_t>(spheres + tile));
      ContactColouring serial, tiled;
      colour_contacts(d.contacts, spheres, serial, tile);
      check_colouring(d.contacts, serial, tile);
      TiledColouring parts;
      const DetectionBlocks blocks{d.static_offsets, d.pair_offsets, 256, 64};
      for (int run = 0; run < 2; ++run) {  // reused storage: the first run must not leak into the second
        const std::size_t tiles = parts.begin(d.contacts, blocks, spheres, tiled, tile, nullptr);
        REQUIRE(tiles == (spheres + tile - 1) / tile);
        // The tiles in any order (threads take them as they come): here last to first.
        for (std::size_t t = tiles; t-- > 0;) parts.colour_tile(t);
        parts.colour_shared();
        for (std::size_t t = tiles; t-- > 0;) parts.place_tile(t);
        CHECK(tiled.order == serial.order);
        CHECK(tiled.colour_begin == serial.colour_begin);
        CHECK(tiled.tile_colour_begin == serial.tile_colour_begin);
        CHECK(tiled.serial == serial.serial);
      }
      // The cases mean something: shared contacts, a serial overflow colour.
      if (tile == 100) CHECK(serial.colour_begin.back() - serial.colour_begin[serial.shared_colour_begin()] > 0);
      CHECK(std::any_of(serial.serial.begin(), serial.serial.end(), [](std::uint8_t s) { return s != 0; }));
    }
}
