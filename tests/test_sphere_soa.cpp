// SphereSoA: alignment, inert padding, stable handles across removal and permutation.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "catch.h"
#include "hail/sphere_soa.h"

namespace {
hail::SphereRecord record(float x) { return {x, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 1, 1, 0.5f, 0.5f, 0}; }
}  // namespace

TEST_CASE("Arrays are 64-byte aligned and padded with inert lanes", "[soa]") {
  hail::SphereSoA s;
  for (int k = 0; k < 5; ++k) s.add(record(float(k)));
  REQUIRE(s.padded_size() % hail::kSimdPadding == 0);
  REQUIRE(s.px.size() >= s.padded_size());
  CHECK(reinterpret_cast<std::uintptr_t>(s.px.data()) % 64 == 0);
  CHECK(reinterpret_cast<std::uintptr_t>(s.radius.data()) % 64 == 0);
  for (std::size_t k = s.size(); k < s.padded_size(); ++k) {
    CHECK(s.radius[k] == 0.0f);
    CHECK(s.inv_mass[k] == 0.0f);
    CHECK(s.px[k] == hail::kPaddingPosition);
  }
}

TEST_CASE("Handles stay valid when spheres are removed and slots move", "[soa]") {
  hail::SphereSoA s;
  std::vector<hail::SphereId> ids;
  for (int k = 0; k < 40; ++k) ids.push_back(s.add(record(float(k))));
  REQUIRE(s.remove(ids[3]));
  REQUIRE(s.remove(ids[0]));
  CHECK_FALSE(s.remove(ids[0]));  // stale now
  CHECK(s.slot_of(ids[0]) < 0);
  CHECK(s.size() == 38);
  for (int k = 0; k < 40; ++k) {
    if (k == 0 || k == 3) continue;
    const auto slot = s.slot_of(ids[k]);
    REQUIRE(slot >= 0);
    CHECK(s.px[static_cast<std::size_t>(slot)] == float(k));
  }
  // A recycled id index gets a new generation: the old handle stays stale.
  const hail::SphereId fresh = s.add(record(100));
  CHECK(fresh != ids[0]);
  CHECK(s.slot_of(ids[0]) < 0);
  CHECK(s.px[static_cast<std::size_t>(s.slot_of(fresh))] == 100.0f);
  // Padding after removal is inert again.
  for (std::size_t k = s.size(); k < s.padded_size(); ++k) CHECK(s.radius[k] == 0.0f);
}

TEST_CASE("Permuting slots keeps every handle on its sphere", "[soa]") {
  hail::SphereSoA s;
  std::vector<hail::SphereId> ids;
  for (int k = 0; k < 20; ++k) ids.push_back(s.add(record(float(k))));
  std::vector<std::uint32_t> order;
  for (std::uint32_t k = 0; k < 20; ++k) order.push_back(19 - k);
  s.permute(order);
  for (int k = 0; k < 20; ++k) CHECK(s.px[static_cast<std::size_t>(s.slot_of(ids[k]))] == float(k));
}

TEST_CASE("Permuting over ranges run in any order gives permute's state", "[soa]") {
  // The World's re-sort runs permute's loops over blocks in parallel (kernel/world/step_pipeline.cpp).
  hail::SphereSoA serial, blocked;
  std::vector<hail::SphereId> ids;
  for (int k = 0; k < 100; ++k) {
    hail::SphereRecord r = record(float(k));
    r.vy = float(2 * k), r.wz = float(3 * k), r.friction = 0.01f * float(k);
    ids.push_back(serial.add(r));
    blocked.add(r);
  }
  std::vector<std::uint32_t> order;
  for (std::uint32_t k = 0; k < 100; ++k) order.push_back((k * 37) % 100);  // 37 is prime to 100
  serial.permute(order);
  std::size_t calls = 0;
  blocked.permute(order, true, true, [&](std::size_t count, auto&& f) {
    constexpr std::size_t kBlock = 7;
    for (std::size_t first = (count - 1) / kBlock * kBlock;; first -= kBlock) {  // last block first
      f(first, std::min(count, first + kBlock));
      ++calls;
      if (first == 0) break;
    }
  });
  CHECK(calls > 0);
  for (std::size_t k = 0; k < 100; ++k) {
    CHECK(blocked.px[k] == serial.px[k]);
    CHECK(blocked.vy[k] == serial.vy[k]);
    CHECK(blocked.wz[k] == serial.wz[k]);
    CHECK(blocked.friction[k] == serial.friction[k]);
    CHECK(blocked.flags[k] == serial.flags[k]);
    CHECK(blocked.id_at(k) == serial.id_at(k));
  }
  for (std::size_t k = 0; k < 100; ++k) CHECK(blocked.slot_of(ids[k]) == serial.slot_of(ids[k]));
  CHECK(serial.px[1] == 37.0f);  // the permutation really moved spheres
}

TEST_CASE("Reserved capacity means adding spheres does not reallocate", "[soa]") {
  hail::SphereSoA s;
  s.reserve(1000);
  const float* before = s.px.data();
  for (int k = 0; k < 1000; ++k) s.add(record(float(k)));
  CHECK(s.px.data() == before);
}
