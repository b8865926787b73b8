#include <noether/forces.hpp>
#include <noether/state.hpp>

namespace noether {

State State::zeros(const System& system) {
  State s;
  s.x = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(system.size()));
  s.p = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(system.size()));
  s.R.assign(system.rigid_count(), Mat3::Identity());
  s.Pi = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(system.rigid_count()));
  return s;
}

Eigen::VectorXd State::difference(const State& from, const State& to) {
  const Eigen::Index n = from.x.cols(), m = from.Pi.cols();
  Eigen::VectorXd dz(6 * (n + m));
  for (Eigen::Index i = 0; i < n; ++i) {
    dz.segment<3>(3 * i) = to.x.col(i) - from.x.col(i);
    dz.segment<3>(3 * (n + m) + 3 * i) = to.p.col(i) - from.p.col(i);
  }
  for (Eigen::Index k = 0; k < m; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    dz.segment<3>(3 * n + 3 * k) = log_so3(from.R[ku].transpose() * to.R[ku]);
    dz.segment<3>(3 * (2 * n + m) + 3 * k) = to.Pi.col(k) - from.Pi.col(k);
  }
  return dz;
}

Eigen::Index State::tangent_rows(const System& system) {
  return static_cast<Eigen::Index>(6 * (system.size() + system.rigid_count()));
}

std::vector<std::string> State::tangent_coordinates(const System& system) {
  std::vector<std::string> names;
  auto add = [&](std::size_t body, const char* what) {
    for (const char* axis : {"x", "y", "z"}) names.push_back(system.body(body).name + "." + what + "." + axis);
  };
  for (std::size_t i = 0; i < system.size(); ++i) add(i, "position");
  for (std::size_t r = 0; r < system.rigid_count(); ++r) add(system.body_of_rigid(r), "attitude");
  for (std::size_t i = 0; i < system.size(); ++i) add(i, "momentum");
  for (std::size_t r = 0; r < system.rigid_count(); ++r) add(system.body_of_rigid(r), "angular_momentum");
  return names;
}

void Forces::resize(const System& system) {
  f.resize(3, static_cast<Eigen::Index>(system.size()));
  M.resize(3, static_cast<Eigen::Index>(system.rigid_count()));
  set_zero();
}

void Forces::set_zero() {
  U = 0.0;
  f.setZero();
  M.setZero();
}

}  // namespace noether
