#pragma once
// Engine-neutral scenes and engines, so that hail and a peer (Bullet) run exactly the same
// scene in one process: `hail-bench compare` and `hail-bench accuracy` build a PeerScene once
// and hand it to each engine. Engines are stepped and read through this narrow interface; the
// virtual calls happen once per step, never per sphere.

#include <memory>
#include <string>
#include <vector>

#include "hail/heightmap.h"
#include "hail/vec3.h"
#include "hail/world.h"

namespace hail::bench {

/// One sphere as the scene defines it. Materials are the *effective* values of the scene
/// definitions (docs/scenes.md): each engine sets its per-body values so that its own
/// combination rule gives them.
struct PeerSphere {
  Vec3 position{0, 0, 0}, velocity{0, 0, 0}, angular_velocity{0, 0, 0};
  float radius = 0.5f, mass = 1.0f, restitution = 0.5f, friction = 0.5f;  ///< mass 0: static
};

struct PeerPlane {
  Vec3 normal{0, 1, 0};  ///< unit, out of the solid
  float offset = 0;      ///< n . x = offset on the surface
  float restitution = 0.5f, friction = 0.5f;
};

struct PeerScene {
  std::string name;
  Vec3 gravity{0.0f, -9.81f, 0.0f};
  std::shared_ptr<const Heightmap> heightmap;  ///< null: no terrain
  float terrain_restitution = 0.5f, terrain_friction = 0.5f;
  std::vector<PeerPlane> planes;
  std::vector<PeerSphere> spheres;
};

/// What an engine reports of one sphere, in the scene's sphere order.
struct PeerState {
  Vec3 position{0, 0, 0}, velocity{0, 0, 0}, angular_velocity{0, 0, 0};
};

class PeerEngine {
 public:
  virtual ~PeerEngine() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// One frame of dt seconds.
  virtual void step(float dt) = 0;
  /// Every sphere's state, in the order of PeerScene::spheres.
  virtual void read_state(std::vector<PeerState>& out) const = 0;
};

/// hail with these settings (gravity is the scene's).
[[nodiscard]] std::unique_ptr<PeerEngine> make_hail_engine(const PeerScene& scene, WorldSettings settings = {});

/// Peers compiled in (Bullet when it was found at configure time), each as a name and a
/// factory; empty when none is. Defined beside the peer's engine.
struct PeerFactory {
  std::string name;
  std::unique_ptr<PeerEngine> (*make)(const PeerScene&);
};
[[nodiscard]] std::vector<PeerFactory> peer_factories();

/// The scene a built-in or file scene starts from: its World's spheres (in creation order,
/// by Scene::ids), planes, terrain and materials.
struct Scene;
[[nodiscard]] PeerScene peer_scene_from(const Scene& scene, const std::string& name);

}  // namespace hail::bench
