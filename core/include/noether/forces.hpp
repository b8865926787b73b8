#pragma once
// Forces: what a Potential computes at a State (docs/equations.md §2).
#include <noether/system.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct Forces {
  double U = 0.0;          // mutual potential
  Eigen::Matrix3Xd f;      // f_i = −∂U/∂x_i, inertial, every body
  Eigen::Matrix3Xd M;      // M_k, body-frame gravitational moment (24), rigid bodies only

  void resize(const System& system);
  void set_zero();
};

}  // namespace noether

#pragma GCC visibility pop
