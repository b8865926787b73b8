// A prescribed body's conic about its center (prescribed_conic.hpp, docs/equations.md §35).
#include <noether/error.hpp>
#include <noether/prescribed_conic.hpp>

#include <cmath>

namespace noether {

namespace {

Vec3 vector_param(const Params& p, const char* key, const std::string& plugin) {
  const std::vector<double> v = p.at(key).as_doubles();
  if (v.size() != 3) throw SceneError(p.at(key).here() + plugin + ": '" + key + "' must be [x, y, z]");
  const Vec3 out(v[0], v[1], v[2]);
  if (!out.allFinite()) throw SceneError(p.at(key).here() + plugin + ": '" + key + "' must be finite");
  return out;
}

// The conic's relative position, which must leave its center (a Kepler conic through r = 0 is
// not one: KeplerOrbit refuses it) and stay within kLargestCoordinate.
Vec3 position_param(const Params& p, const std::string& plugin) {
  const Vec3 r = vector_param(p, "position", plugin);
  if (r.cwiseAbs().maxCoeff() > kLargestCoordinate)
    throw SceneError(p.at("position").here() + plugin + ": 'position' is beyond 1e150, where distances overflow a "
                     "double; give the scene units that keep its numbers far from 1e±300 (docs/user-guide.md \"Units\")");
  if (!(r.norm() > 0))
    throw SceneError(p.at("position").here() + plugin + ": 'position' is [0, 0, 0], its center itself; give where it "
                     "stands relative to `center` at `epoch` (a conic cannot start at its focus)");
  return r;
}

// −1 the barycentre, −2 the origin, else a body's index.
Eigen::Index center_of(const System& system, const Params& p, const std::string& plugin) {
  const std::string center = p.has("center") ? p.at("center").as_string() : "barycentre";
  if (center == "barycentre" || center == "barycenter") return -1;
  if (center == "origin") return -2;
  const int index = system.index_of(center);
  if (index < 0)
    throw SceneError(p.at("center").here() + plugin + ": center must be barycentre, origin or a body, not '" + center +
                     "'");
  return index;
}

double mu_of(const System& system, const Params& p, double mass, Eigen::Index center, const std::string& plugin) {
  if (p.has("mu")) {
    const double mu = p.at("mu").as_double();
    if (!(mu > 0)) throw SceneError(p.at("mu").here() + plugin + ": mu must be positive");
    return mu;
  }
  double center_mass = 0.0;
  if (center == -1)
    for (const auto& b : system.bodies()) center_mass += b.mass;
  else if (center >= 0)
    center_mass = system.body(static_cast<std::size_t>(center)).mass;
  if (center == -2 || !(mass > 0))
    throw SceneError(p.here() + plugin + ": give 'mu', the G M of the conic" +
                     (center == -2 ? " (center: origin has no mass)" : ""));
  return system.G() * (mass + center_mass);
}

}  // namespace

PrescribedConic::PrescribedConic(const System& system, const Params& p, double mass, const std::string& plugin)
    : center_(center_of(system, p, plugin)),
      orbit_(position_param(p, plugin), vector_param(p, "velocity", plugin),
             mu_of(system, p, mass, center_, plugin), p.has("epoch") ? p.at("epoch").as_double() : 0.0) {
  for (const auto& b : system.bodies()) {
    masses_.push_back(b.mass);
    scene_mass_ += b.mass;
  }
}

Vec3 PrescribedConic::center(const State& s) const {
  if (center_ >= 0) return s.x.col(center_);
  if (center_ == -2) return Vec3::Zero();
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < masses_.size(); ++i) sum += masses_[i] * Vec3(s.x.col(static_cast<Eigen::Index>(i)));
  return sum / scene_mass_;
}

Vec3 PrescribedConic::velocity(const State& s) const {
  Vec3 rho, rho_dot;
  orbit_.state(s.t, rho, rho_dot);
  if (center_ >= 0) return rho_dot + s.p.col(center_) / masses_[static_cast<std::size_t>(center_)];
  if (center_ == -2) return rho_dot;
  return rho_dot + Vec3(s.p.rowwise().sum()) / scene_mass_;  // the barycentre's: Σ γ_i / Σ m_i
}

Vec3 PrescribedConic::position(const State& s) const {
  Vec3 rho, rho_dot;
  orbit_.state(s.t, rho, rho_dot);
  return center(s) + rho;
}

}  // namespace noether
