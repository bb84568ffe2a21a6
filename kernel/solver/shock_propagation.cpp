#include "kernel/solver/shock_propagation.h"

#include <algorithm>

#include "kernel/solver/contact_impulse.h"
#include "soa/grow.h"

namespace hail {

namespace {
constexpr std::uint32_t kNone = ShockPropagation::kNoLevel;

bool immovable(const SolverBody& b) { return b.inv_mass <= 0.0f; }
}  // namespace

void ShockPropagation::plan(std::span<const Contact> contacts, std::span<const SolverBody> bodies, const Vec3& up) {
  up_ = up;
  const std::size_t n = bodies.size() - 1;  // the last body is the static one
  assign_geometric(level_, n, kNone);
  assign_geometric(first_edge_, n + 1, std::uint32_t{0});
  queue_.clear();
  // Neighbour lists (compressed rows) of the sphere-sphere contacts; the ground seeds the search.
  for (const Contact& c : contacts) {
    if (c.b == kStaticBody) continue;
    ++first_edge_[c.a + 1];
    ++first_edge_[c.b + 1];
  }
  for (std::size_t i = 0; i < n; ++i) first_edge_[i + 1] += first_edge_[i];
  resize_geometric(edges_, first_edge_[n]);
  for (const Contact& c : contacts) {
    if (c.b == kStaticBody) continue;
    edges_[first_edge_[c.a]++] = c.b;
    edges_[first_edge_[c.b]++] = c.a;
  }
  for (std::size_t i = n; i > 0; --i) first_edge_[i] = first_edge_[i - 1];  // undo the fill's advance
  first_edge_[0] = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (immovable(bodies[i])) level_[i] = 0, queue_.push_back(static_cast<std::uint32_t>(i));
  for (const Contact& c : contacts)
    if (c.b == kStaticBody && level_[c.a] == kNone) level_[c.a] = 1, queue_.push_back(c.a);
  // Breadth first: the queue holds level 0, then level 1, ... so each sphere gets its least level.
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const std::uint32_t i = queue_[head];
    for (std::uint32_t e = first_edge_[i]; e < first_edge_[i + 1]; ++e) {
      const std::uint32_t j = edges_[e];
      if (level_[j] == kNone) level_[j] = level_[i] + 1, queue_.push_back(j);
    }
  }
  // Contacts by the lower level of their two bodies (static geometry: 0), stable in index.
  auto key = [&](const Contact& c) { return c.b == kStaticBody ? 0u : std::min(level_[c.a], level_[c.b]); };
  std::uint32_t top = 0;
  for (std::uint32_t l : level_)
    if (l != kNone) top = std::max(top, l);
  assign_geometric(level_count_, top + 2, std::uint32_t{0});
  for (const Contact& c : contacts)
    if (const std::uint32_t k = key(c); k != kNone) ++level_count_[k + 1];
  for (std::size_t l = 0; l + 1 < level_count_.size(); ++l) level_count_[l + 1] += level_count_[l];
  resize_geometric(order_, level_count_.back());
  for (std::uint32_t k = 0; k < contacts.size(); ++k)
    if (const std::uint32_t l = key(contacts[k]); l != kNone) order_[level_count_[l]++] = k;
}

ShockPropagation::Holder ShockPropagation::holder(const Contact& c) const {
  if (c.b == kStaticBody) return Holder::B;
  const std::uint32_t la = level_[c.a], lb = level_[c.b];
  if (la != lb) return la < lb ? Holder::A : Holder::B;
  return holder_by_height(c, up_);
}

ShockPropagation::Holder ShockPropagation::holder_by_height(const Contact& c, const Vec3& up) {
  // The normal points from a to b: b sits on a where it points up.
  const float rise = c.nx * up.x() + c.ny * up.y() + c.nz * up.z();
  return rise > kBelowCosine ? Holder::A : (rise < -kBelowCosine ? Holder::B : Holder::None);
}

namespace {

void shock_pass(const ShockPropagation& shock, std::span<const Contact> contacts, std::span<SolverBody> bodies,
                float inv_dt) {
  for (const std::uint32_t index : shock.order()) {
    const Contact& c = contacts[index];
    ContactBodies k = gather_bodies<kLinearFriction>(bodies, c);
    if (c.b != kStaticBody) {
      // The lower body holds still: it was settled earlier in this pass, or is the ground.
      const ShockPropagation::Holder holder = shock.holder(c);
      if (holder == ShockPropagation::Holder::A) k.ima = 0.0f, k.iia = 0.0f;
      if (holder == ShockPropagation::Holder::B) k.imb = 0.0f, k.iib = 0.0f;
    }
    const float kn = normal_mass_denominator(k);
    if (kn <= 0.0f) continue;
    const float vn = normal_relative_velocity(c, k);
    const float allowed_closing = c.gap > 0.0f ? c.gap * inv_dt : 0.0f;
    const float j = -(vn + allowed_closing) / kn;
    if (!(j > 0.0f)) continue;  // not closing faster than its gap allows
    const float p[3] = {j * c.nx, j * c.ny, j * c.nz};
    apply_linear_impulse(k, p);  // along n: through both centres, no torque
    scatter_bodies<kLinearFriction>(bodies, c, k);
  }
}

}  // namespace

void ShockPropagation::solve(std::span<const Contact> contacts, std::span<SolverBody> bodies, float inv_dt) const {
  shock_pass(*this, contacts, bodies, inv_dt);
}

}  // namespace hail
