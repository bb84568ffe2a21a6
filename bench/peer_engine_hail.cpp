#include <stdexcept>

#include "peer_engine.h"
#include "scenes/scenes.h"

namespace hail::bench {
namespace {

class HailEngine final : public PeerEngine {
 public:
  HailEngine(const PeerScene& scene, WorldSettings settings) {
    settings.gravity = scene.gravity;
    world_ = std::make_unique<World>(settings);
    if (scene.heightmap)
      world_->set_terrain(std::make_shared<const Terrain>(*scene.heightmap), scene.terrain_restitution,
                          scene.terrain_friction);
    for (const PeerPlane& p : scene.planes)
      world_->add_plane({.normal = p.normal, .offset = p.offset, .restitution = p.restitution, .friction = p.friction});
    world_->reserve(scene.spheres.size());
    // hail combines restitution by the minimum and friction by the geometric mean, so a sphere
    // given the effective values meets a surface of the same values with exactly those.
    for (const PeerSphere& s : scene.spheres)
      ids_.push_back(world_->add_sphere({.position = s.position,
                                         .velocity = s.velocity,
                                         .angular_velocity = s.angular_velocity,
                                         .radius = s.radius,
                                         .mass = s.mass,
                                         .restitution = s.restitution,
                                         .friction = s.friction,
                                         .is_static = s.mass == 0.0f}));
  }
  [[nodiscard]] std::string name() const override { return "hail"; }
  void step(float dt) override { world_->step(dt); }
  void read_state(std::vector<PeerState>& out) const override {
    out.resize(ids_.size());
    for (std::size_t k = 0; k < ids_.size(); ++k)
      out[k] = {world_->position(ids_[k]), world_->velocity(ids_[k]), world_->angular_velocity(ids_[k])};
  }

 private:
  std::unique_ptr<World> world_;
  std::vector<SphereId> ids_;
};

}  // namespace

std::unique_ptr<PeerEngine> make_hail_engine(const PeerScene& scene, WorldSettings settings) {
  return std::make_unique<HailEngine>(scene, settings);
}

PeerScene peer_scene_from(const Scene& scene, const std::string& name) {
  const World& w = *scene.world;
  PeerScene peer;
  peer.name = name;
  peer.gravity = w.settings().gravity;
  if (const Terrain* t = w.terrain()) {
    peer.heightmap = std::make_shared<const Heightmap>(t->heightmap());
    peer.terrain_restitution = w.terrain_restitution();
    peer.terrain_friction = w.terrain_friction();
  }
  for (const Plane& p : w.planes())
    peer.planes.push_back(
        {.normal = {p.nx, p.ny, p.nz}, .offset = p.offset, .restitution = p.restitution, .friction = p.friction});
  const SphereSoA& s = w.soa();
  if (scene.ids.size() != w.sphere_count())
    throw std::logic_error("peer_scene_from: the scene does not list its sphere handles");
  for (SphereId id : scene.ids) {
    const std::size_t i = static_cast<std::size_t>(w.slot_of(id));
    const float mass = s.inv_mass[i] > 0.0f ? 1.0f / s.inv_mass[i] : 0.0f;
    peer.spheres.push_back({.position = {s.px[i], s.py[i], s.pz[i]},
                            .velocity = {s.vx[i], s.vy[i], s.vz[i]},
                            .angular_velocity = {s.wx[i], s.wy[i], s.wz[i]},
                            .radius = s.radius[i],
                            .mass = mass,
                            .restitution = s.restitution[i],
                            .friction = s.friction[i]});
  }
  return peer;
}

}  // namespace hail::bench
