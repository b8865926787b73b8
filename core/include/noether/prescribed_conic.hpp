#pragma once
// PrescribedConic: where a body the scene does not integrate stands — a Kepler conic about a
// center that may move with the scene (docs/equations.md §35): X(t) = c(t) + ρ(t), c the scene's
// barycentre where the run stands, a body, or the origin. Read from a force plugin's parameters
// `position`, `velocity`, `epoch`, `center` and `mu`; shared by prescribed-body (the body's
// gravity) and radiation (where its light comes from).
#include <noether/kepler_orbit.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class PrescribedConic {
 public:
  // `mass` is the prescribed body's (0 when unknown); mu defaults to G (mass + the center's mass,
  // the scene's total for the barycentre) and must be given when that is 0 or the center is the
  // origin. Throws SceneError naming `plugin` and the field.
  PrescribedConic(const System& system, const Params& p, double mass, const std::string& plugin);

  // X(t) where the run stands at s (35.1)–(35.3).
  Vec3 position(const State& s) const;
  // Ẋ(t) where the run stands at s: the center's velocity and the conic's.
  Vec3 velocity(const State& s) const;
  // The center c(t) where the run stands at s.
  Vec3 center(const State& s) const;
  const KeplerOrbit& orbit() const { return orbit_; }

 private:
  std::vector<double> masses_;
  double scene_mass_ = 0.0;
  Eigen::Index center_ = -1;  // a body, −1 the barycentre, −2 the origin
  KeplerOrbit orbit_;
};

}  // namespace noether

#pragma GCC visibility pop
