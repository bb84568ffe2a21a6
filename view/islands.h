#pragma once
// The colour modes' per-sphere data: which island each sphere is in (the --colour island mode)
// and the colour an island label is drawn in. No OpenGL: hail-view-tests checks them.

#include <array>
#include <cstdint>
#include <vector>

#include "hail/world.h"

namespace hail::view {

/// The island label of an immovable sphere (static or kinematic): it joins no island
/// (kernel/world/sleep_islands.h), and is drawn grey.
inline constexpr std::uint32_t kNoIsland = 0xFFFFFFFFu;

/// Per slot, the label of the sphere's island, by the kernel's rule (sleep_islands.h): movable
/// spheres joined by the last step's sphere-sphere contacts form one island, the terrain,
/// planes and immovable spheres join none; its label is the smallest handle index in it, the
/// label a sleeping island keeps (SphereSoA::sleep_island), which a sleeper takes here (its
/// contacts are left out of last_contacts()). A lone sphere is an island of one. O(spheres +
/// contacts): a union-find over the contacts.
void island_labels(const World& world, std::vector<std::uint32_t>& out);

/// An island's colour, RGB in [0, 1]: a hue from a hash of the label, so that neighbouring
/// islands (labels close together) differ; grey for kNoIsland.
[[nodiscard]] std::array<float, 3> island_colour(std::uint32_t label);

}  // namespace hail::view
