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
