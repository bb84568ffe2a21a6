#pragma once
// A fixture for the layer check, never compiled: a public header that includes an internal one.
#include "kernel/geometry/aabb.h"
