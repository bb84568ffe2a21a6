// hail-game: a small game loop driving hail through its game API, checking its own outcome.
//
//  - An arena of planes; 240 balls of two teams (red, blue) dropped into it, interleaved so that
//    every red ball shares space with blue ones: collision filters let the teams pass through
//    each other while each team piles up on itself.
//  - A kinematic paddle circling through the balls, moved each step to where the game wants it
//    (World::move_kinematic): it pushes balls and is never pushed.
//  - Once a second the player clicks on a red ball: a ray from the camera through it (World::raycast
//    with a filter: blue balls in front do not block it) picks it, and the game kicks it with an impulse at the picked point (World::apply_impulse_at).
//  - Hit events as sounds: every impact faster than 1 m/s, its loudness the approach speed;
//    touch events tell which balls the paddle touched.
//  - Rollback: the world is saved half-way (World::save); at the end a second World restored
//    from those bytes replays the second half with the same inputs and must reach bitwise the
//    same state (World::state_hash).
// Exit status 1 if a check fails.

#include <hail/hail.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <optional>
#include <vector>

namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr int kSteps = 360;      // 6 s
constexpr int kSaveAt = 180;     // the rollback point
constexpr float kArena = 6.0f;   // the arena's half width, m
constexpr float kRadius = 0.3f;  // ball radius, m
constexpr float kPaddleRadius = 0.9f;
constexpr float kKick = 2.0f;                 // impulse, N s (on 1 kg: 2 m/s)
constexpr std::uint64_t kRed = 1, kBlue = 2;  // user data: the team

// Box2D's rule: two spheres collide when each one's category is in the other's mask. The
// paddle and the ground keep the default filter, which meets both teams.
constexpr hail::CollisionFilter kRedTeam{0x2u, ~0x4u}, kBlueTeam{0x4u, ~0x2u};

hail::Vec3 paddle_target(int step) {  // where the game wants the paddle after `step` steps
  const float t = static_cast<float>(step) * kDt;
  return {3.5f * std::cos(1.5f * t), kPaddleRadius, 3.5f * std::sin(1.5f * t)};
}

struct Tally {
  std::size_t hits = 0, red_blue_events = 0, team_touches = 0, kicks = 0, blue_picks = 0;
  float loudest = 0.0f;              // m/s
  float paddle_error = 0.0f;         // m, largest distance from where the game put the paddle
  float kick_error = 0.0f;           // m/s, largest |dv - J / m| of a kick
  std::vector<bool> paddle_touched;  // by handle index
};

/// One frame of the game: the player's input, then the step, then what the game reads back.
void play_step(hail::World& world, hail::SphereId paddle, const std::vector<hail::SphereId>& balls, int step,
               Tally* tally) {
  world.move_kinematic(paddle, paddle_target(step + 1), kDt);
  if (step % 60 == 30) {  // the player clicks on a red ball: a ray from the camera through it picks it
    const hail::SphereId aimed = balls[static_cast<std::size_t>(step / 60) * 40];  // even indices are red
    const hail::Vec3 eye(0.0f, 9.0f, -11.0f);
    const hail::Ray ray{.origin = eye, .direction = world.position(aimed) - eye};
    const std::optional<hail::QueryHit> hit = world.raycast(ray, {.mask = kRedTeam.category, .planes = false});
    if (hit && hit->kind == hail::QueryHitKind::Sphere) {  // the aimed ball, or a red one in front of it
      const hail::Vec3 before = world.velocity(hit->sphere);
      const hail::Vec3 impulse = (ray.direction.normalized() + hail::Vec3(0, 1, 0)) * kKick;
      world.apply_impulse_at(hit->sphere, impulse, hit->point);
      if (tally) {
        ++tally->kicks;
        tally->kick_error = std::max(tally->kick_error, (world.velocity(hit->sphere) - before - impulse).norm());
        if (world.user_data(hit->sphere) != kRed) ++tally->blue_picks;  // the query's filter let a blue one through
      }
    }
  }
  world.step(kDt);
  if (!tally) return;
  tally->paddle_error = std::max(tally->paddle_error, (world.position(paddle) - paddle_target(step + 1)).norm());
  auto team = [&](hail::SphereId id) { return id == paddle ? 0 : world.user_data(id); };
  for (const hail::HitEvent& h : world.hit_events()) {  // a sound per hit, as loud as it was fast
    ++tally->hits;
    tally->loudest = std::max(tally->loudest, h.approach_speed);
    if (h.with == hail::ContactWith::Sphere && team(h.a) + team(h.b) == kRed + kBlue) ++tally->red_blue_events;
  }
  for (const hail::TouchEvent& t : world.touch_begin_events()) {
    if (t.with != hail::ContactWith::Sphere) continue;
    if (team(t.a) + team(t.b) == kRed + kBlue) ++tally->red_blue_events;
    if (team(t.a) == team(t.b)) ++tally->team_touches;
    if (t.a == paddle) tally->paddle_touched[t.b.index] = true;
    if (t.b == paddle) tally->paddle_touched[t.a.index] = true;
  }
}

int run() {
  std::printf("hail %s game example\n", HAIL_VERSION_STRING);
  const hail::WorldSettings settings{.gravity = {0.0f, -9.81f, 0.0f}, .threads = 2};
  hail::World world(settings);
  world.add_plane({.normal = {0, 1, 0}, .offset = 0.0f, .restitution = 0.4f});
  for (const float sign : {-1.0f, 1.0f}) {  // walls: the solid side is outside the arena
    world.add_plane({.normal = {sign, 0, 0}, .offset = -kArena});
    world.add_plane({.normal = {0, 0, sign}, .offset = -kArena});
  }
  std::vector<hail::SphereId> balls;
  for (int k = 0; k < 240; ++k) {
    const bool red = k % 2 == 0;
    const int cell = k / 2;  // a red and a blue ball share each cell, 0.2 m apart
    const float x = -4.5f + 1.0f * static_cast<float>(cell % 10), z = -4.5f + 1.0f * static_cast<float>(cell / 10 % 10);
    const float y = 1.0f + 1.2f * static_cast<float>(cell / 100) + (red ? 0.0f : 0.2f);
    const hail::SphereId id = world.add_sphere({.position = {x, y + 0.5f * static_cast<float>(cell % 3), z},
                                                .radius = kRadius,
                                                .mass = 1.0f,
                                                .restitution = 0.4f,
                                                .friction = 0.5f,
                                                .filter = red ? kRedTeam : kBlueTeam});
    world.set_user_data(id, red ? kRed : kBlue);
    balls.push_back(id);
  }
  const hail::SphereId paddle = world.add_sphere(
      {.position = paddle_target(0), .radius = kPaddleRadius, .restitution = 0.6f, .is_kinematic = true});
  world.set_events({.touch = true, .hits = true, .hit_speed = 1.0f});

  Tally tally;
  tally.paddle_touched.assign(balls.size() + 1, false);
  std::vector<std::byte> saved;
  for (int step = 0; step < kSteps; ++step) {
    if (step == kSaveAt) world.save(saved);
    play_step(world, paddle, balls, step, &tally);
  }

  // Rollback: a fresh World restored from the half-way bytes, the same inputs again.
  hail::World replay(settings);
  replay.restore(saved);
  for (int step = kSaveAt; step < kSteps; ++step) play_step(replay, paddle, balls, step, nullptr);

  float deepest = 0.0f;  // into the floor
  for (const hail::SphereId id : balls) deepest = std::max(deepest, kRadius - world.position(id).y());
  const auto touched_by_paddle = std::count(tally.paddle_touched.begin(), tally.paddle_touched.end(), true);
  std::printf("paddle: touched %td balls, off its path by at most %.2e m\n", touched_by_paddle, tally.paddle_error);
  std::printf("kicks: %zu red balls picked by ray and kicked, velocity off J/m by at most %.2e m/s\n", tally.kicks,
              tally.kick_error);
  std::printf("sounds: %zu hits, loudest %.2f m/s; %zu same-team touches, %zu red-blue events\n", tally.hits,
              tally.loudest, tally.team_touches, tally.red_blue_events);
  std::printf("floor: deepest ball %.4f m in; NaN %zu; state hash %016llx, replayed from step %d: %016llx\n", deepest,
              world.nan_count(), static_cast<unsigned long long>(world.state_hash()), kSaveAt,
              static_cast<unsigned long long>(replay.state_hash()));

  bool ok = true;
  auto require = [&](bool condition, const char* what) {
    if (!condition) std::printf("FAILED: %s\n", what);
    ok = ok && condition;
  };
  require(world.nan_count() == 0, "no NaN in the state");
  require(tally.paddle_error < 1e-4f, "the kinematic paddle is where the game put it");
  require(touched_by_paddle >= 10, "the paddle touched at least 10 balls");
  require(tally.kicks == kSteps / 60 && tally.blue_picks == 0, "every kick's ray picked a red ball");
  require(tally.kick_error < 1e-5f, "a kick changed the ball's velocity by J / m");
  require(tally.red_blue_events == 0, "red and blue balls never touched or hit each other");
  require(tally.team_touches > 100, "balls of one team touched each other");
  require(tally.hits > 0 && tally.loudest > 3.0f, "landings made sounds");
  require(deepest < 0.05f * kRadius, "no ball sank into the floor by 5% of its radius");
  require(replay.state_hash() == world.state_hash(), "the replay from the snapshot reached the same state");
  std::printf(ok ? "ok\n" : "FAILED\n");
  return ok ? 0 : 1;
}

}  // namespace

int main() {
  try {
    return run();
  } catch (const std::exception& e) {  // hail::InvalidArgument, hail::FileError: the message names the value
    std::fprintf(stderr, "hail-game: %s\n", e.what());
    return 1;
  }
}
