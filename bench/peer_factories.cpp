// The peers hail-bench can run beside hail: those found at configure time.

#include "peer_engine.h"
#include "peer_engine_bullet.h"

namespace hail::bench {

std::vector<PeerFactory> peer_factories() {
  std::vector<PeerFactory> peers;
  if (bullet_available()) {
    peers.push_back({"bullet", [](const PeerScene& scene) { return make_bullet_engine(scene); }});
    peers.push_back({"bullet-4-substeps", [](const PeerScene& scene) { return make_bullet_engine(scene); }});
  }
  return peers;
}

}  // namespace hail::bench
