#pragma once
// PythonPotential: a gravitational model written in Python, for prototyping (docs/python.md,
// "A potential in Python"). Every evaluation calls back into the interpreter: expect it to be
// 100–1000 times slower than a plugin.
#include <noether/potential.hpp>

#include <pybind11/pybind11.h>

namespace noether::python {

// `function(positions, attitudes)` with positions an (n, 3) array of x_i and attitudes an
// (m, 3, 3) array of R_k (rigid bodies, in System::rigid_index order) returns
// (U, forces, moments): U a float, forces (n, 3) with f_i = −∂U/∂x_i in the inertial frame,
// moments (m, 3) the gravitational moment M_k of each rigid body in its body frame
// (docs/equations.md §2), or None when there are no rigid bodies.
class PythonPotential final : public Potential {
 public:
  explicit PythonPotential(pybind11::object function);
  ~PythonPotential() override;
  using Potential::evaluate;
  void evaluate(const State& state, Forces& forces, Workspace& workspace) const override;

 private:
  pybind11::object function_;
};

}  // namespace noether::python
