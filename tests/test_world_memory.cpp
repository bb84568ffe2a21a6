// World::memory_use: the heap bytes of a World by part, from its buffers' capacities.

#include <cstddef>

#include "catch.h"
#include "hail/world.h"

using namespace hail;

TEST_CASE("memory_use counts the sphere arrays and the contacts a step keeps", "[memory]") {
  World world({.threads = 1});
  world.add_plane({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.2f, .friction = 0.5f});
  const MemoryUse empty = world.memory_use();
  constexpr int kSide = 16;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)
      for (int k = 0; k < 2; ++k)
        world.add_sphere({.position = {1.0f * float(i), 0.5f + 0.99f * float(k), 1.0f * float(j)}, .radius = 0.5f, .mass = 1});
  const std::size_t n = world.sphere_count();
  const MemoryUse added = world.memory_use();
  // Every per-sphere array holds room for each sphere: positions, velocities and spins alone are
  // nine floats.
  CHECK(added.spheres >= empty.spheres + n * 9 * sizeof(float));
  for (int s = 0; s < 3; ++s) world.step(1.0f / 60.0f);
  const MemoryUse stepped = world.memory_use();
  // The merged contact list alone holds every contact of the last step; the warm-start cache keeps
  // an impulse for each.
  REQUIRE(world.last_contacts().size() > n);
  CHECK(stepped.contacts >= world.last_contacts().size() * sizeof(Contact));
  CHECK(stepped.warm_start > 0);
  CHECK(stepped.solver >= n * 4 * sizeof(float));  // a solver body per sphere: at least its velocity and inverse mass
  CHECK(stepped.total() == stepped.spheres + stepped.pairs + stepped.contacts + stepped.solver + stepped.warm_start +
                               stepped.sweep + stepped.per_sphere + stepped.services);
}
