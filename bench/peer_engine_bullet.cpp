#include "peer_engine_bullet.h"

#include <cmath>
#include <limits>
#include <string>

#if HAIL_HAVE_BULLET

#include <btBulletDynamicsCommon.h>

#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <algorithm>
#include <map>
#include <vector>

namespace hail::bench {
namespace {

// Materials. The scenes give *effective* contact values; hail combines restitution by the
// minimum and friction by the geometric mean (kernel/broadphase/sphere_pairs.h), Bullet by default by the
// product of both. Per-body values whose product is the effective value (sqrt(e) on each body)
// only work where every body has the same material, so instead Bullet's global combining
// callbacks are set to hail's rules while any Bullet engine exists, and every body gets the
// scene's own values: then any mix of materials gives both engines the same effective values.
// Bullet keeps these callbacks in globals; the count below restores Bullet's own when the last
// engine goes (engines are made and destroyed on one thread).
btScalar min_restitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::min(a->getRestitution(), b->getRestitution());
}
btScalar geometric_mean_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}

int g_engines = 0;
CalculateCombinedCallback g_saved_restitution = nullptr, g_saved_friction = nullptr;

void acquire_combine_rules() {
  if (g_engines++ > 0) return;
  g_saved_restitution = gCalculateCombinedRestitutionCallback;
  g_saved_friction = gCalculateCombinedFrictionCallback;
  gCalculateCombinedRestitutionCallback = &min_restitution;
  gCalculateCombinedFrictionCallback = &geometric_mean_friction;
}

void release_combine_rules() {
  if (--g_engines > 0) return;
  gCalculateCombinedRestitutionCallback = g_saved_restitution;
  gCalculateCombinedFrictionCallback = g_saved_friction;
}

/// Holds hail's combining rules for as long as it lives.
struct CombineRules {
  CombineRules() { acquire_combine_rules(); }
  ~CombineRules() { release_combine_rules(); }
  CombineRules(const CombineRules&) = delete;
  CombineRules& operator=(const CombineRules&) = delete;
};

btVector3 to_bt(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 from_bt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

class BulletEngine final : public PeerEngine {
 public:
  BulletEngine(const PeerScene& scene, const BulletOptions& options) : options_(options) {
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    world_ =
        std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
    world_->setGravity(to_bt(scene.gravity));
    world_->getSolverInfo().m_numIterations = options.solver_iterations;
    if (scene.heightmap) add_terrain(scene);
    for (const PeerPlane& p : scene.planes) {
      shapes_.push_back(std::make_unique<btStaticPlaneShape>(to_bt(p.normal), p.offset));
      add_static(shapes_.back().get(), btTransform::getIdentity(), p.restitution, p.friction);
    }
    spheres_.reserve(scene.spheres.size());
    std::map<float, btSphereShape*> shape_of_radius;  // one shape per distinct radius, shared
    for (const PeerSphere& s : scene.spheres) {
      btSphereShape*& shape = shape_of_radius[s.radius];
      if (!shape) {
        shapes_.push_back(std::make_unique<btSphereShape>(s.radius));
        shape = static_cast<btSphereShape*>(shapes_.back().get());
      }
      btVector3 inertia(0, 0, 0);
      if (s.mass > 0.0f) shape->calculateLocalInertia(s.mass, inertia);  // solid sphere, 2/5 m r^2
      btRigidBody::btRigidBodyConstructionInfo info(s.mass, nullptr, shape, inertia);
      info.m_startWorldTransform.setIdentity();
      info.m_startWorldTransform.setOrigin(to_bt(s.position));
      info.m_restitution = s.restitution;
      info.m_friction = s.friction;
      info.m_rollingFriction = 0;
      info.m_spinningFriction = 0;
      bodies_.push_back(std::make_unique<btRigidBody>(info));
      btRigidBody* body = bodies_.back().get();
      body->setLinearVelocity(to_bt(s.velocity));
      body->setAngularVelocity(to_bt(s.angular_velocity));
      if (!options.sleeping) body->setActivationState(DISABLE_DEACTIVATION);
      world_->addRigidBody(body);
      spheres_.push_back(body);
    }
  }

  ~BulletEngine() override {
    for (const auto& body : bodies_) world_->removeRigidBody(body.get());
    bodies_.clear();
    world_.reset();
  }

  BulletEngine(const BulletEngine&) = delete;
  BulletEngine& operator=(const BulletEngine&) = delete;

  [[nodiscard]] std::string name() const override { return options_.sleeping ? "Bullet" : "Bullet, no sleep"; }

  // maxSubSteps = 0: one internal step of exactly dt, no fixed-step accumulator (which could
  // take 0 or 2 steps in a frame) and no motion-state interpolation.
  void step(float dt) override { world_->stepSimulation(dt, 0); }

  void read_state(std::vector<PeerState>& out) const override {
    out.resize(spheres_.size());
    for (std::size_t k = 0; k < spheres_.size(); ++k) {
      const btRigidBody* b = spheres_[k];
      out[k] = {from_bt(b->getWorldTransform().getOrigin()), from_bt(b->getLinearVelocity()),
                from_bt(b->getAngularVelocity())};
    }
  }

  [[nodiscard]] btDiscreteDynamicsWorld* world() { return world_.get(); }
  [[nodiscard]] const btCollisionObject* terrain() const { return terrain_; }

 private:
  // btHeightfieldTerrainShape reads the heights in place (row-major, j * cols + i, as
  // Heightmap) and puts vertex (i, j) at local ((i - (cols-1)/2) sx, h - (min+max)/2,
  // (j - (rows-1)/2) sz) with the local scaling (sx, 1, sz): it centres itself on its AABB. The
  // body is moved by that centre, so vertex (i, j) lands at (x_of(i), h(i, j), z_of(j)) as in
  // hail. flipQuadEdges = false splits cell (i, j) along (i+1, j)-(i, j+1), as hail does.
  void add_terrain(const PeerScene& scene) {
    heightmap_ = scene.heightmap;
    const Heightmap& map = *heightmap_;
    const HeightmapParams& params = map.params();
    const float low = map.min_height(), high = map.max_height();
    auto shape = std::make_unique<btHeightfieldTerrainShape>(int(map.cols()), int(map.rows()), map.heights().data(),
                                                             low, high, /*upAxis=*/1, /*flipQuadEdges=*/false);
    shape->setLocalScaling(btVector3(params.cell_x, 1.0f, params.cell_z));
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(params.origin_x + 0.5f * float(map.cols() - 1) * params.cell_x, 0.5f * (low + high),
                           params.origin_z + 0.5f * float(map.rows() - 1) * params.cell_z));
    shapes_.push_back(std::move(shape));
    terrain_ = add_static(shapes_.back().get(), at, scene.terrain_restitution, scene.terrain_friction);
  }

  btRigidBody* add_static(btCollisionShape* shape, const btTransform& at, float restitution, float friction) {
    btRigidBody::btRigidBodyConstructionInfo info(0.0f, nullptr, shape);
    info.m_startWorldTransform = at;
    info.m_restitution = restitution;
    info.m_friction = friction;
    info.m_rollingFriction = 0;
    info.m_spinningFriction = 0;
    bodies_.push_back(std::make_unique<btRigidBody>(info));
    world_->addRigidBody(bodies_.back().get());
    return bodies_.back().get();
  }

  CombineRules rules_;  // first member: set before any contact, restored after everything else
  BulletOptions options_;
  std::shared_ptr<const Heightmap> heightmap_;  // the heightfield shape points into its heights
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;  // every body (static ones too), owned
  std::vector<btRigidBody*> spheres_;                 // the scene's spheres, in scene order
  const btCollisionObject* terrain_ = nullptr;
};

/// Closest hit on one collision object only.
struct HitOnly final : btCollisionWorld::ClosestRayResultCallback {
  HitOnly(const btVector3& from, const btVector3& to, const btCollisionObject* only)
      : ClosestRayResultCallback(from, to), only_(only) {}
  bool needsCollision(btBroadphaseProxy* proxy) const override { return proxy->m_clientObject == only_; }
  const btCollisionObject* only_;
};

}  // namespace

bool bullet_available() { return true; }

std::string bullet_version() {
  const int v = btGetVersion();
  return "Bullet " + std::to_string(v / 100) + "." + std::to_string(v % 100);
}

std::unique_ptr<PeerEngine> make_bullet_engine(const PeerScene& scene, const BulletOptions& options) {
  return std::make_unique<BulletEngine>(scene, options);
}

btDiscreteDynamicsWorld* bullet_world(PeerEngine& engine) {
  auto* bullet = dynamic_cast<BulletEngine*>(&engine);
  return bullet ? bullet->world() : nullptr;
}

int bullet_sleeping_bodies(const btDiscreteDynamicsWorld& world) {
  int count = 0;
  for (int k = 0; k < world.getNumCollisionObjects(); ++k) {
    const btCollisionObject* o = world.getCollisionObjectArray()[k];
    count += !o->isStaticObject() && o->getActivationState() == ISLAND_SLEEPING ? 1 : 0;
  }
  return count;
}

double bullet_terrain_ray_error(PeerEngine& engine, const Heightmap& map, int samples) {
  auto* bullet = dynamic_cast<BulletEngine*>(&engine);
  if (!bullet || !bullet->terrain()) return 0.0;
  const HeightmapExtent e = map.extent();
  const float top = map.max_height() + 10.0f, bottom = map.min_height() - 10.0f;
  double worst = 0.0;
  for (int a = 0; a < samples; ++a)
    for (int b = 0; b < samples; ++b) {
      // Offsets 0.37 and 0.61 of a sample step keep the rays off vertices and cell diagonals.
      const float x = e.min_x + (e.max_x - e.min_x) * (float(a) + 0.37f) / float(samples);
      const float z = e.min_z + (e.max_z - e.min_z) * (float(b) + 0.61f) / float(samples);
      HitOnly hit(btVector3(x, top, z), btVector3(x, bottom, z), bullet->terrain());
      bullet->world()->rayTest(hit.m_rayFromWorld, hit.m_rayToWorld, hit);
      if (!hit.hasHit()) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, std::abs(double(hit.m_hitPointWorld.y()) - map.surface_height(x, z)));
    }
  return worst;
}

}  // namespace hail::bench

#else  // built without Bullet

namespace hail::bench {

bool bullet_available() { return false; }
std::string bullet_version() { return ""; }
std::unique_ptr<PeerEngine> make_bullet_engine(const PeerScene&, const BulletOptions&) { return nullptr; }
btDiscreteDynamicsWorld* bullet_world(PeerEngine&) { return nullptr; }
int bullet_sleeping_bodies(const btDiscreteDynamicsWorld&) { return 0; }
double bullet_terrain_ray_error(PeerEngine&, const Heightmap&, int) { return 0.0; }

}  // namespace hail::bench

#endif
