#include "view/replay.h"

#include <cmath>

namespace hail::view {

void Replay::load(std::size_t k, Frame& out) {
  const RecordingHeader& h = reader_.header();
  const std::size_t n = h.handles.size();
  reader_.read_frame(k, frame_);
  const bool from_previous = !h.velocities && k > 0;
  if (from_previous) reader_.read_frame(k - 1, previous_);
  out.step = frame_.step;
  out.centre = frame_.positions;
  out.radius = h.radii;
  out.speed.assign(n, 0.0f);
  const float seconds = from_previous ? float(frame_.step - previous_.step) * h.dt : 1.0f;
  for (std::size_t s = 0; s < n; ++s) {
    const float* v = h.velocities ? &frame_.velocities[3 * s] : nullptr;
    float d[3] = {0, 0, 0};
    if (v) d[0] = v[0], d[1] = v[1], d[2] = v[2];
    if (from_previous && seconds > 0.0f)
      for (int c = 0; c < 3; ++c) d[c] = (frame_.positions[3 * s + c] - previous_.positions[3 * s + c]) / seconds;
    out.speed[s] = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }
  out.phase_ms = {};
  out.step_ms = 0.0;
  out.kinetic_energy = 0.0;
}

}  // namespace hail::view
