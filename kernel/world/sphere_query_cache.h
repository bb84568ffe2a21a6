#pragma once
// The world queries' BVH over the spheres, built lazily: every World call that changes what a
// query sees of the spheres (step, add/remove, set_position(s), set_radius,
// set_collision_filter, shift_origin) calls invalidate(); the first query after it rebuilds.
//
// Threads: World's const methods may run at the same time as each other, and a query is const,
// so two queries may both find the structure stale: get() builds it under a mutex, and the
// structure is only read after that until the next non-const World call (which by World's rule
// runs alone). invalidate() needs no lock for the same reason.

#include <cstdint>
#include <mutex>

#include "hail/sphere_soa.h"
#include "kernel/bvh/sphere_query_bvh.h"
#include "soa/heap_bytes.h"

namespace hail {

class SphereQueryCache {
 public:
  /// The spheres changed: the next get() rebuilds.
  void invalidate() { stale_ = true; }
  /// The structure over `spheres`, rebuilt first if anything changed since the last build.
  const SphereQueryBvh& get(const SphereSoA& spheres) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stale_) {
      bvh_.build(spheres);
      stale_ = false;
      ++builds_;
    }
    return bvh_;
  }
  [[nodiscard]] std::uint64_t builds() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return builds_;
  }

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(bvh_.bvh.nodes, bvh_.bvh.primitive_order, bvh_.x, bvh_.y, bvh_.z, bvh_.r, bvh_.category, bvh_.handle, bvh_.bounds);
  }

 private:
  mutable std::mutex mutex_;
  bool stale_ = true;
  std::uint64_t builds_ = 0;
  SphereQueryBvh bvh_;
};

}  // namespace hail
