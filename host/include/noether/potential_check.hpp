#pragma once
// Potential checker: compares a potential's forces and moments with central finite
// differences of its energy (docs/equations.md §2: f_i = −∂U/∂x_i, and η · M_i = −dU/dε along
// R_i exp(ε S(η))), at a scene's state and at randomly perturbed states; the force Jacobian
// (§20) against central differences of the forces (when the model has its own) and the symmetry
// (20.3) of K − ½ diag(S(M)); and that total force and total torque vanish (Newton's third law
// for mutual potentials).
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <string>
#include <vector>

namespace noether {

struct PotentialCheckOptions {
  int perturbed_states = 3;      // random states besides the given one
  double tolerance = 1e-6;       // finite-difference agreement, relative to the largest force
                                 // (or moment) of the state; the round-off floor of central
                                 // differences, 64 ε |U| / h, is added to it
  double third_law_tolerance = 1e-12;  // ‖Σ f‖ and ‖Σ torque‖, relative to Σ of magnitudes
  bool third_law = true;         // external-field models do not satisfy it: turn off
  unsigned seed = 1;
};

struct PotentialCheckRow {
  std::string state;     // "scene" or "perturbed k"
  std::string quantity;  // "force", "moment", "jacobian", "symmetry" (of the force Jacobian, 20.3), "net force", "net torque", "finite"
  std::string body;      // body name, or "all"
  double error = 0.0;
  double tolerance = 0.0;
  bool pass = false;
};

struct PotentialCheckReport {
  std::vector<PotentialCheckRow> rows;
  bool passed() const;
  std::string format() const;  // the table printed by `noether check-potential`
};

PotentialCheckReport check_potential(const System& system, const Potential& potential,
                                     const State& state, const PotentialCheckOptions& options = {});

}  // namespace noether
