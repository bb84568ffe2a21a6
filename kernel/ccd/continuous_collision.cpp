#include "kernel/ccd/continuous_collision.h"

#include <algorithm>
#include <cmath>

#include "kernel/broadphase/sphere_filters.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/ccd/path_box_scan.h"
#include "kernel/dispatch/kernel_table.h"
#include "kernel/geometry/coincident_normal.h"
#include "kernel/geometry/swept_sphere.h"
#include "kernel/solver/contact_impulse.h"
#include "soa/grow.h"

namespace hail {
namespace {

constexpr double kNoEvent = -1.0;

/// A sphere counts as still touching what it hit (its backer) while the gap between them is no
/// more than this fraction of its radius (the gap a pinched sphere's bounces leave shrinks
/// impact by impact, so the threshold only sets how many impacts come before it is held).
constexpr double kHeldGapFraction = 0.25;
/// And the strike presses it into the backer: within 60 degrees of their normal.
constexpr double kHeldPressCosine = 0.5;

/// Float boxes around double paths are grown by this much (relative to the coordinates, plus
/// 0.1 mm) so that rounding can only add candidates, never drop one.
float box_padding(const double lo[3], const double hi[3]) {
  double largest = 0.0;
  for (int d = 0; d < 3; ++d) largest = std::max({largest, std::fabs(lo[d]), std::fabs(hi[d])});
  return static_cast<float>(1e-4 + 1e-5 * largest);
}

}  // namespace

bool ContinuousCollision::later(const Event& a, const Event& b) {
  // A total order, so that the event taken next never depends on heap history.
  if (a.t != b.t) return a.t > b.t;
  if (a.motion != b.motion) return a.motion > b.motion;
  if (a.target != b.target) return a.target > b.target;
  return a.other > b.other;
}

std::uint32_t ContinuousCollision::version_of(std::uint32_t slot) const {
  const std::int32_t m = motion_of_[slot];
  return m >= 0 ? motions_[static_cast<std::size_t>(m)].version : 0u;
}

void ContinuousCollision::centre_at(const SphereSoA& s, std::uint32_t slot, double t, double out[3],
                                    double v[3]) const {
  const std::int32_t m = motion_of_[slot];
  if (m < 0) {  // not swept: still on the straight path the solver left it on
    const double p[3] = {s.px[slot], s.py[slot], s.pz[slot]}, u[3] = {s.vx[slot], s.vy[slot], s.vz[slot]};
    for (int d = 0; d < 3; ++d) out[d] = p[d] + u[d] * t, v[d] = u[d];
    return;
  }
  const Motion& mo = motions_[static_cast<std::size_t>(m)];
  for (int d = 0; d < 3; ++d) {
    v[d] = mo.stopped ? 0.0 : mo.v[d];
    out[d] = mo.x[d] + v[d] * (t - mo.t0);
  }
}

double ContinuousCollision::path_start(std::uint32_t slot) const {
  const std::int32_t m = motion_of_[slot];
  return m >= 0 ? motions_[static_cast<std::size_t>(m)].t0 : 0.0;
}

std::uint32_t ContinuousCollision::activate(const SphereSoA& s, std::uint32_t slot) {
  if (motion_of_[slot] >= 0) return static_cast<std::uint32_t>(motion_of_[slot]);
  Motion m{};
  m.x[0] = s.px[slot], m.x[1] = s.py[slot], m.x[2] = s.pz[slot];
  m.v[0] = s.vx[slot], m.v[1] = s.vy[slot], m.v[2] = s.vz[slot];
  m.slot = slot;
  m.backer = kNoBacker;
  motion_of_[slot] = static_cast<std::int32_t>(motions_.size());
  motions_.push_back(m);
  return static_cast<std::uint32_t>(motions_.size() - 1);
}

void ContinuousCollision::sync_path(SphereSoA& s, const Motion& mo) {
  const std::uint32_t i = mo.slot;
  const double v[3] = {mo.stopped ? 0.0 : mo.v[0], mo.stopped ? 0.0 : mo.v[1], mo.stopped ? 0.0 : mo.v[2]};
  s.px[i] = static_cast<float>(mo.x[0] - v[0] * mo.t0);
  s.py[i] = static_cast<float>(mo.x[1] - v[1] * mo.t0);
  s.pz[i] = static_cast<float>(mo.x[2] - v[2] * mo.t0);
  s.vx[i] = static_cast<float>(v[0]);
  s.vy[i] = static_cast<float>(v[1]);
  s.vz[i] = static_cast<float>(v[2]);
}

void ContinuousCollision::advance(std::uint32_t m, double t) {
  Motion& mo = motions_[m];
  if (!mo.stopped)
    for (int d = 0; d < 3; ++d) mo.x[d] += mo.v[d] * (t - mo.t0);
  mo.t0 = t;
}

void ContinuousCollision::record_impact(const SphereSoA& s, const Contact& c, double t, const double a_centre[3],
                                        const double n[3], float impulse) {
  const double r = s.radius[c.a];
  impacts_.push_back({.a = c.a,
                      .b = c.b,
                      .feature = c.feature,
                      .time = static_cast<float>(t),
                      .px = static_cast<float>(a_centre[0] + n[0] * r),
                      .py = static_cast<float>(a_centre[1] + n[1] * r),
                      .pz = static_cast<float>(a_centre[2] + n[2] * r),
                      .nx = c.nx,
                      .ny = c.ny,
                      .nz = c.nz,
                      .impulse = impulse});
}

void ContinuousCollision::remember(std::uint32_t m, std::uint32_t hit, const double into[3]) {
  Motion& mo = motions_[m];
  mo.backer = hit;
  for (int d = 0; d < 3; ++d) mo.back_x[d] = mo.x[d], mo.back_n[d] = into[d];
}

bool ContinuousCollision::held_by_backer(const SphereSoA& s, std::uint32_t m, std::uint32_t striker,
                                         const double push[3], double t, float ratio, Hold& hold) const {
  const Motion& mo = motions_[m];
  double* into = hold.into;
  double* backer_v = hold.backer_v;
  if (mo.backer == kNoBacker || mo.backer == striker || !std::isfinite(ratio)) return false;
  const double r = s.radius[mo.slot];
  double gap = 0.0;
  if (mo.backer == kStaticBody) {
    for (int d = 0; d < 3; ++d) into[d] = mo.back_n[d], backer_v[d] = 0.0, gap += (mo.back_x[d] - mo.x[d]) * into[d];
  } else {
    const float backer_inv_mass = s.inv_mass[mo.backer];
    if (backer_inv_mass > 0.0f && !(s.inv_mass[mo.slot] > ratio * backer_inv_mass)) return false;
    double c[3], len2 = 0.0;
    centre_at(s, mo.backer, t, c, backer_v);
    for (int d = 0; d < 3; ++d) into[d] = c[d] - mo.x[d], len2 += into[d] * into[d];
    const double len = std::sqrt(len2);
    if (!(len > 0.0)) return false;
    for (int d = 0; d < 3; ++d) into[d] /= len;
    gap = len - r - s.radius[mo.backer];
  }
  const double press = push[0] * into[0] + push[1] * into[1] + push[2] * into[2];
  return press > kHeldPressCosine && gap <= kHeldGapFraction * r;
}

void ContinuousCollision::strike_held(SphereSoA& s, const SweepScene& scene, const Contact& c, double t,
                                      std::uint32_t held, std::uint32_t striker, const Hold& hold,
                                      float restitution_threshold, int max_events) {
  ++stats_.held;
  ++stats_.events;
  const std::uint32_t backer = motions_[held].backer;
  const double* g = hold.into;
  // The impulse on the held sphere is along d: the normal (a to b) when it is b.
  const double sign = motions_[held].slot == c.b ? 1.0 : -1.0;
  const double d[3] = {sign * c.nx, sign * c.ny, sign * c.nz};
  const double imp = s.inv_mass[motions_[held].slot], ims = s.inv_mass[motions_[striker].slot];
  const double imh = backer == kStaticBody ? 0.0 : s.inv_mass[backer];
  double* vp = motions_[held].v;
  double* vs = motions_[striker].v;
  // Bound along g: it moves with the backer there, and across g by its own mass.
  const double vpg = vp[0] * g[0] + vp[1] * g[1] + vp[2] * g[2];
  const double vhg = hold.backer_v[0] * g[0] + hold.backer_v[1] * g[1] + hold.backer_v[2] * g[2];
  for (int k = 0; k < 3; ++k) vp[k] += (vhg - vpg) * g[k];
  const double dg = d[0] * g[0] + d[1] * g[1] + d[2] * g[2];
  const double closing = (vs[0] - vp[0]) * d[0] + (vs[1] - vp[1]) * d[1] + (vs[2] - vp[2]) * d[2];
  const double denominator = ims + imp * (1.0 - dg * dg) + imh * dg * dg;
  double j = 0.0;
  if (closing > 0.0 && denominator > 0.0) {
    const double bounce = closing > restitution_threshold ? c.restitution : 0.0;
    j = (1.0 + bounce) * closing / denominator;
    for (int k = 0; k < 3; ++k) {
      vs[k] -= j * ims * d[k];
      vp[k] += j * (imp * (d[k] - dg * g[k]) + imh * dg * g[k]);
    }
    const double n[3] = {sign * d[0], sign * d[1], sign * d[2]};
    record_impact(s, c, t, motions_[c.a == motions_[held].slot ? held : striker].x, n, static_cast<float>(j));
  }
  // The striker remembers the held sphere; the held one keeps its backer.
  remember(striker, motions_[held].slot, d);
  float v[3];
  for (int k = 0; k < 3; ++k) v[k] = static_cast<float>(vs[k]);
  take_new_path(s, striker, v, max_events);
  for (int k = 0; k < 3; ++k) v[k] = static_cast<float>(vp[k]);
  take_new_path(s, held, v, max_events);
  // A sphere backer takes the impulse's part along g.
  const bool moves_backer = backer != kStaticBody && j > 0.0;
  const std::uint32_t mh = moves_backer ? activate(s, backer) : striker;
  if (moves_backer) {
    advance(mh, t);
    for (int k = 0; k < 3; ++k) v[k] = static_cast<float>(motions_[mh].v[k] + j * imh * dg * g[k]);
    take_new_path(s, mh, v, max_events);
  }
  push(earliest_event(s, scene, striker));
  push(earliest_event(s, scene, held));
  if (moves_backer) push(earliest_event(s, scene, mh));
}

void ContinuousCollision::push(const Event& e) {
  if (e.t < 0.0) return;
  heap_.push_back(e);
  std::push_heap(heap_.begin(), heap_.end(), later);
}

void ContinuousCollision::begin(const SphereSoA& s, std::span<const std::uint32_t> fast, float dt, float fast_fraction,
                                SweepCandidates candidates, bool slots_coherent) {
  for (const Motion& m : motions_) moved_[m.slot] = 0;  // last step's marks
  motions_.clear();
  heap_.clear();
  impacts_.clear();
  stats_ = {};
  dt_ = dt;
  fast_fraction_ = fast_fraction;
  fast_count_ = fast.size();
  any_ = !fast.empty();
  if (!any_) return;
  if (motion_of_.size() < s.size()) motion_of_.resize(s.size(), -1);
  if (moved_.size() < s.size()) moved_.resize(s.size(), 0);
  for (std::uint32_t slot : fast) motions_[activate(s, slot)].meets_spheres = true;
  resize_geometric(first_events_, fast.size());
  stats_.fast = fast.size();
  use_bvh_ =
      candidates == SweepCandidates::Automatic ? fast.size() >= kSweepBvhMinFast : candidates == SweepCandidates::Bvh;
  if (!use_bvh_) return;
  resize_geometric(path_boxes_, s.size());
  float max_radius = 0.0f;
  for (std::size_t j = 0; j < s.size(); ++j) {
    max_radius = std::max(max_radius, s.radius[j]);
    const double lo[3] = {std::min<double>(s.px[j], double(s.px[j]) + double(s.vx[j]) * dt),
                          std::min<double>(s.py[j], double(s.py[j]) + double(s.vy[j]) * dt),
                          std::min<double>(s.pz[j], double(s.pz[j]) + double(s.vz[j]) * dt)};
    const double hi[3] = {std::max<double>(s.px[j], double(s.px[j]) + double(s.vx[j]) * dt),
                          std::max<double>(s.py[j], double(s.py[j]) + double(s.vy[j]) * dt),
                          std::max<double>(s.pz[j], double(s.pz[j]) + double(s.vz[j]) * dt)};
    const float pad = box_padding(lo, hi) + s.radius[j];
    for (int d = 0; d < 3; ++d)
      path_boxes_[j].min[d] = static_cast<float>(lo[d]) - pad, path_boxes_[j].max[d] = static_cast<float>(hi[d]) + pad;
  }
  // Rebuilt every step: over Morton-ordered slots the input-order tree costs O(n) and queries
  // about as fast as the median split's (terrain-rain 64k: docs/benchmarks.md).
  path_bvh_.build(path_boxes_, {.split = slots_coherent ? BvhSplit::InputOrder : BvhSplit::Median});
  // Cells of two diameters: a changed path (a short one, after an impact) covers a few.
  changed_paths_.reset(std::max(4.0f * max_radius, 1e-3f), motions_.size());
}

ContinuousCollision::Event ContinuousCollision::earliest_event(const SphereSoA& s, const SweepScene& scene,
                                                               std::uint32_t m) const {
  const Motion& mo = motions_[m];
  Event best{kNoEvent, m, mo.version, Target::Terrain, 0, 0, {0, 0, 0}};
  const double t_left = dt_ - mo.t0;
  if (mo.stopped || !(t_left > 0.0)) return best;
  const std::uint32_t slot = mo.slot;
  const double r = s.radius[slot];
  const double* c = mo.x;
  const double* v = mo.v;
  // Ties go to the smaller (target, other), so the result does not depend on the order in
  // which candidates are found (scan or BVH).
  auto offer = [&](double t, Target target, std::uint32_t other, std::uint32_t other_version, const double* n) {
    if (best.t >= 0.0 &&
        (t > best.t || (t == best.t && (target > best.target || (target == best.target && other >= best.other)))))
      return;
    best.t = t, best.target = target, best.other = other, best.other_version = other_version;
    for (int d = 0; d < 3; ++d) best.n[d] = n ? n[d] : 0.0;
  };
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::min(c[d], c[d] + v[d] * t_left) - r;
    hi[d] = std::max(c[d], c[d] + v[d] * t_left) + r;
  }
  const float pad = box_padding(lo, hi);
  const bool meets_the_ground = !scene.modes.filtering || meets_ground(s, slot, scene.modes.ground);

  if (scene.terrain && meets_the_ground) {
    // The path walks the BVH as a ray whose node boxes are grown by the radius, pruned by the
    // earliest hit so far (float, conservative); the hits themselves are timed in double.
    const TerrainTriangles& tri = scene.terrain->triangles();
    const float origin[3] = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
    const float dir[3] = {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
    const float reach = static_cast<float>(r) + pad;
    const float t_walk = static_cast<float>(t_left) * (1.0f + 1e-6f);
    (void)query_swept_sphere(scene.terrain->bvh(), origin, dir, t_walk, reach, [&](std::uint32_t k) {
      const double a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]}, b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
      const double cc[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]}, n[3] = {tri.nx[k], tri.ny[k], tri.nz[k]};
      SweptHit hit;
      if (!swept_sphere_triangle(c, v, r, a, b, cc, n, tri.internal_edges[k], t_left, hit)) return -1.0f;
      offer(mo.t0 + hit.t, Target::Terrain, k, 0, hit.n);
      return static_cast<float>(hit.t);
    });
  }
  for (std::size_t m = 0; scene.meshes && meets_the_ground && m < scene.meshes->size(); ++m) {
    // As the terrain, except that a shell's triangle is met on the face the path starts in
    // front of: its corners reversed and its normal turned for a centre behind it.
    const MeshCollider& mesh = (*scene.meshes)[m];
    const TerrainTriangles& tri = mesh.triangles;
    const float origin[3] = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
    const float dir[3] = {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
    const float reach = static_cast<float>(r) + pad;
    const float t_walk = static_cast<float>(t_left) * (1.0f + 1e-6f);
    (void)query_swept_sphere(mesh.bvh, origin, dir, t_walk, reach, [&](std::uint32_t k) {
      double a[3] = {tri.v0x[k], tri.v0y[k], tri.v0z[k]}, b[3] = {tri.v1x[k], tri.v1y[k], tri.v1z[k]};
      double cc[3] = {tri.v2x[k], tri.v2y[k], tri.v2z[k]}, n[3] = {tri.nx[k], tri.ny[k], tri.nz[k]};
      std::uint8_t internal = tri.internal_edges[k];
      if (mesh.two_sided && n[0] * c[0] + n[1] * c[1] + n[2] * c[2] < double{tri.d[k]}) {
        for (int d = 0; d < 3; ++d) std::swap(b[d], cc[d]), n[d] = -n[d];
        // Reversed, edge 0 (a-b) is the old edge 2 (c-a), edge 1 (b-c) the old edge 1, edge 2 the old edge 0.
        internal =
            static_cast<std::uint8_t>(((internal & kEdge2Internal) ? kEdge0Internal : 0) | (internal & kEdge1Internal) |
                                      ((internal & kEdge0Internal) ? kEdge2Internal : 0));
      }
      SweptHit hit;
      if (!swept_sphere_triangle(c, v, r, a, b, cc, n, internal, t_left, hit)) return -1.0f;
      offer(mo.t0 + hit.t, Target::Mesh, mesh.first_feature + k, 0, hit.n);
      return static_cast<float>(hit.t);
    });
  }
  for (std::uint32_t k = 0; meets_the_ground && k < scene.planes.size(); ++k) {
    const Plane& p = scene.planes[k];
    const double n[3] = {p.nx, p.ny, p.nz};
    SweptHit hit;
    if (swept_sphere_plane(c, v, r, n, p.offset, t_left, hit)) offer(mo.t0 + hit.t, Target::Plane, k, 0, hit.n);
  }
  if (!scene.sphere_collisions || !mo.meets_spheres) return best;
  // The pair is timed from when the later of the two current paths began: a search that starts
  // at this sphere's last impact (again, after its event went stale) must not follow j back
  // along a path j took up only later. Such an impact, with where j never was, came before
  // events already taken and moved j back in time; and the grid, which lists a changed path
  // from its start on, could miss what the scan (every path over mo.t0..dt) found.
  auto try_sphere = [&](std::uint32_t j) {
    if (scene.modes.filtering && !pair_collides(s, slot, j)) return;
    const double start = std::max(mo.t0, path_start(j));
    double ci[3], cj[3], vj[3];
    centre_at(s, j, start, cj, vj);
    for (int d = 0; d < 3; ++d) ci[d] = start == mo.t0 ? c[d] : c[d] + v[d] * (start - mo.t0);
    const double dp[3] = {cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]},
                 dv[3] = {vj[0] - v[0], vj[1] - v[1], vj[2] - v[2]};
    const double t = sphere_sphere_time_of_impact(dp, dv, r + s.radius[j], dt_ - start);
    if (t >= 0.0) offer(start + t, Target::Sphere, j, version_of(j), nullptr);
  };
  PathBox box;
  for (int d = 0; d < 3; ++d)
    box.min[d] = static_cast<float>(lo[d]) - pad, box.max[d] = static_cast<float>(hi[d]) + pad;
  if (use_bvh_) {
    // The BVH holds every path as it was at the start of the step: right for spheres whose
    // path has not changed, and those that changed are few (each had an impact) and tried all.
    Aabb query;
    for (int d = 0; d < 3; ++d) query.min[d] = box.min[d], query.max[d] = box.max[d];
    query_aabb(path_bvh_, query, [&](std::uint32_t k) {
      const std::uint32_t j = path_bvh_.primitive_order[k];
      if (j != slot && version_of(j) == 0) try_sphere(j);
    });
    changed_paths_.query(
        box.min, box.max, [&](std::uint32_t m_changed) { return motions_[m_changed].version; },
        [&](std::uint32_t m_changed) {
          if (motions_[m_changed].slot != slot) try_sphere(motions_[m_changed].slot);
        });
    return best;
  }
  // Every sphere's SoA position and velocity describe its current straight path (for swept
  // ones, as set by sync_path), so one scan covers swept and unswept spheres alike.
  // The SIMD scan of the active path (kernel/dispatch/kernel_table.h); it visits the slots in order.
  auto visit = [&](std::uint32_t j) {
    if (j != slot) try_sphere(j);
  };
  simd_kernels().scan_path_boxes(s, box, static_cast<float>(mo.t0), static_cast<float>(dt_), slot_sink(visit));
  return best;
}

void ContinuousCollision::find_first_events(const SphereSoA& s, const SweepScene& scene, std::size_t first,
                                            std::size_t last) {
  for (std::size_t k = first; k < last; ++k) first_events_[k] = earliest_event(s, scene, static_cast<std::uint32_t>(k));
}

void ContinuousCollision::resolve(SphereSoA& s, const SweepScene& scene, float restitution_threshold, int max_events) {
  if (!any_) return;
  for (std::size_t k = 0; k < fast_count_; ++k) push(first_events_[k]);
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const Event e = heap_.back();
    heap_.pop_back();
    if (e.version != motions_[e.motion].version) continue;  // superseded: a newer search was pushed
    if (e.target == Target::Sphere && e.other_version != version_of(e.other)) {
      push(earliest_event(s, scene, e.motion));  // the other sphere changed path: search again
      continue;
    }
    const std::uint32_t ma = e.motion;
    const std::uint32_t mb = e.target == Target::Sphere ? activate(s, e.other) : ma;
    advance(ma, e.t);
    if (mb != ma) advance(mb, e.t);
    const std::uint32_t a = motions_[ma].slot;
    Contact contact;
    contact.a = a;
    double n[3] = {e.n[0], e.n[1], e.n[2]};
    if (e.target == Target::Sphere) {
      contact.b = e.other;
      double len2 = 0.0;
      for (int d = 0; d < 3; ++d) n[d] = motions_[mb].x[d] - motions_[ma].x[d], len2 += n[d] * n[d];
      const double len = std::sqrt(len2);
      if (!centres_coincide(static_cast<float>(len), s.radius[a], s.radius[e.other])) {
        for (double& x : n) x /= len;
      } else {
        float pair[3];  // no direction from the centres: the pair's own (make_sphere_contact's)
        coincident_normal(s.id_at(a).index, s.id_at(e.other).index, pair);
        for (int d = 0; d < 3; ++d) n[d] = pair[d];
      }
      contact.restitution = combine_restitution(s.restitution[a], s.restitution[e.other]);
      contact.friction = combine_friction(s.friction[a], s.friction[e.other]);
    } else if (e.target == Target::Terrain) {
      contact.restitution = combine_restitution(s.restitution[a], scene.terrain_restitution);
      contact.friction = combine_friction(s.friction[a], scene.terrain_friction);
      contact.feature = e.other;
    } else if (e.target == Target::Mesh) {
      const MeshCollider& mesh = (*scene.meshes)[scene.meshes->mesh_of(e.other)];
      contact.restitution = combine_restitution(s.restitution[a], mesh.restitution);
      contact.friction = combine_friction(s.friction[a], mesh.friction);
      contact.feature = kMeshFeature | e.other;
    } else {
      const Plane& p = scene.planes[e.other];
      contact.restitution = combine_restitution(s.restitution[a], p.restitution);
      contact.friction = combine_friction(s.friction[a], p.friction);
      contact.feature = kPlaneFeature | e.other;
    }
    contact.nx = static_cast<float>(n[0]), contact.ny = static_cast<float>(n[1]), contact.nz = static_cast<float>(n[2]);
    // A light sphere pinched between a heavy striker and what it hit before (hold_mass_ratio).
    if (e.target == Target::Sphere) {
      const float ima = s.inv_mass[a], imb = s.inv_mass[e.other];
      const double onto_a[3] = {-n[0], -n[1], -n[2]};
      Hold hold;
      std::uint32_t held = kNoBacker;
      if (ima > scene.hold_mass_ratio * imb && held_by_backer(s, ma, e.other, onto_a, e.t, scene.hold_mass_ratio, hold))
        held = ma;
      else if (imb > scene.hold_mass_ratio * ima && held_by_backer(s, mb, a, n, e.t, scene.hold_mass_ratio, hold))
        held = mb;
      if (held != kNoBacker) {
        strike_held(s, scene, contact, e.t, held, held == ma ? mb : ma, hold, restitution_threshold, max_events);
        continue;
      }
    }
    remember(ma, e.target == Target::Sphere ? e.other : kStaticBody, n);
    if (mb != ma) {
      const double back[3] = {-n[0], -n[1], -n[2]};
      remember(mb, a, back);
    }
    // Without rotation the impulse acts on linear velocities alone and w is not touched.
    const bool spin = scene.modes.rotation;
    ContactBodies bodies = spin ? gather_bodies<kWithFriction>(s, contact) : gather_bodies<kLinearFriction>(s, contact);
    for (int d = 0; d < 3; ++d) bodies.va[d] = static_cast<float>(motions_[ma].v[d]);
    if (mb != ma)
      for (int d = 0; d < 3; ++d) bodies.vb[d] = static_cast<float>(motions_[mb].v[d]);
    const float j = spin ? solve_impact<kWithFriction>(contact, bodies, restitution_threshold)
                         : solve_impact<kLinearFriction>(contact, bodies, restitution_threshold);
    // Angular velocities (linear ones: sync_path below).
    if (spin) scatter_bodies<kWithFriction>(s, contact, bodies);
    ++stats_.events;
    if (j > 0.0f) record_impact(s, contact, e.t, motions_[ma].x, n, j);
    // Both spheres take their new paths before either searches. scatter_bodies (above) has
    // written both new velocities into the SoA already: had a searched before b's path was
    // synced, the scan would have seen b's old position with its new velocity, while
    // centre_at, the BVH and the grid still followed b's old path, and the two candidate
    // sources disagreed. Now a's search meets b where b really goes.
    take_new_path(s, ma, bodies.va, max_events);
    if (mb != ma) take_new_path(s, mb, bodies.vb, max_events);
    push(earliest_event(s, scene, ma));
    if (mb != ma) push(earliest_event(s, scene, mb));
  }
}

void ContinuousCollision::take_new_path(SphereSoA& s, std::uint32_t m, const float vnew[3], int max_events) {
  Motion& mo = motions_[m];
  for (int d = 0; d < 3; ++d) mo.v[d] = vnew[d];
  if (!mo.meets_spheres) {
    const float speed2 = vnew[0] * vnew[0] + vnew[1] * vnew[1] + vnew[2] * vnew[2];
    mo.meets_spheres = is_fast(speed2, static_cast<float>(dt_), s.radius[mo.slot], fast_fraction_);
  }
  ++mo.version;
  if (++mo.events >= max_events && !mo.stopped) {
    mo.stopped = true;
    ++stats_.capped;
  }
  sync_path(s, mo);
  if (use_bvh_) list_changed_path(s, m);
}

void ContinuousCollision::list_changed_path(const SphereSoA& s, std::uint32_t m) {
  // The box of the path from now (t0) to the end of the step, as centre_at follows it, padded
  // by the radius as the searches pad theirs: every search from now on starts at t0 or later.
  const Motion& mo = motions_[m];
  const double rest = dt_ - mo.t0;
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double end = mo.x[d] + (mo.stopped ? 0.0 : mo.v[d]) * rest;
    lo[d] = std::min(mo.x[d], end), hi[d] = std::max(mo.x[d], end);
  }
  const float pad = box_padding(lo, hi) + s.radius[mo.slot];
  float box_lo[3], box_hi[3];
  for (int d = 0; d < 3; ++d) box_lo[d] = static_cast<float>(lo[d]) - pad, box_hi[d] = static_cast<float>(hi[d]) + pad;
  changed_paths_.insert(m, mo.version, box_lo, box_hi);
}

void ContinuousCollision::finish(SphereSoA& s) {
  if (!any_) return;
  for (Motion& mo : motions_) {
    const double rest = dt_ - mo.t0;
    const std::uint32_t i = mo.slot;
    const double x[3] = {mo.x[0], mo.x[1], mo.x[2]};
    const double step = mo.stopped ? 0.0 : rest;
    s.px[i] = static_cast<float>(x[0] + mo.v[0] * step);
    s.py[i] = static_cast<float>(x[1] + mo.v[1] * step);
    s.pz[i] = static_cast<float>(x[2] + mo.v[2] * step);
    s.vx[i] = static_cast<float>(mo.v[0]);
    s.vy[i] = static_cast<float>(mo.v[1]);
    s.vz[i] = static_cast<float>(mo.v[2]);
    moved_[i] = 1;
    motion_of_[i] = -1;
  }
  stats_.swept = motions_.size();
  stats_.meets_spheres = static_cast<std::size_t>(
      std::count_if(motions_.begin(), motions_.end(), [](const Motion& mo) { return mo.meets_spheres; }));
}

}  // namespace hail
