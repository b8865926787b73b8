#include <noether/error.hpp>
#include <noether/full_body_model.hpp>
#include <noether/simulation.hpp>

namespace noether {

FullBodyModel FullBodyModel::from_scene(const Scene& scene, PluginRegistry& registry) {
  if (scene.system.size() < 1) throw SceneError("the orbit tools need at least one body");
  if (!scene.impulses.empty())
    throw SceneError("the orbit tools follow the scene's conservative dynamics; its impulses would break every "
                     "orbit: remove them (--set impulses=[])");
  FullBodyModel m;
  m.system = scene.system;
  m.potentials = scene.potentials;
  m.potential = make_scene_potential(scene, registry);
  m.registry = std::make_shared<PluginRegistry>(registry.search_path());
  m.workspace = m.potential->make_workspace();
  return m;
}

double FullBodyModel::total_mass() const {
  double M = 0;
  for (const auto& b : system.bodies()) M += b.mass;
  return M;
}

Forces FullBodyModel::forces(const State& state) const {
  Forces f;
  f.resize(system);
  potential->evaluate(state, f, *workspace);
  return f;
}

Vec3 FullBodyModel::barycentre(const State& s) const {
  Vec3 c = Vec3::Zero();
  for (std::size_t i = 0; i < n(); ++i) c += system.body(i).mass * s.x.col(static_cast<Eigen::Index>(i));
  return c / total_mass();
}

Vec3 FullBodyModel::barycentre_velocity(const State& s) const { return s.p.rowwise().sum() / total_mass(); }

double FullBodyModel::energy(const State& s) const {
  double E = forces(s).U;
  for (std::size_t i = 0; i < n(); ++i) E += s.p.col(static_cast<Eigen::Index>(i)).squaredNorm() / (2 * system.body(i).mass);
  for (std::size_t k = 0; k < rigid(); ++k) {
    const Vec3 Pi = s.Pi.col(static_cast<Eigen::Index>(k));
    E += 0.5 * Pi.dot(system.body(system.body_of_rigid(k)).inertia_inverse * Pi);
  }
  return E;
}

Vec3 FullBodyModel::angular_momentum(const State& s) const {
  const Vec3 c = barycentre(s), vc = barycentre_velocity(s);
  Vec3 L = Vec3::Zero();
  for (std::size_t i = 0; i < n(); ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    L += (s.x.col(j) - c).cross(s.p.col(j) - system.body(i).mass * vc);
  }
  for (std::size_t k = 0; k < rigid(); ++k) L += s.R[k] * s.Pi.col(static_cast<Eigen::Index>(k));
  return L;
}

}  // namespace noether
