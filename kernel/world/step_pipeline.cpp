// World::step: the phases of one step, in order, each a parallel loop over fixed blocks.
//
//   predict      v += g dt; largest speed of the spheres that are not fast (sizes the
//                speculative contact margin); the fast ones listed for the sweep
//   detect       sphere-plane contacts and sphere-sphere pairs (SIMD brute force), at the same
//                time; per-block buffers merged in block order
//   solve        contacts coloured so that a colour has no shared sphere, per solver tile
//                (kernel/solver/contact_colouring.h) and then across tiles; each pass runs the tiles
//                in parallel, each its colours in order, then the shared colours one after
//                another, each in parallel; a SIMD batch of contacts (4, 8 or 16 by path) per
//                instruction: collision passes, then resting passes
//   sweep        fast spheres moved along their paths impact by impact (continuous collision)
//   integrate    positions of the others, with exact time-of-impact bounces on planes
//   depenetrate  push overlapping spheres apart, colour by colour (tiles in parallel)
//
// Nothing here depends on the thread count except which thread runs a block, so the state
// after a step is bitwise the same for any number of threads.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <new>

#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_sort.h>

#include "hail/phase_trace.h"
#include "hail/world.h"
#include "jobs/parallel_blocks.h"
#include "jobs/phase_timer.h"
#include "jobs/stage_crew.h"
#include "jobs/sync_count.h"
#include "kernel/broadphase/spatial_order.h"
#include "kernel/broadphase/sphere_filters.h"
#include "kernel/mesh/mesh_set.h"
#include "kernel/solver/contact_impulse.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/depenetrate.h"
#include "kernel/solver/integrate.h"
#include "kernel/solver/rolling_resistance.h"
#include "kernel/solver/soft_step.h"
#include "kernel/solver/solver_body.h"
#include "kernel/solver/step_modes.h"
#include "kernel/terrain/plane_contacts.h"
#include "kernel/terrain/terrain_parts.h"
#include "kernel/world/sleep_islands.h"
#include "kernel/world/step_heuristics.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_services.h"
#include "soa/grow.h"

namespace hail {

namespace {
constexpr std::size_t kReorderBlock = 16384;  // spheres per block of the re-sort: few parallel loops at 4k
constexpr std::size_t kSphereBlock = 256;     // spheres per block in per-sphere phases
constexpr std::size_t kPairRowBlock = 64;     // rows i per block of the brute-force pair search
constexpr std::size_t kPairRowChunk = 16;     // rows per search call once a block may pass its contact cap
constexpr std::size_t kContactChunk = 256;    // contacts per task within one colour
constexpr std::size_t kBatchChunk = 32;       // SIMD contact batches per task within one colour
// Terrain guard in steps of mixed masses: a sphere whose centre is lower than (1 - this) of its
// radius above the surface under it overlaps flat ground by more than this share of its radius
// (the depenetration slop is 1%, the stress battery's bound 5%), and is pushed out.
constexpr float kGuardSinkFraction = 0.02f;
/// Gap, as a fraction of the mean radius, within which two spheres at rest count as touching
/// and keep their contact (remember_travel): 0.5 mm at r = 0.5, far above the rounding of
/// positions placed touching (ulps), and small enough that scenes under gravity step bitwise as
/// before (terrain-rain 4k keeps its hash). At the depenetration's slop, 1%, terrain-rain's
/// hash moved (spheres near the top of a hop travel less than the floor: docs/accuracy.md).
constexpr float kRestingContactSlop = 1e-3f;
}  // namespace

/// What a step reads and writes of its World besides the scratch: World::substep hands these
/// over, so the pipeline needs no access to World's private members.
struct StepWorld {
  const WorldSettings& settings;
  SphereSoA& spheres;
  std::span<const Plane> planes;
  const Terrain* terrain;  ///< null: no terrain
  float terrain_restitution, terrain_friction;
  const MeshSet* meshes;  ///< null: no meshes
  StepStats& stats;
  PhaseTimes& times;
  PhaseTrace& trace;
  std::uint64_t steps_taken;  ///< steps before this one (the re-sort's phase)
};

struct StepPipeline {
  StepWorld w;
  StepScratch& st;           // w's scratch (kernel/world/step_scratch.h)
  WorldServices& services;   // w's events, sleeping islands and queries (kernel/world/world_services.h)
  const StepModes& modes;    // what this substep does (kernel/solver/step_modes.h), decided by World::substep
  IntegrationParams params;  // with a copy of the modes, for the integrator
  float min_radius = 0.0f, max_radius = 0.0f;  // of this step's spheres (predict)
  bool shock = false;                          // masses differ more than shock_mass_ratio: shock propagation
  bool friction_needed_ = true;                // some contact of this step has friction > 0 (merge_contacts)
  bool rolled_ = false;                        // rolling resistance ran (solve): its impulses are remembered

  /// No sphere of slots [first, last) moves (all asleep, or immovable and still): a block of
  /// sleepers, which predict, static detection and integration skip whole.
  [[nodiscard]] bool block_still(std::size_t first, std::size_t last) const {
    for (std::size_t i = first; i < last; ++i)
      if (sphere_moves(w.spheres, i)) return false;
    return true;
  }
  /// Sleepers keep a zero velocity: predict's gravity on a block that mixes them with awake
  /// spheres is taken back (their speed of g dt only widens this step's margin a little).
  void keep_sleepers_still(std::size_t first, std::size_t last) {
    SphereSoA& s = w.spheres;
    for (std::size_t i = first; i < last; ++i)
      if (sphere_sleeps(s, i)) s.vx[i] = s.vy[i] = s.vz[i] = s.wx[i] = s.wy[i] = s.wz[i] = 0.0f;
  }

  void predict(float& margin) {
    SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t blocks = block_count(n, kSphereBlock);
    assign_geometric(st.block_max_speed, blocks, 0.0f);
    if (st.block_extremes.size() < blocks) resize_geometric(st.block_extremes, blocks);
    grow_block_lists(st.fast_blocks, blocks);
    for_each_block(n, kSphereBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Predict);
      st.fast_blocks[b].clear();
      const bool still = modes.sleeping && block_still(first, last);
      if (modes.uniform_acceleration()) remember_start_velocities(first, last);
      if (!still && modes.forces) apply_forces(s, first, last, params.dt, modes.rotation);
      st.block_max_speed[b] = still ? 0.0f
                                    : predict_velocities(s, first, last, params, w.settings.fast_travel_fraction,
                                                         modes.sweeping ? &st.fast_blocks[b] : nullptr);
      if (modes.sleeping && !still) keep_sleepers_still(first, last);
      st.block_extremes[b] = block_extremes(first, last);
      if (modes.terrain_guard) remember_reach(first, last);
      if (modes.pair_margins) remember_travel(first, last);
    });
    float max_speed = 0.0f;
    for (float v : st.block_max_speed) max_speed = std::max(max_speed, v);
    st.fast.clear();
    std::size_t fast_count = 0;
    for (std::size_t b = 0; b < blocks; ++b) fast_count += st.fast_blocks[b].size();
    reserve_geometric(st.fast, fast_count);
    for (std::size_t b = 0; b < blocks; ++b)
      st.fast.insert(st.fast.end(), st.fast_blocks[b].begin(), st.fast_blocks[b].end());
    // Minima and maxima do not depend on the order they are combined in.
    SphereExtremes all = block_extremes(0, 0);
    for (const SphereExtremes& e : st.block_extremes) all.combine(e);
    max_radius = n > 0 ? all.max_radius : 0.0f;
    min_radius = n > 0 ? all.min_radius : 0.0f;
    const float min_inv_mass = all.min_inv_mass, max_inv_mass = all.max_inv_mass;
    // Heaviest over lightest = largest inverse mass over smallest.
    shock = max_inv_mass > w.settings.shock_mass_ratio * min_inv_mass;
    margin = std::min(2.0f * max_speed * params.dt, w.settings.speculative_radii * max_radius);
  }

  /// The uniform-acceleration integrator's start velocities (IntegrationParams::start_vx..vz):
  /// the velocities of spheres [first, last) before this (sub)step's forces and gravity.
  void remember_start_velocities(std::size_t first, std::size_t last) {
    const SphereSoA& s = w.spheres;
    std::copy(s.vx.data() + first, s.vx.data() + last, st.start_vx.data() + first);
    std::copy(s.vy.data() + first, s.vy.data() + last, st.start_vy.data() + first);
    std::copy(s.vz.data() + first, s.vz.data() + last, st.start_vz.data() + first);
  }

  /// Radii and inverse masses (of movable spheres) of spheres [first, last), branch-free.
  SphereExtremes block_extremes(std::size_t first, std::size_t last) const {
    const SphereSoA& s = w.spheres;
    SphereExtremes e;
    for (std::size_t i = first; i < last; ++i) {
      const float r = s.radius[i], im = s.inv_mass[i];
      e.max_radius = r > e.max_radius ? r : e.max_radius;
      e.min_radius = r < e.min_radius ? r : e.min_radius;
      e.min_inv_mass = im > 0.0f && im < e.min_inv_mass ? im : e.min_inv_mass;
      e.max_inv_mass = im > e.max_inv_mass ? im : e.max_inv_mass;
    }
    return e;
  }

  /// Terrain guard, part 1: where each sphere starts and how far its terrain contacts reach
  /// (the reach of Terrain::find_contacts; swept spheres need no guard), plus the overlap the
  /// depenetration tolerates anyway (slop): a sphere that moved no further than that cannot
  /// have entered ground outside its contacts by more than the slop. Without that allowance
  /// rounding flags every falling sphere (its move is exactly its reach), and the guard spends
  /// its queries on spheres that move nothing (callgrind: docs/benchmarks.md, "Figures behind
  /// the code's choices").
  void remember_reach(std::size_t first, std::size_t last) {
    const SphereSoA& s = w.spheres;
    const float slop = w.settings.depenetration.slop_fraction;
    const float swept_reach = modes.sweeping ? std::numeric_limits<float>::infinity() : 0.0f;
    // Selects, no branches, and unaliased pointers, so that it vectorises: it runs for every sphere.
    float* __restrict x0 = st.start_x.data();
    float* __restrict y0 = st.start_y.data();
    float* __restrict z0 = st.start_z.data();
    float* __restrict reach2_out = st.reach2.data();
    const float* __restrict px = s.px.data();
    const float* __restrict py = s.py.data();
    const float* __restrict pz = s.pz.data();
    const float* __restrict vx = s.vx.data();
    const float* __restrict vy = s.vy.data();
    const float* __restrict vz = s.vz.data();
    const float* __restrict radius = s.radius.data();
    for (std::size_t i = first; i < last; ++i) {
      x0[i] = px[i], y0[i] = py[i], z0[i] = pz[i];
      const float v2 = vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
      const bool fast = is_fast(v2, params.dt, radius[i], w.settings.fast_travel_fraction);
      const float reach =
          (fast ? w.settings.fast_travel_fraction * radius[i] : std::sqrt(v2) * params.dt) + slop * radius[i];
      const float reach2 = reach * reach;
      reach2_out[i] = fast ? std::max(reach2, swept_reach) : reach2;
    }
  }

  /// Plane guard: a movable sphere awake whose centre ends the step behind a plane (inside its
  /// solid) is set back onto it, touching; its velocity is left to the next step's contact.
  /// Integration bounces off planes at the exact time of impact, so only depenetration puts a
  /// centre there: in a crowd its passes do not converge, and 500 spheres created at one point
  /// on a plane had 49 centres behind it after the first step, down to 1.02 m, and needed five
  /// more steps to come out (docs/robustness.md). So only the spheres depenetration moved this
  /// step (st.moved_at stamped) are looked at. Each sphere on its own: blocks in parallel.
  void guard_planes() {
    SphereSoA& s = w.spheres;
    const std::uint32_t* const moved = st.moved_at.data();
    std::atomic<std::size_t> pushed{0};  // a sum: the order of adds cannot change it
    for_each_block(s.size(), kSphereBlock, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Depenetrate);
      std::size_t count = 0;
      for (std::size_t i = first; i < last; ++i) {
        if (moved[i] == 0 || !(s.inv_mass[i] > 0.0f) || (modes.sleeping && sphere_sleeps(s, i))) continue;
        if (modes.filtering && !meets_ground(s, i, modes.ground)) continue;  // it passes through the ground
        bool moved = false;
        for (const Plane& p : w.planes) {
          const float centre = p.nx * s.px[i] + p.ny * s.py[i] + p.nz * s.pz[i] - p.offset;
          if (!(centre < 0.0f)) continue;
          const float lift = s.radius[i] - centre;
          s.px[i] += p.nx * lift, s.py[i] += p.ny * lift, s.pz[i] += p.nz * lift;
          moved = true;
        }
        count += moved ? 1 : 0;
      }
      if (count > 0) pushed += count;
    });
    w.stats.pushed_out += pushed.load();
  }

  /// The unit vector against gravity, zero without gravity: it orders two spheres of one level
  /// in the shock passes (ShockPropagation::holder).
  [[nodiscard]] Vec3 up() const {
    const float g = w.settings.gravity.norm();
    return g > 0.0f ? Vec3(-w.settings.gravity / g) : Vec3(Vec3::Zero());
  }

  /// Shock propagation for positions, in steps of very different masses, after the guards: one
  /// pass of depenetration over the contacts from the ground up in which the holding body
  /// (ShockPropagation::holder) stays put and the other takes the whole correction. A light
  /// sphere on the ground under a heavy one otherwise took their pair's correction into the
  /// ground, was pushed back out by the guard, and ended inside the heavy sphere (two of its
  /// radii deep: hail-bench stress, small-under-big-rain). Serial, as the velocity pass: its
  /// order is its point. A sleeper holds still.
  void shock_push_out() {
    ScopedTraceRecord record(w.trace, Phase::Depenetrate);
    SphereSoA& s = w.spheres;
    DepenetrationParams whole = w.settings.depenetration;
    whole.fraction = 1.0f;  // one pass: settle each contact as the velocity pass does
    bool deep = false;      // unused: this pass is one pass
    for (const std::uint32_t index : st.shock.order()) {
      const Contact& c = st.contacts[index];
      const bool dynamic_b = c.b != kStaticBody;
      float ima = s.inv_mass[c.a], imb = dynamic_b ? s.inv_mass[c.b] : 0.0f;
      const ShockPropagation::Holder holder = st.shock.holder(c);
      if (holder == ShockPropagation::Holder::A || (modes.sleeping && sphere_sleeps(s, c.a))) ima = 0.0f;
      if (holder == ShockPropagation::Holder::B || (dynamic_b && modes.sleeping && sphere_sleeps(s, c.b))) imb = 0.0f;
      push_apart_weighted(s, c, whole, ima, imb, 0.0f, deep);
    }
  }

  /// Where masses differ, the pairs that met in the sweep are parted once more, last: the sweep
  /// found them (they had no contact), so depenetration and the shock pass did not see them,
  /// and the guard may have lifted a pebble the sweep left on the ground back into the heavy
  /// sphere above it (0.24 of its radius: small-under-big-rain). As in shock_push_out, the
  /// lower of two spheres stacked within 78 degrees of up holds and the upper takes the whole
  /// correction; side by side, they part by their masses. Serial, in the sweep's impact order.
  void part_swept_pairs() {
    ScopedTraceRecord record(w.trace, Phase::Depenetrate);
    SphereSoA& s = w.spheres;
    DepenetrationParams whole = w.settings.depenetration;
    whole.fraction = 1.0f;
    bool deep = false;  // unused: one pass
    const Vec3 up_axis = up();
    for (const Impact& m : st.ccd.impacts()) {
      if (m.b == kStaticBody) continue;
      Contact c;
      c.a = m.a, c.b = m.b;
      const float dx = s.px[c.b] - s.px[c.a], dy = s.py[c.b] - s.py[c.a], dz = s.pz[c.b] - s.pz[c.a];
      const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (!(d > 0.0f)) continue;  // coincident: depenetration's pair normal is for contacts
      c.nx = dx / d, c.ny = dy / d, c.nz = dz / d;
      float ima = s.inv_mass[c.a], imb = s.inv_mass[c.b];
      if (modes.sleeping && sphere_sleeps(s, c.a)) ima = 0.0f;
      if (modes.sleeping && sphere_sleeps(s, c.b)) imb = 0.0f;
      const ShockPropagation::Holder holder = ShockPropagation::holder_by_height(c, up_axis);
      if (holder == ShockPropagation::Holder::A) ima = 0.0f;
      if (holder == ShockPropagation::Holder::B) imb = 0.0f;
      push_apart_weighted(s, c, whole, ima, imb, 0.0f, deep);
    }
  }

  /// Terrain guard, part 2: a sphere that ended the step further from where it started than
  /// its terrain contacts reached may be inside ground it had no contact with; it is moved out
  /// (Terrain::push_out_spheres, and MeshSet::push_out for meshes). Each sphere on its own, so
  /// blocks run in parallel.
  void guard_terrain() {
    SphereSoA& s = w.spheres;
    std::atomic<std::size_t> pushed{0};  // a sum: the order of adds cannot change it
    for_each_block(s.size(), kSphereBlock, [&](std::size_t block, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Depenetrate);
      // Flags first, branch-free so that it vectorises; then the few flagged spheres, a packet
      // at a time (Terrain::push_out_spheres).
      std::uint8_t beyond[kSphereBlock];
      for (std::size_t i = first; i < last; ++i) {
        const float dx = s.px[i] - st.start_x[i], dy = s.py[i] - st.start_y[i], dz = s.pz[i] - st.start_z[i];
        beyond[i - first] = static_cast<std::uint8_t>(dx * dx + dy * dy + dz * dz > st.reach2[i]) &
                            static_cast<std::uint8_t>(s.inv_mass[i] > 0.0f);  // & on purpose: no branch
      }
      if (modes.filtering)  // a sphere that passes through the ground is not pushed out of it
        for (std::size_t i = first; i < last; ++i)
          if (!meets_ground(s, i, modes.ground)) beyond[i - first] = 0;
      // Where masses differ (shock propagation runs), a light sphere between a heavy one and
      // the ground takes nearly all of their pair's depenetration, and is pressed into the
      // ground a little more each step; one struck while it had no ground contact is driven
      // further than its own speed reached. So in such steps a sphere is pushed out too when
      // one of its ground contacts (this block's, from detection) now overlaps by more than
      // kGuardSinkFraction of its radius, or when its centre ended lower than that short of
      // resting on the surface under it. Only then: with equal masses no sphere is driven
      // through its ground contact, and scenes that never mix masses pay nothing (issue 28).
      if (shock) {
        for (const Contact& c : st.contact_blocks[block])
          if (c.b == kStaticBody && current_gap(s, c) < -kGuardSinkFraction * s.radius[c.a])
            beyond[c.a - first] = static_cast<std::uint8_t>(s.inv_mass[c.a] > 0.0f);
        for (std::size_t i = first; w.terrain && i < last; ++i)
          if (!beyond[i - first] && s.inv_mass[i] > 0.0f &&
              s.py[i] <
                  w.terrain->heightmap().surface_height(s.px[i], s.pz[i]) + (1.0f - kGuardSinkFraction) * s.radius[i] &&
              (!modes.filtering || meets_ground(s, i, modes.ground)))
            beyond[i - first] = 1;
      }
      if (modes.sleeping)  // a sleeper did not move, and is not pushed while it sleeps
        for (std::size_t i = first; i < last; ++i)
          if (sphere_sleeps(s, i)) beyond[i - first] = 0;
      std::uint32_t flagged[kSphereBlock];
      std::size_t flagged_count = 0;
      for (std::size_t i = first; i < last; ++i)
        if (beyond[i - first]) flagged[flagged_count++] = static_cast<std::uint32_t>(i);
      // One moved right through the ground (pushed by a crowd) ends too deep for push_out's
      // query to find a triangle: it is lifted above the surface first. With continuous
      // collision off, not one that is fast by its own speed: tunnelling is what the discrete
      // step does with those (WorldSettings::continuous_collision). With it on, a fast sphere
      // is flagged only by the mixed-mass rules above: a light sphere a heavy one drove into
      // the ground after its sweep, which would otherwise fall through it.
      std::size_t count = 0;
      if (w.terrain) {
        for (std::size_t k = 0; k < flagged_count; ++k) {
          const std::uint32_t i = flagged[k];
          const float v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
          if (modes.sweeping || !is_fast(v2, params.dt, s.radius[i], w.settings.fast_travel_fraction))
            w.terrain->lift_above_surface(s.px[i], s.py[i], s.pz[i], s.radius[i]);
        }
        count += w.terrain->push_out_spheres(s, std::span<const std::uint32_t>(flagged, flagged_count));
      }
      // Meshes: out of what the sphere overlaps, a shell from the side it started on
      // (MeshSet::push_out); one sphere at a time, and few are flagged.
      for (std::size_t k = 0; w.meshes && k < flagged_count; ++k) {
        const std::uint32_t i = flagged[k];
        const float from[3] = {st.start_x[i], st.start_y[i], st.start_z[i]};
        count += w.meshes->push_out(s.px[i], s.py[i], s.pz[i], s.radius[i], from);
      }
      if (count) pushed += count;
    });
    w.stats.pushed_out += pushed.load();
  }

  void detect_static() {
    const SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t blocks = block_count(n, kSphereBlock);
    grow_block_lists(st.contact_blocks, blocks);
    for_each_block(n, kSphereBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::DetectTerrain);
      st.contact_blocks[b].clear();
      if (modes.sleeping && block_still(first, last)) return;  // sleepers' ground contacts are left out
      find_plane_contacts(s, w.planes, first, last, st.contact_blocks[b]);
      if (w.terrain)
        w.terrain->find_contacts(s, first, last, params.dt, w.terrain_restitution, w.terrain_friction,
                                 st.contact_blocks[b], w.settings.fast_travel_fraction, modes.sweeping);
      if (w.meshes)
        w.meshes->find_contacts(s, first, last, params.dt, st.contact_blocks[b], w.settings.fast_travel_fraction,
                                modes.sweeping);
      if (modes.filtering)  // static contacts all have the sphere in a
        std::erase_if(st.contact_blocks[b], [&](const Contact& c) { return !meets_ground(s, c.a, modes.ground); });
      if (modes.sleepers) std::erase_if(st.contact_blocks[b], [&](const Contact& c) { return sphere_sleeps(s, c.a); });
    });
  }

  void detect_pairs(float margin) {
    const SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t blocks = block_count(n, kPairRowBlock);
    grow_block_lists(st.pair_blocks, blocks);
    grow_block_lists(st.pair_row_scratch, blocks);
    for (std::size_t b = 0; b < blocks; ++b) st.pair_blocks[b].clear();
    w.stats.sphere_contacts_capped = false;
    if (!modes.detect_pairs) return;
    PairSearch search = w.settings.pair_search;
    if (search == PairSearch::Automatic) search = automatic_pair_search(n, min_radius, max_radius);
    w.stats.pair_search = search;
    // The grid applies the per-pair margins itself (the same predicate, so the same pairs).
    const PairMargins own_margins =
        modes.pair_margins ? PairMargins{st.travel.data(), w.settings.pair_margin_travel} : PairMargins{};
    if (search == PairSearch::Grid) st.grid.build(s, margin, own_margins);
    if (search == PairSearch::SweepAndPrune) st.sorted_axis.build(s, margin);
    if (search == PairSearch::Bvh) st.sphere_bvh.build(s, margin);
    const std::size_t per_sphere = w.settings.max_sphere_contacts_per_sphere;
    std::atomic<bool> capped{false};  // an OR: the order of stores cannot change it
    for_each_block(n, kPairRowBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::DetectPairs);
      std::vector<SpherePair>& out = st.pair_blocks[b];
      std::vector<std::uint32_t>& row = st.pair_row_scratch[b];
      auto find = [&](std::size_t from, std::size_t to) {
        const std::size_t found_before = out.size();
        switch (search) {
          case PairSearch::Grid:
            st.grid.find_pairs(s, from, to, margin, out, row);
            break;
          case PairSearch::SweepAndPrune:
            st.sorted_axis.find_pairs(s, from, to, margin, out, row);
            break;
          case PairSearch::Bvh:
            st.sphere_bvh.find_pairs(s, from, to, margin, out, row);
            break;
          default:
            find_sphere_pairs_simd(s, from, to, margin, out);
            break;
        }
        if (modes.filtering) drop_filtered_pairs(s, out, found_before);
        if (modes.sleepers)  // sleepers among themselves (and on still spheres) need no contact
          out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(found_before), out.end(),
                                   [&](const SpherePair& p) { return sleeping_contact(s, p.a, p.b); }),
                    out.end());
      };
      // The block's share of WorldSettings::max_sphere_contacts_per_sphere. A row has fewer
      // than n pairs, so a small world cannot reach it: one search. Otherwise the rows are
      // searched a chunk at a time and the search stops at the share, so that coincident
      // spheres (every pair a contact) hold at most the share plus a chunk's rows of pairs
      // here, not n^2 / 2. The pairs kept are the first in row order: the same for any
      // thread count and any search.
      const std::size_t share = per_sphere * (last - first);
      if ((last - first) * n <= share) {
        find(first, last);
      } else {
        for (std::size_t from = first; from < last; from += kPairRowChunk) {
          find(from, std::min(last, from + kPairRowChunk));
          if (out.size() <= share) continue;
          out.resize(share);
          out.shrink_to_fit();  // overflow only: drop what a chunk of coincident spheres made
          capped.store(true, std::memory_order_relaxed);
          break;
        }
      }
      if (!st.fast.empty()) drop_fast_speculative_pairs(out);
      if (modes.pair_margins && search != PairSearch::Grid) keep_pairs_within_their_margin(out, margin);
    });
    w.stats.sphere_contacts_capped = capped.load();
  }

  /// Drops the pairs whose gap is beyond their own margin (WorldSettings::pair_margin_travel):
  /// the search used the step's margin, which the fastest sphere sets for every pair. The
  /// predicate is spheres_within's, with the pair's margin in place of the step's.
  void keep_pairs_within_their_margin(std::vector<SpherePair>& pairs, float margin) const {
    const SphereSoA& s = w.spheres;
    const float k = w.settings.pair_margin_travel;
    const float* travel = st.travel.data();
    std::erase_if(pairs, [&](const SpherePair& p) {
      const float pair_margin = std::min(margin, k * (travel[p.a] + travel[p.b]));
      const float reach = s.radius[p.b] + (s.radius[p.a] + pair_margin);
      return !spheres_within(s.px[p.b] - s.px[p.a], s.py[p.b] - s.py[p.a], s.pz[p.b] - s.pz[p.a], reach);
    });
  }

  /// |v| dt of spheres [first, last), for keep_pairs_within_their_margin (and the grid's
  /// margins), and never less than a share of the contact slop: k (ta + tb) is then at least
  /// kRestingContactSlop (ra + rb) / 2, so two spheres at rest that touch, or nearly, keep
  /// their contact. Without it their margin was 0, the pair search's strict test left out
  /// spheres touching exactly, and a pulse crossed a resting row one sphere per step (the
  /// cradle: the far sphere left 4 steps after the impact, tests/test_known_answers.cpp).
  /// The floor, kRestingContactSlop r / 2k, is 0.125 mm at r = 0.5, k = 2: under gravity only a
  /// sphere near the top of a hop travels less (g dt^2 is 2.7 mm at 60 Hz).
  void remember_travel(std::size_t first, std::size_t last) {
    const SphereSoA& s = w.spheres;
    const float floor_per_radius = kRestingContactSlop / (2.0f * w.settings.pair_margin_travel);  // k > 0 here
    float* __restrict travel = st.travel.data();
    const float* __restrict vx = s.vx.data();
    const float* __restrict vy = s.vy.data();
    const float* __restrict vz = s.vz.data();
    const float* __restrict radius = s.radius.data();
    for (std::size_t i = first; i < last; ++i) {
      const float moved = std::sqrt(vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]) * params.dt;
      const float least = floor_per_radius * radius[i];
      travel[i] = moved > least ? moved : least;
    }
  }

  /// A fast sphere meets what it does not touch yet in the sweep, at the time it hits: a
  /// speculative contact would bounce it at the start of the step instead.
  void drop_fast_speculative_pairs(std::vector<SpherePair>& pairs) const {
    const SphereSoA& s = w.spheres;
    auto fast = [&](std::uint32_t i) { return std::binary_search(st.fast.begin(), st.fast.end(), i); };
    std::erase_if(pairs, [&](const SpherePair& p) {
      if (!fast(p.a) && !fast(p.b)) return false;
      const float dx = s.px[p.b] - s.px[p.a], dy = s.py[p.b] - s.py[p.a], dz = s.pz[p.b] - s.pz[p.a];
      const float reach = s.radius[p.a] + s.radius[p.b];
      return dx * dx + dy * dy + dz * dz > reach * reach;
    });
  }

  /// Where masses differ (shock propagation runs), a light sphere that a heavy one strikes in
  /// the solve can leave it many times faster than it came: 17 m/s from 4 m/s (hail-bench
  /// stress, small-under-big-rain). It had no contacts for that speed (its margins were its
  /// own), and went a third of its radius into a heavy sphere beyond them in the same step.
  /// So in such steps a sphere the solve made fast is swept too, as if fast from the start
  /// (its contacts so far were solved, and it meets the rest of its path in the sweep). Each
  /// block's are found in parallel and kept in slot order, so st.fast stays sorted.
  void add_struck_fast() {
    const SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const float fraction = w.settings.fast_travel_fraction;
    std::atomic<bool> any{false};
    for_each_block(n, kSphereBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Sweep);
      std::vector<std::uint32_t>& fast = st.fast_blocks[b];
      const std::size_t already = fast.size();
      for (std::size_t i = first; i < last; ++i) {
        const float v2 = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
        if (s.inv_mass[i] > 0.0f && is_fast(v2, params.dt, s.radius[i], fraction) &&
            !std::binary_search(fast.begin(), fast.begin() + static_cast<std::ptrdiff_t>(already),
                                static_cast<std::uint32_t>(i)))
          fast.push_back(static_cast<std::uint32_t>(i));
      }
      if (fast.size() == already) return;
      std::inplace_merge(fast.begin(), fast.begin() + static_cast<std::ptrdiff_t>(already), fast.end());
      any.store(true, std::memory_order_relaxed);
    });
    if (!any.load()) return;
    st.fast.clear();
    for (const std::vector<std::uint32_t>& block : st.fast_blocks) st.fast.insert(st.fast.end(), block.begin(), block.end());
  }

  /// Continuous collision: the fast spheres' first impacts found in parallel, then all impacts
  /// taken in time order (serial, few), then the swept spheres placed at their end of step.
  void sweep() {
    ContinuousCollision& ccd = st.ccd;
    SphereSoA& s = w.spheres;
    ccd.begin(s, st.fast, params.dt, w.settings.fast_travel_fraction, SweepCandidates::Automatic,
              w.settings.reorder_interval > 0);
    if (st.fast.empty()) return;
    const SweepScene scene{.terrain = w.terrain,
                           .terrain_restitution = w.terrain_restitution,
                           .terrain_friction = w.terrain_friction,
                           .planes = w.planes,
                           .sphere_collisions = w.settings.sphere_collisions,
                           .modes = modes,
                           .hold_mass_ratio = w.settings.shock_mass_ratio,
                           .meshes = w.meshes};
    for_each_block(st.fast.size(), 16, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Sweep);
      ccd.find_first_events(s, scene, first, last);
    });
    ccd.resolve(s, scene, params.restitution_threshold, w.settings.max_sweep_events);
    ccd.finish(s);
    if (modes.sleeping) services.sleep.wake_hit(s, ccd.impacts());  // a sleeper hit moves with its impulse now
  }

  /// All contacts in one array, in block order: static contacts, then sphere pairs. Block
  /// offsets are summed first, so the blocks are copied (and pairs made into contacts) in
  /// parallel into fixed places.
  void merge_contacts() {
    const SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t static_blocks = block_count(n, kSphereBlock), pair_blocks = block_count(n, kPairRowBlock);
    std::vector<std::size_t>& offset = st.merge_offsets;
    assign_geometric(offset, static_blocks + pair_blocks + 1, std::size_t{0});
    for (std::size_t b = 0; b < static_blocks; ++b) offset[b + 1] = offset[b] + st.contact_blocks[b].size();
    for (std::size_t b = 0; b < pair_blocks; ++b)
      offset[static_blocks + b + 1] = offset[static_blocks + b] + st.pair_blocks[b].size();
    resize_geometric(st.contacts, offset.back());
    const std::size_t static_count = offset[static_blocks];
    const bool warm = modes.warm_start;
    // Rolling resistance starts from last step's rolling impulses too (resist_rolling).
    float* const rolling = warm && resists_rolling() ? resized_rolling_impulses() : nullptr;
    std::atomic<bool> friction{false};    // an OR: the order of stores cannot change the result
    std::atomic<std::size_t> matched{0};  // a sum: the order of adds cannot change it
    if (warm) st.contact_cache.begin_layout(s);
    for_each_block(static_blocks + pair_blocks, 1, [&](std::size_t b, std::size_t, std::size_t) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      Contact* const first = st.contacts.data() + offset[b];
      Contact* out = first;
      if (b < static_blocks) {
        out = std::copy(st.contact_blocks[b].begin(), st.contact_blocks[b].end(), out);
      } else {
        // Made in place (the returned prvalue initialises *out): assigned from a temporary,
        // its copy read back 16 bytes at a time what the call had just stored 4 bytes at a time,
        // and store forwarding failed on each contact, most of the merge's time (perf:
        // docs/benchmarks.md, "Figures behind the code's choices").
        for (const SpherePair& pair : st.pair_blocks[b - static_blocks])
          ::new (static_cast<void*>(out++)) Contact(make_sphere_contact(s, pair));
      }
      if (std::any_of(first, out, [](const Contact& c) { return c.friction > 0.0f; }))
        friction.store(true, std::memory_order_relaxed);
      // The block's warm-start impulses while its contacts are still in this core's cache
      // (a pass of its own read them all back from memory at 64k).
      // And where they lie, for remembering their impulses after the solve.
      if (warm) {
        matched += st.contact_cache.load(st.contacts, static_count, offset[b], offset[b + 1], s,
                                         w.settings.warm_start_factor, rolling);
        if (b < static_blocks) {
          st.contact_cache.layout_static(st.contacts, offset[b], offset[b + 1], b * kSphereBlock,
                                         std::min(n, (b + 1) * kSphereBlock), s);
        } else {
          const std::size_t rows = b - static_blocks;
          st.contact_cache.layout_pairs(st.contacts, offset[b], offset[b + 1], rows * kPairRowBlock,
                                        std::min(n, (rows + 1) * kPairRowBlock));
        }
      }
    });
    friction_needed_ = friction.load();
    w.stats.static_contacts = static_count;
    w.stats.sphere_contacts = st.contacts.size() - static_count;
    w.stats.warm_started = matched.load();
  }

  /// Keeps this step's impulses for the next step's warm start: each contact (now in colour
  /// order) into the cache at its detection-order index, where the merge noted the ranges.
  void remember_impulses() {
    if (!modes.warm_start) return;
    ContactImpulseCache& cache = st.contact_cache;
    cache.begin_store(st.contacts.size(), modes.sleepers ? &w.spheres : nullptr);  // sleepers keep theirs
    const std::uint32_t* order = st.colouring.order.data();
    const std::size_t static_count = w.stats.static_contacts;
    // The soft step passes on no impulse of a contact whose push was saturated when the step
    // began (soft_push_saturated): a deep overlap's push, not a weight carried. The contact
    // keeps it for World::last_contacts.
    const bool soft = modes.soft_step();
    const SoftPass saturation = soft_pass_settings();
    // No push saturates at a gap above half the stiffer ground spring's saturation depth (half:
    // clear of rounding at the bound): most contacts are decided without their spheres' masses.
    const float shallowest_saturated =
        -0.5f * saturation.max_push_speed / std::max(saturation.ground.bias_rate, saturation.contact.bias_rate);
    const SphereSoA& s = w.spheres;
    for_each_block(st.contacts.size(), kContactChunk * 4, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      for (std::size_t k = first; k < last; ++k) {
        const Contact& c = st.contacts[k];
        if (soft && !(c.gap > shallowest_saturated)) {
          ContactBodies bodies;
          bodies.ima = s.inv_mass[c.a];
          bodies.imb = c.b == kStaticBody ? 0.0f : s.inv_mass[c.b];
          if (soft_push_saturated(bodies, c.gap, saturation)) {
            Contact spent = c;
            spent.normal_impulse = spent.tx = spent.ty = spent.tz = 0.0f;
            cache.store_entry(order[k], spent, order[k] < static_count, s);
            continue;
          }
        }
        cache.store_entry(order[k], c, order[k] < static_count, s);
      }
    });
    if (rolled_) cache.store_rolling(st.rolling_impulses);
  }

  /// Rolling resistance may run this step (it runs where, besides, some contact has friction).
  [[nodiscard]] bool resists_rolling() const {
    return modes.rotation && !modes.soft_step() && w.settings.rolling_resistance > 0.0f;
  }

  /// st.rolling_impulses sized for this step's contacts (3 floats each, detection order).
  float* resized_rolling_impulses() {
    resize_geometric(st.rolling_impulses, 3 * st.contacts.size());
    return st.rolling_impulses.data();
  }

  /// Runs f(tile, first_batch, last_batch, scalar_contacts) over the staged contact batches:
  /// first every tile t (kernel/solver/contact_colouring.h) for which tile_wanted(t), as one block, its
  /// colours in order, tiles in parallel (one crew stage for all of them); then the shared
  /// colours (tile = tile_count()) one after another, the chunks of each in parallel (one crew
  /// stage per colour). A serial overflow colour is all scalar contacts (a batched colour has
  /// none). Chunks are fixed by the batch count, not the thread count.
  template <class TileWanted, class F>
  void for_each_batch_chunk(StageCrew& crew, TileWanted&& tile_wanted, F&& f) {
    const ContactColouring& col = st.colouring;
    const ContactBatches& batches = st.contact_batches;
    const std::size_t tiles = col.tile_count();
    auto whole_colour = [&](std::size_t tile, std::size_t colour) {
      const std::size_t end = col.colour_begin[colour + 1], tail = batches.tail_begin(colour);
      f(tile, batches.batch_begin(colour), batches.batch_end(colour),
        std::span<Contact>(st.contacts.data() + tail, end - tail));
    };
    crew.stage(tiles, [&](std::size_t t) {
      if (!tile_wanted(t)) return;
      ScopedTraceRecord record(w.trace, Phase::Solve);
      for (std::size_t colour = col.tile_colour_begin[t]; colour < col.tile_colour_begin[t + 1]; ++colour)
        whole_colour(t, colour);
    });
    for (std::size_t colour = col.shared_colour_begin(); colour < col.colour_count(); ++colour) {
      const std::size_t first = batches.batch_begin(colour), count = batches.batch_end(colour) - first;
      if (col.is_serial(colour) || count <= kBatchChunk) {
        crew.stage(1, [&](std::size_t) {
          ScopedTraceRecord record(w.trace, Phase::Solve);
          whole_colour(tiles, colour);
        });
        continue;
      }
      const std::size_t chunks = block_count(count, kBatchChunk);
      crew.stage(chunks, [&](std::size_t k) {
        ScopedTraceRecord record(w.trace, Phase::Solve);
        f(tiles, first + k * kBatchChunk, first + std::min(count, (k + 1) * kBatchChunk), std::span<Contact>());
      });
    }
  }

  /// for_each_batch_chunk over every tile.
  template <class F>
  void for_each_batch_chunk(StageCrew& crew, F&& f) {
    for_each_batch_chunk(
        crew, [](std::size_t) { return true; }, f);
  }

  /// After collision pass `pass` applied impulses to some contacts in shared batches [first,
  /// last) or `scalar`: each tile with a body the pass changed (stamp pass + 1) gets that stamp
  /// too, so that the next pass runs the tile (tile_changed_ is the most recent stamp of any of
  /// the tile's bodies). Chunks of one colour may mark one tile at once, with the same value.
  void mark_changed_tiles(std::size_t first, std::size_t last, std::span<const Contact> scalar,
                          std::span<const SolverBody> bodies, std::uint32_t pass, std::size_t tile_spheres) {
    const std::uint32_t stamp = pass + 1;
    const std::size_t n = bodies.size() - 1;  // the static body is last
    auto mark = [&](std::uint32_t slot) {
      if (slot < n && bodies[slot].changed_in_pass == stamp)
        std::atomic_ref<std::uint32_t>(st.tile_changed[slot / tile_spheres]).store(stamp, std::memory_order_relaxed);
    };
    auto mark_contacts = [&](std::span<const Contact> run) {
      for (const Contact& c : run) {
        mark(c.a);
        if (c.b != kStaticBody) mark(c.b);
      }
    };
    const auto [begin, end] = st.contact_batches.contact_range(first, last);
    mark_contacts(std::span<const Contact>(st.contacts.data() + begin, end - begin));
    mark_contacts(scalar);
  }

  /// colour_contacts, its tiles in parallel (TiledColouring: the same colouring, bit for bit)
  /// when there are tiles and threads to share them. On one thread the plain loop is faster
  /// (it lists no tiles), on two the tiles' colouring no longer leaves a thread idle (solve
  /// phase, terrain-rain: docs/benchmarks.md, "Figures behind the code's choices").
  void colour(std::size_t n, std::size_t tile_spheres, const SolveStartVelocities& velocities) {
    if (tile_spheres == 0 || tbb::this_task_arena::max_concurrency() == 1) {
      colour_contacts(st.contacts, n, st.colouring, tile_spheres, &velocities);
      return;
    }
    const std::size_t static_blocks = block_count(n, kSphereBlock), pair_blocks = block_count(n, kPairRowBlock);
    const std::vector<std::size_t>& offset = st.merge_offsets;
    const DetectionBlocks blocks{std::span<const std::size_t>(offset.data(), static_blocks + 1),
                                 std::span<const std::size_t>(offset.data() + static_blocks, pair_blocks + 1),
                                 kSphereBlock, kPairRowBlock};
    TiledColouring& tiled = st.tiled_colouring;
    const std::size_t tiles = tiled.begin(st.contacts, blocks, n, st.colouring, tile_spheres, &velocities);
    for_each_block(tiles, 1, [&](std::size_t t, std::size_t, std::size_t) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      tiled.colour_tile(t);
    });
    tiled.colour_shared();
    for_each_block(tiles, 1, [&](std::size_t t, std::size_t, std::size_t) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      tiled.place_tile(t);
    });
  }

  /// This (sub)step's velocity change from gravity at scale 1, g dt: what the uniform
  /// integrator's approach speeds take off the closing speeds (the passes' restitution and the
  /// hit events' speeds).
  [[nodiscard]] std::array<float, 3> gravity_dt() const {
    return {params.gravity[0] * params.dt, params.gravity[1] * params.dt, params.gravity[2] * params.dt};
  }

  /// Solver::Passes: collision passes, warm start, resting passes (kernel/solver/contact_impulse.h).
  void passes(std::size_t stages, std::span<SolverBody> bodies, FrictionWork work, float threshold, float inv_dt,
              std::size_t tile_spheres, const RollingContacts* rolling) {
    const ContactColouring& col = st.colouring;
    ContactBatches& batches = st.contact_batches;
    const std::size_t tiles = col.tile_count();
    // Under the uniform-acceleration integrator restitution takes the approach speed, the
    // closing speed less what this step's gravity added (solve_collision's gravity_closing).
    const std::array<float, 3> g_dt = gravity_dt();
    const float* approach = modes.uniform_acceleration() ? g_dt.data() : nullptr;
    st.crew.run(stages, [&](StageCrew& crew) {
      for (int pass = 0; pass < w.settings.collision_iterations; ++pass) {
        std::atomic<bool> any{false};  // an OR: the order of stores cannot change the result
        const auto number = static_cast<std::uint32_t>(pass);
        // A tile none of whose bodies changed since the previous pass began would skip every
        // batch (ContactBatches::solve_collision): skipped whole, without reading its batches.
        auto tile_wanted = [&](std::size_t t) { return pass == 0 || st.tile_changed[t] >= number; };
        for_each_batch_chunk(
            crew, tile_wanted, [&](std::size_t tile, std::size_t first, std::size_t last, std::span<Contact> scalar) {
              const bool simd =
                  batches.solve_collision(first, last, bodies, params.dt, threshold, number, work, approach);
              const bool rest =
                  solve_collision_run_scalar(scalar, bodies, params.dt, threshold, number, work, approach);
              if (!(simd || rest)) return;
              any.store(true, std::memory_order_relaxed);
              if (tile < tiles)
                st.tile_changed[tile] = number + 1;  // only this tile's block writes it
              else if (tiles > 0)
                mark_changed_tiles(first, last, scalar, bodies, number, tile_spheres);
            });
        if (!any.load()) break;
        ++w.stats.collision_passes;
      }
      // Warm start after the collision passes, not before: applied first, an impulse that no
      // longer fits the pile pushes neighbours into each other faster than the restitution
      // threshold, and the collision passes bounce them: the pile keeps jittering (bowl-pile's
      // energy: docs/benchmarks.md, "Figures behind the code's choices").
      if (modes.warm_start && w.stats.warm_started > 0)
        for_each_batch_chunk(crew, [&](std::size_t, std::size_t first, std::size_t last, std::span<Contact> scalar) {
          batches.warm_start(first, last, bodies, work);
          warm_start_run_scalar(scalar, bodies, work);
        });
      // Rolling resistance's too, so that the resting passes' friction holds a sphere that
      // rolling resistance holds still: started after the passes instead, the passes set it
      // rolling every step and the sweeps stopped it only to (5/7)^8 (the pile crept).
      if (rolling && modes.warm_start && w.stats.warm_started > 0) {
        const ContactColouring& col = st.colouring;
        crew.stage(tiles, [&](std::size_t t) {
          ScopedTraceRecord record(w.trace, Phase::Solve);
          warm_start_rolling(*rolling, col.colour_begin[col.tile_colour_begin[t]],
                             col.colour_begin[col.tile_colour_begin[t + 1]], bodies);
        });
        crew.stage(1, [&](std::size_t) {
          ScopedTraceRecord record(w.trace, Phase::Solve);
          warm_start_rolling(*rolling, col.colour_begin[col.shared_colour_begin()], st.contacts.size(), bodies);
        });
      }
      for (int pass = 0; pass < w.settings.resting_iterations; ++pass) {
        for_each_batch_chunk(crew, [&](std::size_t, std::size_t first, std::size_t last, std::span<Contact> scalar) {
          batches.solve_resting(first, last, bodies, inv_dt, work);
          solve_resting_run_scalar(scalar, bodies, inv_dt, work);
        });
      }
    });
  }

  /// The soft step's substep (the step over its substeps).
  [[nodiscard]] float soft_substep() const { return params.dt / static_cast<float>(w.settings.soft_step.substeps); }

  /// The soft passes' springs and push limit (what soft_push_saturated reads too).
  [[nodiscard]] SoftPass soft_pass_settings() const {
    const SoftStepParams& knobs = w.settings.soft_step;
    const float h = soft_substep();
    const float hertz = knobs.contact_cycles / h;
    SoftPass pass;
    pass.inv_h = 1.0f / h;
    pass.contact = make_soft(hertz, knobs.damping_ratio, h);
    pass.ground = make_soft(2.0f * hertz, knobs.damping_ratio, h);
    pass.max_push_speed = knobs.max_push_speed;
    return pass;
  }

  /// Solver::SoftStep (kernel/solver/soft_step.h): prepare, then per substep of h gravity (from
  /// the second), warm start, one soft iteration (and the shock pass where masses differ),
  /// positions, relax iterations; then restitution.
  void soft_step(StageCrew& crew, std::span<SolverBody> bodies, FrictionWork work, float h) {
    const SoftStepParams& knobs = w.settings.soft_step;
    ContactBatches& batches = st.contact_batches;
    const std::size_t n = bodies.size() - 1;
    SoftPass pass = soft_pass_settings();
    pass.restitution_threshold = params.restitution_threshold;
    auto run = [&](SoftPassKind kind) {
      pass.kind = kind;
      for_each_batch_chunk(crew, [&](std::size_t, std::size_t first, std::size_t last, std::span<Contact> scalar) {
        batches.solve_soft(first, last, bodies, pass, work);
        soft_run_scalar(scalar, bodies, pass, work);
      });
    };
    auto for_bodies = [&](auto&& f) {
      crew.stage(block_count(n, kSphereBlock), [&](std::size_t b) {
        ScopedTraceRecord record(w.trace, Phase::Solve);
        f(b * kSphereBlock, std::min(n, (b + 1) * kSphereBlock));
      });
    };
    const float g_h[3] = {params.gravity[0] * h, params.gravity[1] * h, params.gravity[2] * h};
    pass.impulse_factor = 1.0f / static_cast<float>(knobs.substeps);
    run(SoftPassKind::Prepare);
    for (int k = 0; k < knobs.substeps; ++k) {
      if (k > 0) for_bodies([&](std::size_t first, std::size_t last) { soft_add_gravity(bodies, first, last, g_h); });
      for_each_batch_chunk(crew, [&](std::size_t, std::size_t first, std::size_t last, std::span<Contact> scalar) {
        batches.warm_start(first, last, bodies, work);
        warm_start_run_scalar(scalar, bodies, work);
      });
      run(SoftPassKind::Solve);
      // Where masses differ, the shock pass (planned by solve()) after each soft iteration,
      // before the positions move: one soft iteration passes a heavy sphere's weight down a
      // stack no better than a resting pass does (kernel/solver/shock_propagation.h).
      if (shock) {
        ScopedTraceRecord record(w.trace, Phase::Solve);
        st.shock.solve(st.contacts, bodies, 1.0f / params.dt);  // a gap closes at most once over the substeps
      }
      for_bodies([&](std::size_t first, std::size_t last) { soft_move(bodies, first, last, h); });
      for (int r = 0; r < knobs.relax_iterations; ++r) run(SoftPassKind::Relax);
    }
    pass.impulse_factor = static_cast<float>(knobs.substeps);
    run(SoftPassKind::Restitution);
  }

  void solve() {
    SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t tile_spheres = solver_tile_size(w.settings.solver_tile_spheres, n);
    const SolveStartVelocities velocities{s.vx.data(), s.vy.data(), s.vz.data(), 1.0f / params.dt};
    colour(n, tile_spheres, velocities);
    // Contacts moved into colour order, so that each colour is a contiguous run that the SIMD
    // batches are staged from and the scalar parts stream through.
    resize_geometric(st.coloured_contacts, st.contacts.size());
    for_each_block(st.contacts.size(), kContactChunk * 4, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      for (std::size_t k = first; k < last; ++k) st.coloured_contacts[k] = st.contacts[st.colouring.order[k]];
    });
    std::swap(st.contacts, st.coloured_contacts);
    // What the passes compute: no friction (no contact has any), friction on linear velocities
    // (rotation off), or friction with the angular terms. Angular velocities are loaded only
    // for the last: normal impulses (the shock pass's too) never turn a sphere.
    const FrictionWork work = friction_work(friction_needed_, modes.rotation);
    const bool angular = modes.rotation && friction_needed_;
    rolled_ = angular && resists_rolling();
    const RollingContacts rolling = rolled_ ? rolling_contacts() : RollingContacts{};
    // Bodies 0..n-1, then one static body (all zero) that static contacts gather from.
    if (st.solver_bodies.size() < n + 1) resize_geometric(st.solver_bodies, n + 1);
    const std::span<SolverBody> bodies(st.solver_bodies.data(), n + 1);
    bodies[n] = SolverBody{};
    const bool soft = modes.soft_step();
    const int substeps = w.settings.soft_step.substeps;
    const float h = params.dt / static_cast<float>(substeps);
    for_each_block(n, kSphereBlock, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      load_solver_bodies(s, first, last, bodies, angular);
      if (!soft) {
        // The collision passes' approach speeds under the uniform integrator (gravity_closing_speed).
        if (modes.uniform_acceleration())
          for (std::size_t i = first; i < last; ++i)
            bodies[i].gravity_scale = s.inv_mass[i] > 0.0f ? (modes.gravity_scaled ? s.gravity_scale[i] : 1.0f) : 0.0f;
        return;
      }
      const float g_rest[3] = {params.gravity[0] * (params.dt - h), params.gravity[1] * (params.dt - h),
                               params.gravity[2] * (params.dt - h)};
      soft_load_bodies(s, first, last, bodies, g_rest, modes.gravity_scaled);
    });
    const ContactColouring& col = st.colouring;
    ContactBatches& batches = st.contact_batches;
    batches.plan(col.colour_begin, col.serial);
    for_each_block(batches.batch_count(), kBatchChunk, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      batches.fill(first, last, st.contacts, std::span<const float>(s.radius.data(), n));
    });
    w.stats.colours = col.sequential_colours();
    w.stats.shared_contacts = col.colour_begin.back() - col.colour_begin[col.shared_colour_begin()];
    w.stats.tile_contacts = st.contacts.size() - w.stats.shared_contacts;
    w.stats.collision_passes = 0;
    const float threshold = params.restitution_threshold;
    const float inv_dt = 1.0f / params.dt;
    // The passes below are about (collision + 1 + resting) x (1 + shared colours) short
    // stages: one crew for all of them (jobs/stage_crew.h) instead of a parallel loop each.
    const std::size_t tiles = col.tile_count();
    const std::size_t stages_per_pass = (tiles > 0 ? 1 : 0) + col.colour_count() - col.shared_colour_begin();
    assign_geometric(st.tile_changed, tiles, std::uint32_t{0});
    const std::size_t stages = (static_cast<std::size_t>(w.settings.collision_iterations) + 1 +
                                static_cast<std::size_t>(w.settings.resting_iterations)) *
                               stages_per_pass;
    if (soft) {
      // Prepare and restitution, and per substep warm start, the soft iteration and the relax
      // ones over the contacts, gravity and positions over the bodies.
      const std::size_t contact_passes = 2 + static_cast<std::size_t>(substeps) *
                                                 (2 + static_cast<std::size_t>(w.settings.soft_step.relax_iterations));
      if (shock) st.shock.plan(st.contacts, bodies, up());
      st.crew.run(contact_passes * stages_per_pass + 2 * static_cast<std::size_t>(substeps),
                  [&](StageCrew& crew) { soft_step(crew, bodies, work, h); });
    } else {
      passes(stages + 1, bodies, work, threshold, inv_dt, tile_spheres, rolled_ ? &rolling : nullptr);
    }
    if (shock && !soft) {
      // Serial: it runs only in scenes of very different masses, and its order is its point.
      ScopedTraceRecord record(w.trace, Phase::Solve);
      st.shock.plan(st.contacts, bodies, up());
      st.shock.solve(st.contacts, bodies, inv_dt);
    }
    for_each_block(batches.batch_count(), kBatchChunk * 4, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      batches.store_impulses(st.contacts, first, last);
    });
    if (rolled_) resist_rolling(bodies, rolling);
    remember_impulses();
    for_each_block(n, kSphereBlock, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Solve);
      if (soft)
        soft_store_bodies(bodies, first, last, s, angular, params);
      else
        store_solver_velocities(bodies, first, last, s, angular);
    });
  }

  /// The step's contacts and their rolling impulses (the merge loaded last step's; zero without
  /// warm starting), for rolling resistance.
  [[nodiscard]] RollingContacts rolling_contacts() {
    if (!modes.warm_start) assign_geometric(st.rolling_impulses, 3 * st.contacts.size(), 0.0f);
    return {st.contacts, st.colouring.order, st.rolling_impulses, w.settings.rolling_resistance};
  }

  /// Rolling resistance after the passes (kernel/solver/rolling_resistance.h): the sweeps, each
  /// the tiles in parallel, each its contacts in colour order, then the contacts across tiles.
  void resist_rolling(std::span<SolverBody> bodies, const RollingContacts& rolling) {
    const ContactColouring& col = st.colouring;
    const std::size_t shared = col.colour_begin[col.shared_colour_begin()];
    auto over_contacts = [&](auto&& f) {
      for_each_block(col.tile_count(), 1, [&](std::size_t t, std::size_t, std::size_t) {
        ScopedTraceRecord record(w.trace, Phase::Solve);
        f(col.colour_begin[col.tile_colour_begin[t]], col.colour_begin[col.tile_colour_begin[t + 1]]);
      });
      f(shared, st.contacts.size());
    };
    for (int sweep = 0; sweep < kRollingResistanceSweeps; ++sweep)
      over_contacts([&](std::size_t first, std::size_t last) { hail::resist_rolling(rolling, first, last, bodies); });
  }

  /// Moves the spheres the sweep did not, then lists the step's impacts (World::last_impacts):
  /// the sweep's, then each block's plane impacts in block order (so in slot order).
  void integrate() {
    SphereSoA& s = w.spheres;
    const bool planes = !w.planes.empty();
    const std::size_t blocks = block_count(s.size(), kSphereBlock);
    if (planes) grow_block_lists(st.impact_blocks, blocks);
    for_each_block(s.size(), kSphereBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Integrate);
      std::vector<Impact>* impacts = planes ? &st.impact_blocks[b] : nullptr;
      if (impacts) impacts->clear();
      if (modes.sleeping && block_still(first, last)) return;  // nothing in it moves
      integrate_positions(s, first, last, w.planes, params, st.ccd.moved(), impacts);
    });
    st.impacts.clear();
    std::size_t count = modes.sweeping ? st.ccd.impacts().size() : 0;
    if (planes)
      for (std::size_t b = 0; b < blocks; ++b) count += st.impact_blocks[b].size();
    reserve_geometric(st.impacts, count);
    if (modes.sweeping) st.impacts.insert(st.impacts.end(), st.ccd.impacts().begin(), st.ccd.impacts().end());
    if (planes)
      for (std::size_t b = 0; b < blocks; ++b)
        st.impacts.insert(st.impacts.end(), st.impact_blocks[b].begin(), st.impact_blocks[b].end());
  }

  /// The soft step's depenetration goes on past depenetration_iterations (up to
  /// SoftStepParams::depenetration_iterations_max) for contacts of spheres smaller than this:
  /// those whose contact spring sags beyond the slop under gravity alone (soft_sag between
  /// spheres, the softer of its two springs, over the slop fraction: 6.9 mm at the defaults and
  /// dt 1/60). A larger sphere's soft contact carries its weight within the slop, and the soft
  /// pushes of the next steps resolve its deeper overlaps, as the passes' resting contacts do;
  /// a smaller one rests as deep as its sag unless depenetration converges each step
  /// (docs/benchmarks.md, "Soft step"). 0 for the passes solver: exactly depenetration_iterations.
  /// Gravity at scale 1, as the step applies it (params); a sphere of a larger gravity scale, or
  /// pressed by a force, sags further than this assumes.
  [[nodiscard]] float soft_deep_radius() const {
    if (!modes.soft_step()) return 0.0f;
    const float* g = params.gravity;
    const float sag = soft_sag(std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]),
                               w.settings.soft_step.contact_cycles / soft_substep());
    const float slop = w.settings.depenetration.slop_fraction;
    return slop > 0.0f ? sag / slop : std::numeric_limits<float>::infinity();
  }

  /// Passes of push_apart, colour after colour. A contact whose spheres did not move since
  /// its previous pass evaluated it (and then moved nothing, or moved them: stamp equal) finds
  /// the same positions and would do nothing, so it is skipped: the same result for less work
  /// (most contacts of a pile are within the slop and never move anything). moved_at_ holds,
  /// per sphere, the number of the last (pass, colour) that moved it, 1-based, and one more
  /// entry, always 0, for the static body's slot. A colour's batches (staged by the solve) run
  /// in SIMD (ContactBatches::depenetrate); a serial overflow colour runs push_apart in order.
  void depenetrate() {
    SphereSoA& s = w.spheres;
    const ContactColouring& col = st.colouring;
    ContactBatches& batches = st.contact_batches;
    const std::size_t colours = col.colour_count();
    assign_geometric(st.moved_at, s.size() + 1, std::uint32_t{0});
    std::uint32_t* const moved = st.moved_at.data();
    DepenetrationArrays arrays{s.px.data(),
                               s.py.data(),
                               s.pz.data(),
                               s.inv_mass.data(),
                               moved,
                               static_cast<std::int32_t>(s.size()),
                               w.settings.depenetration,
                               soft_deep_radius()};
    // The soft step goes on past depenetration_iterations while a pass pushed a contact of
    // spheres that small out of an overlap beyond twice the slop
    // (SoftStepParams::depenetration_iterations_max). `deep` is an OR over the pass's
    // contacts: the order of stores cannot change it.
    const int least = w.settings.depenetration_iterations;
    const int most =
        arrays.deep_radius > 0.0f ? std::max(least, w.settings.soft_step.depenetration_iterations_max) : least;
    std::atomic<bool> deep{true};
    for (int pass = 0; pass < most && (pass < least || deep.load()); ++pass) {
      deep.store(false);
      auto stamps = [&](std::size_t colour) {
        const auto now = static_cast<std::uint32_t>(static_cast<std::size_t>(pass) * colours + colour + 1);
        return std::pair{now, pass == 0 ? 0u : now - static_cast<std::uint32_t>(colours)};
      };
      // The scalar rule, for a serial colour's contacts (which may share spheres).
      auto push_run = [&](std::size_t colour, std::span<const Contact> run) {
        const auto [now, previous] = stamps(colour);
        for (const Contact& c : run) {
          const bool dynamic_b = c.b != kStaticBody;
          if (pass > 0 && moved[c.a] < previous && !(dynamic_b && moved[c.b] >= previous)) continue;
          bool pushed_deep = false;
          if (!push_apart(s, c, w.settings.depenetration, arrays.deep_radius, pushed_deep)) continue;
          if (pushed_deep) deep.store(true, std::memory_order_relaxed);
          moved[c.a] = now;
          if (dynamic_b) moved[c.b] = now;
        }
      };
      auto push_colour = [&](std::size_t colour, std::size_t first_batch, std::size_t last_batch) {
        const auto [now, previous] = stamps(colour);
        if (batches.depenetrate(first_batch, last_batch, arrays, now, previous))
          deep.store(true, std::memory_order_relaxed);
        const std::size_t tail = batches.tail_begin(colour), end = col.colour_begin[colour + 1];
        push_run(colour, std::span<const Contact>(st.contacts.data() + tail, end - tail));
      };
      // Tiles in parallel, each its colours in order (they share no sphere), then the shared colours.
      for_each_block(col.tile_count(), 1, [&](std::size_t t, std::size_t, std::size_t) {
        ScopedTraceRecord record(w.trace, Phase::Depenetrate);
        for (std::size_t colour = col.tile_colour_begin[t]; colour < col.tile_colour_begin[t + 1]; ++colour)
          push_colour(colour, batches.batch_begin(colour), batches.batch_end(colour));
      });
      for (std::size_t colour = col.shared_colour_begin(); colour < colours; ++colour) {
        if (col.is_serial(colour)) {
          ScopedTraceRecord record(w.trace, Phase::Depenetrate);
          push_colour(colour, 0, 0);
          continue;
        }
        const std::size_t first = batches.batch_begin(colour), count = batches.batch_end(colour) - first;
        const std::pair<std::uint32_t, std::uint32_t> now_previous = stamps(colour);
        for_each_block(count, kBatchChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
          ScopedTraceRecord record(w.trace, Phase::Depenetrate);
          if (batches.depenetrate(first + begin, first + end, arrays, now_previous.first, now_previous.second))
            deep.store(true, std::memory_order_relaxed);
        });
      }
      ++w.stats.depenetration_passes;
    }
  }

  /// Every reorder_interval steps: dense slots re-sorted by Morton code (kernel/broadphase/spatial_order.h).
  [[nodiscard]] bool reorder_due() const {
    const int interval = w.settings.reorder_interval;
    return interval > 0 && w.steps_taken % static_cast<std::uint64_t>(interval) == 0;
  }
  /// morton_slot_order and SphereSoA::permute over blocks in parallel: the same order and the
  /// same state (kernel/broadphase/spatial_order.h). Serial, the sort alone was a phase whose share grows
  /// with N (n log n) and with the thread count (terrain-rain 256k: docs/benchmarks.md,
  /// "Figures behind the code's choices").
  void reorder() {
    SphereSoA& s = w.spheres;
    const std::size_t n = s.size();
    const std::size_t blocks = block_count(n, kReorderBlock);
    assign_geometric(st.reorder_bounds, blocks, empty_aabb());
    for_each_block(n, kReorderBlock, [&](std::size_t b, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Reorder);
      st.reorder_bounds[b] = finite_centre_bounds(s, first, last);
    });
    Aabb bounds = empty_aabb();
    for (const Aabb& b : st.reorder_bounds) grow(bounds, b);
    std::vector<std::uint64_t>& keys = st.reorder_keys;
    std::vector<std::uint32_t>& order = st.reorder_slots;
    resize_geometric(keys, n);
    resize_geometric(order, n);
    for_each_block(n, kReorderBlock, [&](std::size_t, std::size_t first, std::size_t last) {
      ScopedTraceRecord record(w.trace, Phase::Reorder);
      morton_keys(s, bounds, first, last, keys.data());
    });
    if (tbb::this_task_arena::max_concurrency() == 1) {
      std::sort(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(n));
    } else {
      SyncCounts::count_loop();
      tbb::parallel_sort(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(n));
    }
    auto for_ranges = [&](std::size_t count, auto&& f) {
      for_each_block(count, kReorderBlock, [&](std::size_t, std::size_t first, std::size_t last) {
        ScopedTraceRecord record(w.trace, Phase::Reorder);
        f(first, last);
      });
    };
    for_ranges(n, [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) order[k] = static_cast<std::uint32_t>(keys[k]);
    });
    // Without rotation every w is 0, without forces pending every accumulator.
    s.permute(std::span<const std::uint32_t>(order.data(), n), /*angular=*/modes.rotation,
              /*accumulators=*/modes.forces, for_ranges);
    st.contact_cache.remap_slots(std::span<const std::uint32_t>(order.data(), n));  // its ranges are kept by slot
  }

  /// The step is assembled from what the scene has (StepParts): a phase with nothing to do is
  /// not entered at all, so a scene pays only for the features it uses.
  void run() {
    PhaseTimes& t = w.times;
    StepParts& ran = w.stats.ran;
    ran = {};
    ran.reorder = reorder_due();
    if (ran.reorder) {
      ScopedPhaseTimer timer(t.reorder);
      ScopedTraceRecord record(w.trace, Phase::Reorder);
      reorder();
    }
    float margin = 0.0f;
    ran.terrain_guard = modes.terrain_guard;
    w.stats.pushed_out = 0;
    w.stats.depenetration_passes = 0;
    if (modes.pair_margins && st.travel.size() < w.spheres.size()) resize_geometric(st.travel, w.spheres.size());
    if (modes.uniform_acceleration()) {
      const std::size_t n = w.spheres.size();
      for (std::vector<float>* v : {&st.start_vx, &st.start_vy, &st.start_vz})
        if (v->size() < n) resize_geometric(*v, n);
      params.start_vx = st.start_vx.data(), params.start_vy = st.start_vy.data(), params.start_vz = st.start_vz.data();
    }
    if (modes.terrain_guard) {
      const std::size_t n = w.spheres.size();
      for (std::vector<float>* v : {&st.start_x, &st.start_y, &st.start_z, &st.reach2})
        if (v->size() < n) resize_geometric(*v, n);
    }
    // Each phase is also recorded on the thread that runs its serial parts (the trace's
    // per-block records cover the parallel parts).
    {
      ScopedPhaseTimer timer(t.predict);
      ScopedTraceRecord record(w.trace, Phase::Predict);
      predict(margin);
    }
    ran.detect_static = modes.detect_static;
    ran.detect_pairs = modes.detect_pairs;
    detect(margin);
    // A contact between a sleeper and a sphere that moves wakes the sleeper's island before the
    // solve; detection runs again so that the woken spheres' own contacts are solved this
    // substep too (and again if they touch another island). Rare: only substeps that wake.
    if (modes.sleeping)
      while (wake_touched()) {
        predict_woken(margin);
        detect(margin);
      }
    solve_and_move();
  }

  /// predict() for the spheres wake_touched just woke, which it skipped while they slept: this
  /// substep's gravity and forces, and the reach and travel their contacts are searched with.
  /// Without it a woken pile started its first substep without gravity and with no travel, so
  /// the pair search found only its overlapping contacts (25,327 of 33,626 for the 10,000-sphere
  /// pile of `hail-bench sleep`), and the pile answered a drop 4.2 mm RMS away from the same
  /// pile with sleeping off, 44 times the solver's step-to-step noise (0.02 mm, 0.2 times, with
  /// it). Serial: a substep that wakes is rare, and a woken sphere is one slot of its block.
  void predict_woken(float& margin) {
    ScopedPhaseTimer timer(w.times.predict);
    SphereSoA& s = w.spheres;
    float max_speed = 0.0f;
    for (const std::uint32_t i : services.sleep.woken_slots()) {
      if (modes.forces) apply_forces(s, i, i + 1, params.dt, modes.rotation);
      max_speed = std::max(max_speed, predict_velocities(s, i, i + 1, params, w.settings.fast_travel_fraction));
      if (modes.terrain_guard) remember_reach(i, i + 1);
      if (modes.pair_margins) remember_travel(i, i + 1);
    }
    margin = std::max(margin, std::min(2.0f * max_speed * params.dt, w.settings.speculative_radii * max_radius));
  }

  bool wake_touched() {
    ScopedPhaseTimer timer(w.times.islands);
    ScopedTraceRecord record(w.trace, Phase::Islands);
    return services.sleep.wake_touched(w.spheres, st.contacts);
  }

  /// Sphere-ground contacts and sphere pairs (both at once when both run), merged.
  void detect(float margin) {
    PhaseTimes& t = w.times;
    const StepParts& ran = w.stats.ran;
    auto detect_static_timed = [&] {
      ScopedPhaseTimer inner(t.detect_terrain);
      ScopedTraceRecord record(w.trace, Phase::DetectTerrain);
      detect_static();
    };
    auto detect_pairs_timed = [&] {
      ScopedPhaseTimer inner(t.detect_pairs);
      ScopedTraceRecord record(w.trace, Phase::DetectPairs);
      detect_pairs(margin);
    };
    if (ran.detect_static && ran.detect_pairs) {
      SyncCounts::count_loop();
      tbb::parallel_invoke(detect_static_timed, detect_pairs_timed);
    } else if (ran.detect_static) {
      detect_static_timed();
      clear_pair_blocks();
    } else if (ran.detect_pairs) {
      clear_static_blocks();
      detect_pairs_timed();
    } else {
      clear_static_blocks();
      clear_pair_blocks();
    }
    {
      ScopedPhaseTimer timer(t.solve);
      ScopedTraceRecord record(w.trace, Phase::Solve);
      merge_contacts();
    }
  }

  /// The rest of run(): solve, sweep, integrate, depenetrate, islands.
  void solve_and_move() {
    PhaseTimes& t = w.times;
    StepParts& ran = w.stats.ran;
    ran.solve = !st.contacts.empty();
    if (ran.solve) {
      ScopedPhaseTimer timer(t.solve);
      ScopedTraceRecord record(w.trace, Phase::Solve);
      if (services.events.wants_hits()) {  // approach speeds: under the uniform integrator before gravity
        const std::array<float, 3> g_dt = gravity_dt();
        services.events.remember_solve_start(w.spheres, modes.uniform_acceleration() ? g_dt.data() : nullptr);
      }
      solve();
    } else {
      w.stats.colours = w.stats.tile_contacts = w.stats.shared_contacts = 0;
      w.stats.collision_passes = 0;
      // Nothing touched: nothing to carry over, but what sleepers carry (the merge laid out
      // every slot's empty range, as begin_store needs).
      if (modes.warm_start && modes.sleeping) {
        st.contact_cache.begin_store(0, modes.sleepers ? &w.spheres : nullptr);
        if (resists_rolling()) st.contact_cache.store_rolling(st.rolling_impulses);  // theirs too
      } else if (modes.warm_start) {
        st.contact_cache.clear();
      }
    }
    ran.friction = ran.solve && friction_needed_;
    ran.rotation = ran.solve && modes.rotation && friction_needed_;
    ran.shock = ran.solve && shock;
    if (modes.sweeping && ran.shock) add_struck_fast();
    ran.sweep = modes.sweeping && !st.fast.empty();
    if (modes.sweeping) {
      ScopedPhaseTimer timer(t.sweep);
      ScopedTraceRecord record(w.trace, Phase::Sweep);
      sweep();
      w.stats.sweep = st.ccd.stats();
    }
    {
      ScopedPhaseTimer timer(t.integrate);
      ScopedTraceRecord record(w.trace, Phase::Integrate);
      // Speculative contacts are the terrain's and the meshes' alone (planes' impacts are the
      // integrator's). The shock pass leaves no trace of its impulses in the contacts, so with it
      // no bounce can be told to be a sphere's only impulse. A step whose collision passes bounced
      // nothing (a pile at rest) does not look.
      const bool time_bounces = ran.solve && (w.terrain != nullptr || w.meshes != nullptr) && !modes.soft_step() &&
                                !shock && w.stats.collision_passes > 0;
      if (time_bounces) st.bounce_timing.plan(st.contacts, w.spheres, params, st.ccd.moved());
      integrate();
      w.stats.timed_bounces = time_bounces ? st.bounce_timing.apply(st.contacts, w.spheres) : 0;
    }
    ran.depenetrate = ran.solve && w.settings.depenetration_iterations > 0;
    if (ran.depenetrate || modes.terrain_guard) {
      ScopedPhaseTimer timer(t.depenetrate);
      ScopedTraceRecord record(w.trace, Phase::Depenetrate);
      if (ran.depenetrate) depenetrate();
      if (ran.depenetrate && shock) shock_push_out();
      if (modes.terrain_guard) guard_terrain();
      if (ran.depenetrate && shock && ran.sweep) part_swept_pairs();
      if (ran.depenetrate && !w.planes.empty()) guard_planes();
    }
    if (modes.sleeping) {
      ScopedPhaseTimer timer(t.islands);
      ScopedTraceRecord record(w.trace, Phase::Islands);
      services.sleep.update(w.spheres, st.contacts, params.dt, w.settings);
    }
  }

  /// Phases that are skipped still leave their block buffers empty for merge_contacts.
  void clear_static_blocks() {
    const std::size_t blocks = block_count(w.spheres.size(), kSphereBlock);
    grow_block_lists(st.contact_blocks, blocks);
    for (std::size_t b = 0; b < blocks; ++b) st.contact_blocks[b].clear();
  }
  void clear_pair_blocks() {
    const std::size_t blocks = block_count(w.spheres.size(), kPairRowBlock);
    grow_block_lists(st.pair_blocks, blocks);
    for (std::size_t b = 0; b < blocks; ++b) st.pair_blocks[b].clear();
  }
};

void World::step(float dt) {
  // Before anything changes: a refused step leaves the world as it was.
  const int substeps = static_cast<int>(check_step(settings_, dt));  // <= max_substeps, an int
  services_->sphere_queries.invalidate();
  times_ = {};
  // Longer steps are split into equal substeps of at most max_substep (see WorldSettings).
  const float scaled = dt * settings_.time_scale;
  ContactEventTracker& events = services_->events;
  SleepIslands& sleep = services_->sleep;
  // Frozen (time_scale 0) or empty; or every movable sphere asleep and nothing else moving,
  // when a step would change nothing: it costs one pass over the flags.
  const bool all_asleep = settings_.sleep && !SleepIslands::anything_moves(spheres_);
  if (substeps == 0 || scaled == 0.0f || spheres_.size() == 0 || all_asleep) {
    clear_forces();
    if (events.on()) events.finish_idle_step(spheres_);
    if (all_asleep) {
      scratch_->contacts.clear();
      scratch_->impacts.clear();
      stats_ = {};
      stats_.sleeping = SleepIslands::count_sleeping(spheres_);
      steps_taken_ += static_cast<std::uint64_t>(substeps);  // the re-sort's phase goes on
    }
    if (settings_.sleep) sleep.publish();
    return;
  }
  refresh_uses();
  const std::size_t lifted = lift_out_of_terrain();  // spheres that start inside the terrain
  // dt * time_scale in float where it is finite (bitwise what steps always took); in double
  // where the float product overflows yet each substep does not.
  const float each = std::isfinite(scaled) ? scaled / static_cast<float>(substeps)
                                           : static_cast<float>(double(dt) * settings_.time_scale / substeps);
  if (events.on()) events.begin_step();
  const std::uint64_t loops_before = SyncCounts::loops.load(std::memory_order_relaxed);
  const std::uint64_t stages_before = SyncCounts::stages.load(std::memory_order_relaxed);
  for (int k = 0; k < substeps; ++k) substep(each);
  if (events.on() && settings_.sleep) events.keep_sleepers_touching(spheres_);
  if (events.on()) events.finish_step();
  clear_forces();  // forces and torques act over one step (each of its substeps), then are gone
  stats_.lifted_out = lifted;
  stats_.parallel_loops = static_cast<std::size_t>(SyncCounts::loops.load(std::memory_order_relaxed) - loops_before);
  stats_.crew_stages = static_cast<std::size_t>(SyncCounts::stages.load(std::memory_order_relaxed) - stages_before);
  if (settings_.sleep) {
    stats_.sleeping = SleepIslands::count_sleeping(spheres_);
    stats_.ready_to_sleep = sleep.ready_to_sleep();
    sleep.publish();
  }
}

void World::substep(float scaled) {
  // What this substep does, decided here once: every phase reads these.
  const StepModes modes{.integrator = settings_.integrator,
                        .solver = settings_.solver,
                        .rotation = settings_.rotation,
                        .warm_start = settings_.warm_start_factor > 0.0f,
                        .sweeping = settings_.continuous_collision,
                        .sleeping = settings_.sleep,
                        .sleepers = settings_.sleep && SleepIslands::any_sleeping(spheres_),
                        .detect_pairs = settings_.sphere_collisions && spheres_.size() > 1,
                        .detect_static = terrain_ != nullptr || !planes_.empty() || has_meshes(),
                        .terrain_guard = terrain_ != nullptr || has_meshes(),
                        .pair_margins = settings_.pair_margin_travel > 0.0f && settings_.sphere_collisions,
                        .forces = forces_pending_,
                        .gravity_scaled = gravity_scaled_,
                        .filtering = filtered_,
                        .ground = ground_filter_};
  StepPipeline pipeline{
      {settings_, spheres_, planes_, terrain_.get(), terrain_restitution_, terrain_friction_,
       has_meshes() ? meshes_.get() : nullptr, stats_, times_, trace_, steps_taken_},
      *scratch_,
      *services_,
      modes,
      {.modes = modes,
       .gravity = {settings_.gravity.x(), settings_.gravity.y(), settings_.gravity.z()},
       .dt = scaled,
       // A sphere lying on the ground closes at |g| dt per step; twice that is still resting.
       .restitution_threshold = std::max(settings_.restitution_threshold, 2.0f * settings_.gravity.norm() * scaled)}};
  arena_->execute([&] { pipeline.run(); });
  if (services_->events.on())
    services_->events.collect_substep(
        spheres_, scratch_->contacts, scratch_->impacts,
        {planes_, terrain_restitution_, has_meshes() ? meshes_.get() : nullptr, pipeline.params.restitution_threshold});
  if (trace_.enabled()) trace_.finish_step(steps_taken_);
  ++steps_taken_;
}

}  // namespace hail
