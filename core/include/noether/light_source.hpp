#pragma once
// LightSource: where the light of a radiation force comes from — a body of the scene (`sun:
// NAME`) or a point on a Kepler conic (`position`, `velocity`, `mu`, `epoch`, `center`, as
// PrescribedConic reads them), never both. Shared by the radiation and cannonball plugins.
#include <noether/prescribed_conic.hpp>

#include <optional>
#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class LightSource {
 public:
  // Reads `sun`, or the conic's keys, from a force plugin's parameters; throws SceneError naming
  // `plugin` and the key (both given, neither given, an unknown body).
  LightSource(const System& system, const Params& p, const std::string& plugin);
  // The scene body that is the source, −1 for a conic.
  Eigen::Index body() const { return body_; }
  Vec3 position(const State& s) const { return body_ >= 0 ? Vec3(s.x.col(body_)) : conic_->position(s); }
  // Its velocity (a scene body's from its momentum and `mass`, the conic's as it moves).
  Vec3 velocity(const State& s, double mass) const {
    return body_ >= 0 ? Vec3(s.p.col(body_) / mass) : conic_->velocity(s);
  }

 private:
  Eigen::Index body_ = -1;
  std::optional<PrescribedConic> conic_;
};

}  // namespace noether

#pragma GCC visibility pop
