#include <noether/integrator.hpp>

namespace noether {

// Out of line, so that the vtable and type information of Integrator live in noether-core
// only (one copy for the host and every plugin).
Integrator::~Integrator() = default;
void Integrator::current_state(State& state) {
  Forces unused;
  current(state, unused);
}
bool Integrator::interpolate(double, State&) { return false; }
double Integrator::fixed_step() const { return 0.0; }
int Integrator::order() const { return 0; }
std::string Integrator::tangent_map_unavailable() const { return "this method has no tangent map"; }
std::string Integrator::carry_parameters(std::shared_ptr<const ParameterDerivatives>) {
  return "this method cannot carry sensitivities to parameters of the dynamics";
}
std::string Integrator::add_forcing(std::shared_ptr<const Forcing>) {
  return "this method does not take forces beyond the potential";
}
std::vector<StepSeries> Integrator::take_step_series() { return {}; }
PotentialEvaluator* Integrator::potential_evaluator() { return nullptr; }
std::vector<double> Integrator::checkpoint() const { return {}; }
void Integrator::restore(const State& state, const std::vector<double>&) { start(state); }

}  // namespace noether
