// World's touch and hit event calls (include/hail/world.h, "Touch and hit events"); the events
// themselves are made by ContactEventTracker (kernel/world/contact_events.h) during World::step.

#include <cmath>
#include <string>

#include "hail/world.h"
#include "kernel/world/world_checks.h"
#include "kernel/world/world_services.h"

namespace hail {

void World::set_events(const EventSettings& settings) {
  checks::require(std::isfinite(settings.hit_speed) && settings.hit_speed >= 0.0f, [&] {
    return "set_events: hit_speed must be finite and >= 0 m/s, got " + checks::number(settings.hit_speed);
  });
  services_->events.configure(settings);
}

const EventSettings& World::event_settings() const { return services_->events.settings(); }
std::span<const TouchEvent> World::touch_begin_events() const { return services_->events.touch_begin(); }
std::span<const TouchEvent> World::touch_end_events() const { return services_->events.touch_end(); }
std::span<const HitEvent> World::hit_events() const { return services_->events.hits(); }

}  // namespace hail
