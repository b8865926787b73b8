#pragma once
// The four discrete forms of the LGVI (Lee, Leok & McClamroch 2007, Fig. 7, right face of the cube) behind one
// interface, so that the plugin drives any of them, and composes the one-step (Hamiltonian)
// forms for order 4.
#include <noether/discrete_attitude.hpp>
#include <noether/force_model.hpp>
#include <noether/forces.hpp>
#include <noether/integrator.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <memory>
#include <string>
#include <vector>

namespace lgvi {

using noether::Forces;
using noether::Mat3;
using noether::State;
using noether::System;
using noether::Vec3;

struct Settings {
  noether::DiscreteAttitudeOptions newton;
};

class DiscreteFlow {
 public:
  virtual ~DiscreteFlow() = default;
  // Starts at an inertial state (evaluates the potential there).
  virtual void start(const State& s) = 0;
  // One step of size h, ending at the time t_next (the plugin's t0 + k h: a time that a continued
  // run, restarted at a step's end, gives the forces exactly as the uninterrupted run did, which
  // a sum of steps would not). The Lagrangian (two-step) forms need the same h every step.
  virtual void advance(double h, double t_next) = 0;
  // The current inertial state (momenta by the discrete Legendre transform where needed) and
  // the forces there (U, inertial f, body-frame M), for output and diagnostics.
  virtual void current(State& s, Forces& f) const = 0;
  // The current state alone (what the step loop's events watch at every step): current()'s,
  // with `scratch` taking the forces, unless the flow has the state at hand.
  virtual void current_state(State& s, Forces& scratch) const { current(s, scratch); }
  virtual double time() const = 0;
  // The flow's own variables beyond the State (noether::Integrator::checkpoint): none for the
  // inertial Hamiltonian form, whose variables are the State's.
  virtual std::vector<double> checkpoint() const { return {}; }
  virtual std::size_t checkpoint_size() const { return 0; }  // checkpoint().size(), fixed for the flow
  virtual void restore(const State& s, const std::vector<double>&) { start(s); }
  // Sensitivities to parameters of the dynamics (noether::Integrator::carry_parameters): false
  // for a form without a tangent map.
  virtual bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives>) { return false; }
  // Forces beyond the potential (noether::Integrator::add_forcing), by the discrete
  // Lagrange–d'Alembert principle (docs/equations.md §33): false for a form that takes none.
  virtual bool add_forcing(std::shared_ptr<const noether::Forcing>) { return false; }

  noether::WorkCounters work;
};

// Solves (93)/(123)/(124)-type equations S(g) = F Jd − Jd Fᵀ for F = exp(S(f)), turning a
// failure into an IntegrationError that names the body, the time, the step and the spin
// |Ω| h (Ω = J⁻¹ Π from the body's angular momentum Π, computed only then).
noether::DiscreteAttitude solve_attitude(const Vec3& g, const Mat3& J, const Mat3& J_inverse, const Settings& settings,
                                         const std::string& body, double t, double h, const Vec3& angular_momentum,
                                         noether::WorkCounters& work);

// vee(Jd F − Fᵀ Jd) for F = exp(S(f)), the left side of (79) and (114) at step k − 1,
// evaluated from f as a J f − b f × J f (= Fᵀ G(f)) instead of from the matrices, whose I
// parts cancel and would lose a factor 1/‖f‖ of precision every step.
Vec3 lagrangian_momentum(const Vec3& f, const Mat3& J);

// Each flow evaluates the potential through the plugin's evaluator (its workspace), which
// outlives it.
using noether::PotentialEvaluator;
std::unique_ptr<DiscreteFlow> make_inertial_hamiltonian(const System&, PotentialEvaluator&, const Settings&);
std::unique_ptr<DiscreteFlow> make_inertial_lagrangian(const System&, PotentialEvaluator&, const Settings&);
std::unique_ptr<DiscreteFlow> make_relative_hamiltonian(const System&, PotentialEvaluator&, const Settings&);
std::unique_ptr<DiscreteFlow> make_relative_lagrangian(const System&, PotentialEvaluator&, const Settings&);

}  // namespace lgvi
