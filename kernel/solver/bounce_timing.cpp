#include "kernel/solver/bounce_timing.h"

#include <algorithm>
#include <cmath>

#include "soa/heap_bytes.h"

namespace hail {

namespace {

/// The collision passes bounced c (a speculative static contact) this step.
[[nodiscard]] bool speculative_bounce(const Contact& c) {
  return c.bounce_impulse > 0.0f && c.b == kStaticBody && c.gap > 0.0f;  // most contacts fail the first
}

[[nodiscard]] float dot(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Surface gap of a static contact's linearised plane for a centre at x (Contact::surface_d).
[[nodiscard]] float static_gap(const Contact& c, const float x[3], float radius) {
  const float n[3] = {c.nx, c.ny, c.nz};
  return c.surface_d - dot(n, x) - radius;
}

/// Surface gap of two spheres with centres x and y.
[[nodiscard]] float sphere_gap(const float x[3], const float y[3], float radii) {
  const float d[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
  return std::sqrt(dot(d, d)) - radii;
}

}  // namespace

BounceTiming::Timed* BounceTiming::find(std::uint32_t sphere) {
  auto it = std::lower_bound(timed_.begin(), timed_.end(), sphere,
                             [](const Timed& t, std::uint32_t i) { return t.sphere < i; });
  return it != timed_.end() && it->sphere == sphere ? &*it : nullptr;
}

void BounceTiming::plan(std::span<const Contact> contacts, const SphereSoA& s, const IntegrationParams& p,
                        std::span<const std::uint8_t> swept) {
  timed_.clear();
  neighbours_.clear();
  for (std::size_t k = 0; k < contacts.size(); ++k)
    if (speculative_bounce(contacts[k]))
      timed_.push_back({.sphere = contacts[k].a, .contact = static_cast<std::uint32_t>(k)});
  if (timed_.empty()) return;
  std::sort(timed_.begin(), timed_.end(), [](const Timed& x, const Timed& y) {
    return x.sphere != y.sphere ? x.sphere < y.sphere : x.contact < y.contact;
  });
  // Two bounces of one sphere (a corner, a valley): which came first is the solve's order, not
  // the sphere's path. Such a sphere keeps the integrator's motion.
  for (std::size_t k = 1; k < timed_.size(); ++k)
    if (timed_[k].sphere == timed_[k - 1].sphere) timed_[k].keep = timed_[k - 1].keep = false;
  const std::size_t words = (s.size() + 63) / 64;
  if (marks_.size() < words) marks_.resize(words, 0);  // all zero: apply clears what it set
  for (Timed& t : timed_) {
    marks_[t.sphere >> 6] |= std::uint64_t{1} << (t.sphere & 63);
    if (!swept.empty() && swept[t.sphere]) t.keep = false;
    if (!holds_no_impulse(contacts[t.contact])) t.keep = false;  // it rested as well as bounced
  }
  // The planned spheres' other contacts: one that carries an impulse changed the sphere's
  // velocity too, so the bounce alone cannot be re-timed; an idle one is checked after the
  // integration (apply). Two planned spheres touching keep the integrator's motion.
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    const bool dynamic_b = c.b != kStaticBody;
    const bool a_planned = marked(c.a), b_planned = dynamic_b && marked(c.b);
    if (!a_planned && !b_planned) continue;
    if (speculative_bounce(c)) continue;  // a planned bounce (or a second one, already refused)
    const bool pushes = !holds_no_impulse(c) || c.bounce_impulse != 0.0f;
    if (a_planned && (pushes || b_planned)) find(c.a)->keep = false;
    if (b_planned && (pushes || a_planned)) find(c.b)->keep = false;
    if (!pushes) neighbours_.push_back(static_cast<std::uint32_t>(k));
  }
  for (Timed& t : timed_)
    if (t.keep) timed_motion(contacts[t.contact], s, p, t);
}

/// The motion integrate_positions gives a sphere against a plane (bounce_off_planes), with the
/// contact's plane: the sphere's velocity without the bounce's normal impulse, the acceleration
/// the integrator would take from it, the impact at its time, restitution from the speed there.
void BounceTiming::timed_motion(const Contact& c, const SphereSoA& s, const IntegrationParams& p, Timed& t) const {
  const std::uint32_t i = t.sphere;
  const float n[3] = {c.nx, c.ny, c.nz};  // into the surface
  const float undo = c.bounce_impulse * s.inv_mass[i];
  const float v_end[3] = {s.vx[i] + undo * n[0], s.vy[i] + undo * n[1], s.vz[i] + undo * n[2]};
  float a[3] = {0.0f, 0.0f, 0.0f};
  if (p.modes.uniform_acceleration()) uniform_step_acceleration(s, i, p, v_end, a);
  float u[3] = {v_end[0] - a[0] * p.dt, v_end[1] - a[1] * p.dt, v_end[2] - a[2] * p.dt};
  float x[3] = {s.px[i], s.py[i], s.pz[i]};
  const float gap = static_gap(c, x, s.radius[i]);
  // Along the plane's outward normal -n, as bounce_off_planes measures.
  const double hit = gap > 0.0f ? earliest_root(gap, -dot(n, u), -dot(n, a), p.dt) : -1.0;
  if (!(hit > 0.0)) {  // rounding: the solve's test passed, the exact root lies past the step
    t.keep = false;
    return;
  }
  const float th = static_cast<float>(hit);
  for (int d = 0; d < 3; ++d) {
    x[d] += u[d] * th + 0.5f * a[d] * th * th;
    u[d] += a[d] * th;
  }
  const float closing = dot(n, u);
  if (!(closing > 0.0f)) {
    t.keep = false;
    return;
  }
  const float e = closing > p.restitution_threshold ? c.restitution : 0.0f;
  for (int d = 0; d < 3; ++d) u[d] -= (1.0f + e) * closing * n[d];
  const float remaining = p.dt - th;
  // Pulled into the surface and back on it before the step ends: it rests there for the rest
  // of the step (bounce_off_planes' rule).
  const float an = -dot(n, a);
  if (an < 0.0f) {
    const float un = -dot(n, u);
    if (2.0f * un < -an * remaining)
      for (int d = 0; d < 3; ++d) a[d] += an * n[d], u[d] += un * n[d];
  }
  for (int d = 0; d < 3; ++d) {
    t.x[d] = x[d] + u[d] * remaining + 0.5f * a[d] * remaining * remaining;
    t.v[d] = u[d] + a[d] * remaining;
  }
}

std::size_t BounceTiming::apply(std::span<const Contact> contacts, SphereSoA& s) {
  if (timed_.empty()) return 0;
  auto position = [&](std::uint32_t i, float x[3]) { x[0] = s.px[i], x[1] = s.py[i], x[2] = s.pz[i]; };
  // An idle contact may end overlapping on the timed path (the sphere went nearer the surface
  // before it bounced): only as deep as on the integrator's path, or not at all.
  for (std::uint32_t k : neighbours_) {
    const Contact& c = contacts[k];
    for (const std::uint32_t end : {c.a, c.b}) {
      if (end == kStaticBody || !marked(end)) continue;
      Timed* t = find(end);
      if (!t->keep) continue;
      float moved_x[3];
      position(end, moved_x);
      float ended = 0.0f, timed = 0.0f;
      if (c.b == kStaticBody) {
        ended = static_gap(c, moved_x, s.radius[end]);
        timed = static_gap(c, t->x, s.radius[end]);
      } else {
        float other[3];
        position(end == c.a ? c.b : c.a, other);
        const float radii = s.radius[c.a] + s.radius[c.b];
        ended = sphere_gap(moved_x, other, radii);
        timed = sphere_gap(t->x, other, radii);
      }
      if (timed < 0.0f && timed < ended) t->keep = false;
    }
  }
  std::size_t moved = 0;
  for (const Timed& t : timed_) {
    marks_[t.sphere >> 6] &= ~(std::uint64_t{1} << (t.sphere & 63));
    if (!t.keep) continue;
    s.px[t.sphere] = t.x[0], s.py[t.sphere] = t.x[1], s.pz[t.sphere] = t.x[2];
    s.vx[t.sphere] = t.v[0], s.vy[t.sphere] = t.v[1], s.vz[t.sphere] = t.v[2];
    ++moved;
  }
  timed_.clear();
  neighbours_.clear();
  return moved;
}

std::size_t BounceTiming::heap_bytes() const { return heap_bytes_of(timed_, neighbours_, marks_); }

}  // namespace hail
