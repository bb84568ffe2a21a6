#include "rays_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>

#include "cli.h"
#include "hail/world.h"
#include "kernel/geometry/ray_sphere.h"
#include "kernel/world/ray_batch_leaf_test.h"
#include "parse_numbers.h"
#include "scenes/machine_info.h"

namespace hail::bench {
namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::vector<long long> parse_sizes(const std::string& text) {
  std::vector<long long> sizes = parse_count_list("--sizes entry", text, 1, 10'000'000);
  if (sizes.empty()) throw std::invalid_argument("--sizes: no sphere count given");
  return sizes;
}

/// n spheres of radius 0.25..0.75 at random in a cube sized for one sphere per 8 m^3 (so a
/// ray passes a few dozen before it hits one, at any n), on a ground plane under the cube.
float fill_world(World& world, long long n, unsigned seed) {
  const float side = std::cbrt(8.0f * static_cast<float>(n));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(0.0f, side), r(0.25f, 0.75f);
  world.reserve(static_cast<std::size_t>(n));
  world.add_plane({.normal = {0, 1, 0}, .offset = -1.0f});
  for (long long k = 0; k < n; ++k) {
    SphereDesc d;
    d.position = {at(rng), at(rng), at(rng)};
    d.radius = r(rng);
    d.is_static = true;
    world.add_sphere(d);
  }
  return side;
}

std::vector<Ray> make_rays(int count, float side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(0.0f, side), u(-1.0f, 1.0f);
  std::vector<Ray> rays(static_cast<std::size_t>(count));
  for (Ray& ray : rays) {
    ray.origin = {at(rng), at(rng), at(rng)};
    ray.direction = {u(rng), u(rng), u(rng)};
    if (ray.direction.squaredNorm() == 0.0f) ray.direction = {0, -1, 0};
  }
  return rays;
}

/// The brute force: every sphere and plane, World::raycast's formulas and its tie rule.
std::optional<QueryHit> brute_raycast(const World& w, const Ray& ray) {
  const Vec3& v = ray.direction;
  const float length = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
  const float o[3] = {ray.origin.x(), ray.origin.y(), ray.origin.z()};
  const float d[3] = {v.x() / length, v.y() / length, v.z() / length};
  std::optional<QueryHit> best;
  const SphereSoA& s = w.soa();
  for (std::size_t i = 0; i < w.sphere_count(); ++i) {
    const float t = ray_sphere(o, d, s.px[i], s.py[i], s.pz[i], s.radius[i]);
    if (!(t >= 0.0f && t < ray.max_distance)) continue;
    QueryHit hit;
    hit.sphere = w.id_at(i), hit.distance = t;
    if (!best || hit_before(hit, *best)) best = hit;
  }
  for (std::uint32_t k = 0; k < w.planes().size(); ++k) {
    const Plane& p = w.planes()[k];
    const float gap = p.nx * o[0] + p.ny * o[1] + p.nz * o[2] - p.offset;
    const float closing = -(p.nx * d[0] + p.ny * d[1] + p.nz * d[2]);
    const float t = gap <= 0.0f ? 0.0f : (closing > 0.0f ? gap / closing : -1.0f);
    if (!(t >= 0.0f && t < ray.max_distance)) continue;
    QueryHit hit;
    hit.kind = QueryHitKind::Plane, hit.index = k, hit.distance = t;
    if (!best || hit_before(hit, *best)) best = hit;
  }
  return best;
}

bool same(const std::optional<QueryHit>& a, const std::optional<QueryHit>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (a->kind == b->kind && a->sphere == b->sphere && a->index == b->index &&
                std::memcmp(&a->distance, &b->distance, sizeof(float)) == 0);
}

}  // namespace

int rays_command(const RaysOptions& o) {
  const std::vector<long long> sizes = parse_sizes(o.sizes);
  std::printf("# hail-bench rays: %d rays, %d threads, median of %d; %s, simd %s\n", o.rays, o.threads, o.repeats,
              cpu_model().c_str(), simd_path().c_str());
  std::printf(
      "# build: the query BVH over the spheres (first query after a change); batch: raycast_batch, leaves\n"
      "# tested in SIMD lanes; scalar: raycast_batch with the scalar leaf test; simd_gain: batch / scalar;\n"
      "# brute: every sphere and plane per ray, one thread; speedup: batch / brute;\n"
      "# mismatches: rays whose hit differs from the batch's (scalar: of all rays; brute: of brute rays)\n");
  std::printf("%10s %10s %14s %14s %10s %14s %11s %10s %11s\n", "spheres", "build_ms", "batch_rays/s", "scalar_rays/s",
              "simd_gain", "brute_rays/s", "brute_rays", "speedup", "mismatches");
  int status = 0;
  for (const long long n : sizes) {
    WorldSettings settings;
    settings.threads = o.threads;
    World world(settings);
    const float side = fill_world(world, n, 1);
    const std::vector<Ray> rays = make_rays(o.rays, side, 2);
    std::vector<std::optional<QueryHit>> hits(rays.size()), scalar_hits(rays.size());
    std::vector<double> build, batch, scalar;
    for (int r = 0; r < o.repeats; ++r) {
      world.set_position(world.id_at(0), world.position(world.id_at(0)));  // a change: the next query rebuilds
      auto t0 = clock_type::now();
      (void)world.overlap_sphere({0, 0, 0}, 0.0f);  // builds the BVH (the query itself is tiny)
      build.push_back(seconds_since(t0));
      t0 = clock_type::now();
      world.raycast_batch(rays, hits);
      batch.push_back(seconds_since(t0));
      set_ray_batch_leaf_test(RayBatchLeafTest::Scalar);
      t0 = clock_type::now();
      world.raycast_batch(rays, scalar_hits);
      scalar.push_back(seconds_since(t0));
      set_ray_batch_leaf_test(RayBatchLeafTest::Simd);
    }
    std::size_t mismatches = 0;
    for (std::size_t k = 0; k < rays.size(); ++k) mismatches += !same(scalar_hits[k], hits[k]);
    const std::size_t brute_rays =
        std::min<std::size_t>(rays.size(), std::max<std::size_t>(64, static_cast<std::size_t>(o.brute_budget / n)));
    std::vector<double> brute;
    std::size_t brute_mismatches = 0;
    for (int r = 0; r < o.repeats; ++r) {
      brute_mismatches = 0;
      const auto t0 = clock_type::now();
      for (std::size_t k = 0; k < brute_rays; ++k) brute_mismatches += !same(brute_raycast(world, rays[k]), hits[k]);
      brute.push_back(seconds_since(t0));
    }
    mismatches += brute_mismatches;
    const double batch_rate = rays.size() / median(batch), scalar_rate = rays.size() / median(scalar);
    const double brute_rate = brute_rays / median(brute);
    std::printf("%10lld %10.2f %14.4g %14.4g %9.2fx %14.4g %11zu %9.1fx %11zu\n", n, 1e3 * median(build), batch_rate,
                scalar_rate, batch_rate / scalar_rate, brute_rate, brute_rays, batch_rate / brute_rate, mismatches);
    std::fflush(stdout);
    if (mismatches) status = 1;
  }
  return status;
}

// The flags of `hail-bench rays` (bench/cli.h's rules).

void add_rays_options(CLI::App& app, RaysOptions& o) {
  app.description("World::raycast_batch throughput (rays/s) against a brute-force loop, by sphere count");
  app.add_option("--sizes", o.sizes, "sphere counts, comma-separated (e.g. 1000,16000,64000,256000,1000000)");
  add_count(app, "--rays", o.rays, 1, 100'000'000, "rays per batch");
  add_count(app, "--threads", o.threads, 1, 1024, "threads of the World's arena");
  add_count(app, "--repeats", o.repeats, 1, 1000, "timed repeats; the median is reported");
  add_count(app, "--brute-budget", o.brute_budget, 1, 1'000'000'000'000LL,
            "ray-sphere tests the brute force may make per repeat (its rays are cut to fit, at least 64)");
}

int rays_command(const std::vector<std::string>& args) {
  const std::optional<RaysOptions> parsed = parse_command("rays", add_rays_options, args);
  return parsed ? rays_command(*parsed) : 0;  // 0 after --help
}

}  // namespace hail::bench
