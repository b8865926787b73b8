// The sensitivities as a run feature (sensitivity_feature.hpp).
#include "run/sensitivity_feature.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

namespace noether::detail {

SensitivityFeature::SensitivityFeature(const Scene& scene, const Potential& potential, PluginRegistry& registry,
                                       bool custom_potential, Integrator& integrator) {
  at_t0_ = scene_sensitivity(scene, scene.run.sensitivities, potential, [&](const Scene& other) {
    if (custom_potential)  // refused before anything is made at p ± d
      throw SceneError("run.sensitivities: the model is given in code, so noether cannot make it at other "
                       "values of a parameter of the dynamics");
    return make_scene_potential(other, registry);
  }, [&registry](const Scene& other) { return make_scene_forcing(other, registry); });
  if (at_t0_.parameters) {
    std::string names;
    for (const auto& p : at_t0_.parameters->parameters) names += (names.empty() ? "" : ", ") + p.name;
    const std::string why = integrator.carry_parameters(at_t0_.parameters);
    if (!why.empty())
      throw SceneError("run.sensitivities: the parameters of the dynamics " + names + " cannot be carried by integrator '" +
                       scene.integrator.plugin + "': " + why);
  }
}

void SensitivityFeature::start(const State&, Eigen::Ref<Eigen::MatrixXd> columns) {
  if (columns.cols() > 0) columns = at_t0_.columns;  // (a 0×0 matrix does not fit N × 0)
}

void SensitivityFeature::refuse_state(const State&) const {
  throw Error("set_state: this run carries sensitivities to its scene's initial state (run.sensitivities), which "
              "a state set here would no longer start from; make a Simulation for the new state instead");
}

void SensitivityFeature::read_frame(const io::RecordedFrame& frame, Eigen::Ref<Eigen::MatrixXd> columns) const {
  if (frame.sensitivity.cols() != columns.cols() || (columns.cols() > 0 && frame.sensitivity.rows() != columns.rows()))
    throw Error("its frames do not hold the sensitivities the scene's run carries (run.sensitivities)");
  if (columns.cols() > 0) columns = frame.sensitivity;
}

}  // namespace noether::detail
