#pragma once
// A Terrain with the kernel's view of its parts: the public class (include/hail/terrain.h)
// declares its triangles, BVH and triangle boxes only; code that walks them includes this.

#include "hail/terrain.h"
#include "kernel/bvh/flat_bvh.h"
#include "kernel/geometry/aabb.h"
#include "kernel/terrain/terrain_triangles.h"
