#pragma once
// The public API of hail in one include: `#include <hail/hail.h>`, with hail::hail linked
// (installed package, add_subdirectory or FetchContent; docs/embedding.md). Each header below
// may also be included on its own.
//
//   <hail/world.h>           hail::World: spheres, planes, terrain; step(); spans over the sphere
//                            state; the contacts and impacts of the last step; SphereDesc, PlaneDesc
//   <hail/world_settings.h>  hail::WorldSettings: every knob, with units and what too little/much does
//   <hail/settings_table.h>  for_each_setting: every setting's name, range and doc line, in one list
//   <hail/step_stats.h>      StepStats, StepParts, PhaseTimes: what the last step did
//   <hail/terrain.h>         hail::Terrain: a heightmap's triangles and BVH; raycast()
//   <hail/heightmap.h>       hail::Heightmap: from a function h(x, z), samples, PGM, PNG, raw files
//   <hail/collision_filter.h> hail::CollisionFilter: category and mask bits, should_collide()
//   <hail/events.h>          TouchEvent, HitEvent, EventSettings: World::set_events, touch_*_events(), hit_events()
//   <hail/queries.h>         Ray, QueryHit, QueryFilter: World::raycast, sphere_cast, overlap_sphere/box
//   <hail/snapshot.h>        terrain_content_hash: what World::save/restore check the terrain by
//   <hail/recording.h>       RecordingWriter, RecordingReader: positions every K steps, to replay
//   <hail/contact.h>         hail::Contact, hail::Impact: what last_contacts()/last_impacts() hold
//   <hail/sphere_soa.h>      hail::SphereSoA, SphereId: the sphere arrays World::soa() shows
//   <hail/plane.h>           hail::Plane: a static plane as World::planes() shows it
//   <hail/phase_trace.h>     hail::PhaseTrace: the per-thread phase trace (World::enable_trace)
//   <hail/errors.h>          InvalidArgument, FileError: what the API throws (never exit/abort)
//   <hail/vec3.h>            hail::Vec3 (Eigen::Vector3f)
//   <hail/version.h>         HAIL_VERSION_*
//
// These are the only headers installed: the kernel's internals (BVH, pair searches, solver,
// SIMD kernels) stay inside the library, compiled with hail's flags. The API needs no -march or
// other flag of yours.
//
// Units are SI (m, s, kg, rad), y is up. Threads: hail runs World::step() inside a
// tbb::task_arena (yours, or one it makes) and never starts threads of its own.

#include "hail/collision_filter.h"
#include "hail/contact.h"
#include "hail/errors.h"
#include "hail/events.h"
#include "hail/heightmap.h"
#include "hail/phase_trace.h"
#include "hail/plane.h"
#include "hail/queries.h"
#include "hail/recording.h"
#include "hail/settings_table.h"
#include "hail/snapshot.h"
#include "hail/sphere_soa.h"
#include "hail/step_stats.h"
#include "hail/terrain.h"
#include "hail/triangle_mesh.h"
#include "hail/vec3.h"
#include "hail/version.h"
#include "hail/world.h"
#include "hail/world_settings.h"
