#pragma once
// StepScratch: what World::step computes and either throws away or hands to the next step:
// the per-block buffers of detection, the contacts and impacts of the last step
// (World::last_contacts, last_impacts), the colouring, solver bodies and SIMD batches, the
// warm-start cache (last step's impulses), the sweep, the terrain guard's and integrator's
// per-sphere arrays, the re-sort's keys, and the solver's threads. Reused, so that a
// steady-state step allocates nothing. World holds it by pointer (include/hail/world.h), so
// that only the step pipeline (kernel/world/step_pipeline.cpp) and the World's own files see
// the kernel's internal types. What serves the World between steps (events, sleep, queries) is
// WorldServices (kernel/world/world_services.h).

#include <cstdint>
#include <vector>

#include "hail/contact.h"
#include "jobs/stage_crew.h"
#include "kernel/broadphase/sorted_axis_pairs.h"
#include "kernel/broadphase/sphere_bvh_pairs.h"
#include "kernel/broadphase/sphere_grid.h"
#include "kernel/broadphase/sphere_pairs.h"
#include "kernel/ccd/continuous_collision.h"
#include "kernel/geometry/aabb.h"
#include "kernel/geometry/sphere_extremes.h"
#include "kernel/solver/bounce_timing.h"
#include "kernel/solver/contact_cache.h"
#include "kernel/solver/contact_colouring.h"
#include "kernel/solver/contact_solve_simd.h"
#include "kernel/solver/shock_propagation.h"
#include "kernel/solver/solver_body.h"

namespace hail {

struct StepScratch {
  // Detect: pairs and contacts per block, merged in block order.
  std::vector<std::vector<SpherePair>> pair_blocks;
  std::vector<std::vector<std::uint32_t>> pair_row_scratch;
  SphereGrid grid;
  SortedAxisPairs sorted_axis;
  SphereBvhPairs sphere_bvh;
  std::vector<std::vector<Contact>> contact_blocks;
  std::vector<Contact> contacts;                   ///< World::last_contacts()
  std::vector<std::vector<Impact>> impact_blocks;  ///< integrate: plane impacts per sphere block
  std::vector<Impact> impacts;                     ///< World::last_impacts(): the sweep's, then impact_blocks in order
  std::vector<std::size_t> merge_offsets;          ///< per detect block: where its contacts start in contacts
  // Solve.
  ContactColouring colouring;
  std::vector<std::uint32_t> tile_changed;  ///< per solver tile, the latest stamp of its bodies (changed_in_pass)
  TiledColouring tiled_colouring;           ///< colours the solver tiles in parallel
  std::vector<Contact> coloured_contacts;   ///< contacts before colour order
  std::vector<SolverBody> solver_bodies;    ///< n bodies and a static one
  ContactBatches contact_batches;           ///< contacts staged for SIMD
  ContactImpulseCache contact_cache;        ///< last step's impulses, for warm starting
  ShockPropagation shock;                   ///< levels and contact order of the shock pass
  StageCrew crew;                           ///< the solver passes' threads (jobs/stage_crew.h)
  BounceTiming bounce_timing;               ///< terrain bounces moved to their time of impact
  std::vector<float> rolling_impulses;      ///< per contact, its rolling resistance's angular impulse (3 floats)
  // Predict and sweep.
  std::vector<float> block_max_speed;
  std::vector<SphereExtremes> block_extremes;           ///< radii and inverse masses per block
  std::vector<std::vector<std::uint32_t>> fast_blocks;  ///< fast spheres per block
  std::vector<std::uint32_t> fast;                      ///< this step's fast spheres, slot order
  ContinuousCollision ccd;
  // Terrain guard (predict -> end of step): where each sphere started and how far (squared) its
  // terrain contacts reached.
  std::vector<float> start_x, start_y, start_z, reach2;
  /// Integrator::UniformAcceleration only: each sphere's velocity before predict (IntegrationParams::start_vx).
  std::vector<float> start_vx, start_vy, start_vz;
  std::vector<float> travel;            ///< per sphere |v| dt this step (pair margins)
  std::vector<std::uint32_t> moved_at;  ///< per sphere: last depenetration (pass, colour) that moved it
  // Morton re-sort.
  std::vector<std::uint64_t> reorder_keys;
  std::vector<std::uint32_t> reorder_slots;  ///< new slot k <- old slot
  std::vector<Aabb> reorder_bounds;          ///< box of each block's centres
};

}  // namespace hail
