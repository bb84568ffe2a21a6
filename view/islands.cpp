#include "view/islands.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hail::view {

void island_labels(const World& world, std::vector<std::uint32_t>& out) {
  const SphereSoA& s = world.soa();
  const std::size_t n = world.sphere_count();
  // Union-find over slots; each root then takes the smallest handle index of its set.
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const Contact& c : world.last_contacts()) {
    if (c.b == kStaticBody || c.a >= n || c.b >= n) continue;
    if (s.inv_mass[c.a] == 0.0f || s.inv_mass[c.b] == 0.0f) continue;
    const std::uint32_t a = find(c.a), b = find(c.b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<std::uint32_t> smallest(n, kNoIsland);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t root = find(std::uint32_t(i));
    smallest[root] = std::min(smallest[root], world.id_at(i).index);
  }
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (s.inv_mass[i] == 0.0f)
      out[i] = kNoIsland;
    else if ((s.flags[i] & kSphereFlagSleeping) != 0)
      out[i] = s.sleep_island[i];
    else
      out[i] = smallest[find(std::uint32_t(i))];
  }
}

std::array<float, 3> island_colour(std::uint32_t label) {
  if (label == kNoIsland) return {0.5f, 0.5f, 0.5f};
  // Knuth's multiplicative hash, its top bits the hue: labels 1 apart land far apart on the wheel.
  const float hue = float((label * 2654435761u) >> 8) / float(1u << 24) * 6.0f;
  const float x = 1.0f - std::fabs(std::fmod(hue, 2.0f) - 1.0f);
  constexpr float kLow = 0.15f, kHigh = 0.95f;  // saturation ~0.85, value 0.95
  const float mid = kLow + (kHigh - kLow) * x;
  switch (int(hue)) {
    case 0:
      return {kHigh, mid, kLow};
    case 1:
      return {mid, kHigh, kLow};
    case 2:
      return {kLow, kHigh, mid};
    case 3:
      return {kLow, mid, kHigh};
    case 4:
      return {mid, kLow, kHigh};
    default:
      return {kHigh, kLow, mid};
  }
}

}  // namespace hail::view
