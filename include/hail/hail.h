#pragma once
// The public API of hail in one include: `#include <hail/hail.h>`, with hail::hail linked
// (installed package, add_subdirectory or FetchContent; docs/embedding.md).
//
// What an embedder uses, and where it is documented:
//   hail::World          kernel/world.h      spheres, planes, terrain; step(); spans over the
//                                            sphere state; the contacts of the last step
//   hail::WorldSettings  kernel/world.h      every knob, with units and what too little/much does
//   hail::Terrain        kernel/terrain.h    a heightmap's triangles and BVH; raycast()
//   hail::Heightmap      kernel/heightmap.h  from a function h(x, z), samples, PGM, PNG, raw files
//   hail::Contact        kernel/contact.h    what World::last_contacts() holds
//   InvalidArgument, FileError  kernel/errors.h  what the API throws (never exit/abort)
//   HAIL_VERSION_*       hail/version.h
//
// The other headers installed beside these (BVH walks, pair searches, solver batches, SIMD
// dispatch, ...) are the kernel's internals, installed because the public headers need them.
// They may change in any minor version, and their SIMD code is meant to be compiled inside the
// library with hail's flags, not in your files. The API above needs no -march or other flag.
//
// Units are SI (m, s, kg, rad), y is up. Threads: hail runs World::step() inside a
// tbb::task_arena (yours, or one it makes) and never starts threads of its own.

#include "hail/version.h"
#include "kernel/contact.h"
#include "kernel/errors.h"
#include "kernel/heightmap.h"
#include "kernel/terrain.h"
#include "kernel/vec3.h"
#include "kernel/world.h"
