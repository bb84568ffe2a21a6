// World's sleeping calls (include/hail/world.h, "Sleeping"); the islands, the sleep decisions
// and the waking rules are SleepIslands' (kernel/world/sleep_islands.h).

#include "hail/world.h"
#include "kernel/world/world_services.h"

namespace hail {

bool World::is_sleeping(SphereId id) const { return sphere_sleeps(spheres_, require_slot(id)); }
std::span<const SphereId> World::sleep_events() const { return services_->sleep.slept(); }
std::span<const SphereId> World::wake_events() const { return services_->sleep.woken(); }

void World::wake(std::size_t slot) {
  if (settings_.sleep) services_->sleep.wake_around(spheres_, slot);
}

void World::wake_all() {
  if (settings_.sleep) services_->sleep.wake_all(spheres_);
}

}  // namespace hail
