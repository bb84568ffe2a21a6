#include "view/live_simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "scenes/metrics.h"
#include "view/islands.h"

namespace hail::view {

void capture_frame(const World& world, double step_ms, std::uint64_t step, Frame& out, const Capture& capture) {
  const SphereState s = world.spheres();
  const std::size_t n = world.sphere_count();
  out.step = step;
  out.centre.resize(3 * n);
  out.radius.resize(n);
  out.speed.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.centre[3 * k] = s.px[k], out.centre[3 * k + 1] = s.py[k], out.centre[3 * k + 2] = s.pz[k];
    out.radius[k] = s.radius[k];
    out.speed[k] = std::sqrt(s.vx[k] * s.vx[k] + s.vy[k] * s.vy[k] + s.vz[k] * s.vz[k]);
  }
  out.sleeping.resize(n);
  const std::span<const std::uint32_t> flags = world.soa().flags.span();
  for (std::size_t k = 0; k < n; ++k) out.sleeping[k] = (flags[k] & kSphereFlagSleeping) != 0 ? 1 : 0;
  if (capture.islands)
    island_labels(world, out.island);
  else
    out.island.clear();
  out.contacts.clear();
  if (capture.contacts)
    for (const Contact& c : world.last_contacts()) {
      if (c.a >= n) continue;
      const float r = s.radius[c.a];
      out.contacts.insert(out.contacts.end(),
                          {s.px[c.a] + r * c.nx, s.py[c.a] + r * c.ny, s.pz[c.a] + r * c.nz, c.nx, c.ny, c.nz, r});
    }
  if (capture.grid)
    world.pair_grid_cells(out.grid_cells);
  else
    out.grid_cells.clear();
  out.phase_ms = world.last_phase_times();
  out.step_ms = step_ms;
  out.kinetic_energy = world.kinetic_energy();
}

LiveSimulation::LiveSimulation(SceneFactory factory, const SceneChoice& choice, bool paused)
    : factory_(std::move(factory)), choice_(choice), paused_(paused) {
  scene_ = factory_(choice_);
  geometry_ = StaticGeometry::of(*scene_.world);
  dt_ = scene_.dt;
  thread_count_ = scene_.world->thread_count();
  capture_frame(*scene_.world, 0.0, 0, published_);
  version_ = 1;
  thread_ = std::thread([this] { run(); });
}

LiveSimulation::~LiveSimulation() {
  stop_ = true;
  wake_.notify_all();
  thread_.join();
}

bool LiveSimulation::latest(Frame& out) {
  std::lock_guard lock(mutex_);
  if (version_ == seen_version_) return false;
  seen_version_ = version_;
  out = published_;
  return true;
}

void LiveSimulation::set_paused(bool paused) {
  paused_ = paused;
  wake_.notify_all();
}

void LiveSimulation::step_once() {
  std::lock_guard lock(mutex_);
  ++single_steps_;
  wake_.notify_all();
}

void LiveSimulation::reset() {
  std::lock_guard lock(mutex_);
  reset_requested_ = true;
  wake_.notify_all();
}

void LiveSimulation::choose_for_reset(std::size_t spheres, PairSearch pair_search, bool sleep) {
  std::lock_guard lock(mutex_);
  SceneChoice next = choice_requested_.value_or(SceneChoice{});
  next.spheres = spheres, next.pair_search = pair_search, next.sleep = sleep;
  choice_requested_ = next;
}

void LiveSimulation::set_threads(int threads) {
  std::lock_guard lock(mutex_);
  threads_requested_ = threads;
  wake_.notify_all();
}

void LiveSimulation::set_capture(const Capture& capture) {
  std::lock_guard lock(mutex_);
  if (capture == capture_) return;
  capture_ = capture, capture_requested_ = true;
  wake_.notify_all();
}

void LiveSimulation::set_material(float restitution, float friction) {
  std::lock_guard lock(mutex_);
  restitution_ = restitution, friction_ = friction, material_requested_ = true;
  wake_.notify_all();
}

namespace {

/// The radius new spheres get: the scene's first sphere's, or 0.5 m.
float typical_radius(const World& world) { return world.sphere_count() > 0 ? world.spheres().radius[0] : 0.5f; }

}  // namespace

void LiveSimulation::spawn_at(const Vec3& origin, const Vec3& direction) {
  std::lock_guard lock(mutex_);
  edits_.push_back([origin, direction](World& world) {
    const std::optional<QueryHit> hit = world.raycast({.origin = origin, .direction = direction});
    if (!hit) return;
    const float r = typical_radius(world);
    const Vec3 base = hit->point + hit->normal * (4.0f * r);
    for (int k = 0; k < 27; ++k) {
      const Vec3 offset(float(k % 3 - 1), float(k / 9), float((k / 3) % 3 - 1));
      world.add_sphere({.position = base + 2.2f * r * offset, .radius = r});
    }
  });
  wake_.notify_all();
}

void LiveSimulation::fire(const Vec3& origin, const Vec3& direction, float speed) {
  std::lock_guard lock(mutex_);
  edits_.push_back([origin, direction, speed](World& world) {
    world.add_sphere({.position = origin, .velocity = direction.normalized() * speed, .radius = typical_radius(world)});
  });
  wake_.notify_all();
}

void LiveSimulation::apply_requests() {
  bool reset = false, material = false, recapture = false;
  Capture capture;
  int threads = -1;
  float restitution = 0, friction = 0;
  std::vector<std::function<void(World&)>> edits;
  {
    std::lock_guard lock(mutex_);
    std::swap(edits, edits_);
    std::swap(reset, reset_requested_);
    std::swap(threads, threads_requested_);
    std::swap(material, material_requested_);
    std::swap(recapture, capture_requested_);
    capture = capture_;
    restitution = restitution_, friction = friction_;
  }
  if (reset) {
    {
      std::lock_guard lock(mutex_);
      if (choice_requested_)
        choice_.spheres = choice_requested_->spheres, choice_.pair_search = choice_requested_->pair_search,
        choice_.sleep = choice_requested_->sleep;
      choice_requested_.reset();
    }
    scene_ = factory_(choice_);
    steps_ = 0;
  }
  if (threads >= 0) {
    // A snapshot keeps everything that decides the future, and the result does not depend on
    // the thread count: the run goes on as it would have.
    std::vector<std::byte> saved;
    scene_.world->save(saved);
    choice_.threads = threads;
    bench::Scene rebuilt = factory_(choice_);
    rebuilt.world->restore(saved);
    scene_ = std::move(rebuilt);
    thread_count_ = scene_.world->thread_count();
  }
  if (material) {
    for (const SphereId id : scene_.world->handles()) {
      scene_.world->set_restitution(id, restitution);
      scene_.world->set_friction(id, friction);
    }
  }
  for (const auto& edit : edits) {
    try {
      edit(*scene_.world);
    } catch (const InvalidArgument&) {
      // A sphere that would overlap the limits (too far out for its radius, say) is not added.
    }
  }
  if (reset || threads >= 0 || material || !edits.empty() || recapture) {
    Frame frame;
    capture_frame(*scene_.world, 0.0, steps_, frame, capture);
    std::lock_guard lock(mutex_);
    published_ = std::move(frame);
    ++version_;
  }
}

void LiveSimulation::run() {
  using clock = std::chrono::steady_clock;
  Frame frame;
  auto next = clock::now();
  while (!stop_) {
    apply_requests();
    {
      std::unique_lock lock(mutex_);
      if (paused_ && single_steps_ == 0) {
        wake_.wait_for(lock, std::chrono::milliseconds(50));
        next = clock::now();
        continue;
      }
      if (single_steps_ > 0) --single_steps_;
    }
    const auto start = clock::now();
    scene_.world->step(dt_);
    const double ms = std::chrono::duration<double, std::milli>(clock::now() - start).count();
    ++steps_;
    Capture capture;
    {
      std::lock_guard lock(mutex_);
      capture = capture_;
    }
    capture_frame(*scene_.world, ms, steps_, frame, capture);
    if (frame.size() <= kErrorFiguresUpTo) {
      const bench::ErrorFigures errors = bench::measure_errors(scene_);
      frame.deepest_overlap = std::max(errors.max_sphere_penetration, errors.max_terrain_penetration);
      frame.tunnelled = errors.tunnelled;
    }
    {
      std::lock_guard lock(mutex_);
      std::swap(published_, frame);
      ++version_;
    }
    // Pace to speed_ x real time; a step slower than that just runs late (never skipped).
    const float speed = std::max(speed_.load(), 1e-3f);
    next += std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(dt_ / speed));
    const auto now = clock::now();
    if (next > now) {
      std::unique_lock lock(mutex_);
      wake_.wait_until(lock, next, [this] { return stop_.load() || reset_requested_ || threads_requested_ >= 0; });
    } else {
      next = now;
    }
  }
}

}  // namespace hail::view
