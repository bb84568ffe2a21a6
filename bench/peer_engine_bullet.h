#pragma once
// Bullet (Debian's libbullet-dev) as a PeerEngine, set up to run exactly the PeerScene hail runs:
// btDiscreteDynamicsWorld with btDbvtBroadphase and btSequentialImpulseConstraintSolver (its
// usual defaults), one internal step per frame, one btSphereShape per distinct radius, the
// heightfield placed so that vertex (i, j) is where hail puts it, and contacts given the scene's
// effective restitution and friction. Built without Bullet (no HAIL_HAVE_BULLET), the factory
// returns nullptr and bullet_available() is false.

#include <memory>
#include <string>

#include "peer_engine.h"

class btDiscreteDynamicsWorld;

namespace hail::bench {

struct BulletOptions {
  /// Bullet's default: a body slower than 0.8 m/s and 1 rad/s for 2 s deactivates (islands
  /// sleep). false: every body DISABLE_DEACTIVATION, so all are stepped every frame as in hail.
  bool sleeping = true;
  /// btContactSolverInfo::m_numIterations; 10 is Bullet's default.
  int solver_iterations = 10;
};

/// True when hail-bench was built with Bullet.
[[nodiscard]] bool bullet_available();

/// "Bullet 3.24" (the headers' version), or "" without Bullet.
[[nodiscard]] std::string bullet_version();

/// Bullet stepping `scene` (single-threaded), or nullptr when built without Bullet. While any
/// Bullet engine exists, Bullet's global material-combining callbacks are hail's rules.
[[nodiscard]] std::unique_ptr<PeerEngine> make_bullet_engine(const PeerScene& scene, const BulletOptions& options = {});

/// The Bullet world inside an engine made by make_bullet_engine (for ray casts in tests), or
/// nullptr for any other engine.
[[nodiscard]] btDiscreteDynamicsWorld* bullet_world(PeerEngine& engine);

/// Moving bodies of `world` that Bullet has deactivated (ISLAND_SLEEPING); static ones are not counted.
[[nodiscard]] int bullet_sleeping_bodies(const btDiscreteDynamicsWorld& world);

/// Casts `samples` x `samples` vertical rays (btCollisionWorld::rayTest) at the terrain of a
/// Bullet engine, on a grid over the heightmap's extent shifted off the vertices, and returns
/// the largest |hit height - Heightmap::surface_height(x, z)| in m (infinity if a ray misses;
/// 0 without terrain). Other bodies are ignored. Shows the heightfield sits where hail's does.
[[nodiscard]] double bullet_terrain_ray_error(PeerEngine& engine, const Heightmap& heightmap, int samples);

}  // namespace hail::bench
