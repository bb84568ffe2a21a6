#pragma once
// What the refusal tests check after every refused call: an InvalidArgument whose message names
// the value, and a World exactly as it was before the call.

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>

#include "catch.h"
#include "hail/world.h"

namespace hail::testing {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr float kInf = std::numeric_limits<float>::infinity();

/// What a refused call must leave as it was.
struct WorldSnapshot {
  std::size_t spheres, planes;
  std::uint64_t hash;
  friend bool operator==(const WorldSnapshot&, const WorldSnapshot&) = default;
};
inline WorldSnapshot snapshot(const World& w) { return {w.sphere_count(), w.planes().size(), w.state_hash()}; }

/// Runs `call`, which must throw InvalidArgument whose message contains every needle, and
/// checks the world did not change.
template <class Call>
void expect_rejected(World& w, Call&& call, std::initializer_list<std::string> needles) {
  const WorldSnapshot before = snapshot(w);
  try {
    call();
    FAIL("expected hail::InvalidArgument mentioning '" << *needles.begin() << "'");
  } catch (const InvalidArgument& e) {
    INFO("message: " << e.what());
    for (const std::string& needle : needles) CHECK(std::string(e.what()).find(needle) != std::string::npos);
  }
  CHECK(snapshot(w) == before);
}

template <class Call>
void expect_rejected(World& w, Call&& call, const std::string& needle) {
  expect_rejected(w, std::forward<Call>(call), {needle});
}

}  // namespace hail::testing
