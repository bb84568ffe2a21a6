#pragma once
// WorldServices: what the World keeps for its callers between steps, beside the sphere state
// and the step's scratch (kernel/world/step_scratch.h): touch and hit events, sleeping islands,
// the spatial queries' cache, and apply_impulses' undo list. World holds it by pointer
// (include/hail/world.h), so that its header needs none of these internal types.

#include <array>
#include <vector>

#include "kernel/world/contact_events.h"
#include "kernel/world/sleep_islands.h"
#include "kernel/world/sphere_query_cache.h"

namespace hail {

struct WorldServices {
  /// Touch and hit events (World::set_events); its touching keys persist between steps.
  ContactEventTracker events;
  /// Sleeping: islands, waking, sleep and wake events (WorldSettings::sleep).
  SleepIslands sleep;
  /// World queries: the BVH over the spheres, rebuilt at the first query after a change.
  SphereQueryCache sphere_queries;
  /// World::apply_impulses: each entry's velocity before it, to put back if a later one is refused.
  std::vector<std::array<float, 3>> impulse_undo;
};

}  // namespace hail
