#include "kernel/bvh/sphere_query_bvh.h"

namespace hail {

void SphereQueryBvh::build(const SphereSoA& spheres) {
  const std::size_t n = spheres.size();
  bounds.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float rr = spheres.radius[i];
    bounds[i] = {{spheres.px[i] - rr, spheres.py[i] - rr, spheres.pz[i] - rr},
                 {spheres.px[i] + rr, spheres.py[i] + rr, spheres.pz[i] + rr}};
  }
  bvh.build(bounds, {.split = BvhSplit::Median, .leaf_size = kLeafSize});
  x.resize(n), y.resize(n), z.resize(n), r.resize(n), category.resize(n), handle.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = bvh.primitive_order[k];
    x[k] = spheres.px[i], y[k] = spheres.py[i], z[k] = spheres.pz[i], r[k] = spheres.radius[i];
    category[k] = spheres.collision_category[i];
    handle[k] = spheres.id_at(i);
  }
}

}  // namespace hail
