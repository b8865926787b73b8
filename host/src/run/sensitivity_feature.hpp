#pragma once
// The sensitivities as a run feature (run.sensitivities, --sensitivity; docs/derivatives.md,
// "Sensitivities"): the tangent's last columns, ∂z(t)/∂p for each key p of the scene, started at
// ∂z(t0)/∂p (scene_sensitivity) and carried by the integrator's tangent map — with the step's own
// dependence on the parameters of the dynamics among the keys, which the integrator is handed
// (docs/equations.md §22). Each frame writes them to /derivatives/sensitivity, from which a
// continued run reads them back (checksummed). A state set from outside is refused: the columns
// are derivatives with respect to the scene's initial state.
#include <noether/integrator.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include "io/frame_schema.hpp"
#include "run/run_feature.hpp"
#include "scene/scene_sensitivity.hpp"

namespace noether::detail {

class SensitivityFeature final : public RunFeature {
 public:
  // The scene's run.sensitivities at its initial state, the model `potential` (made from the
  // scene by `registry`, or given in code: `custom_potential`, for which parameters of the
  // dynamics are refused); the parameters among them handed to `integrator`. SceneError when a
  // key cannot be taken or the integrator cannot carry the parameters.
  SensitivityFeature(const Scene& scene, const Potential& potential, PluginRegistry& registry, bool custom_potential,
                     Integrator& integrator);
  std::string_view name() const override { return "sensitivities"; }
  Eigen::Index tangent_columns() const override { return at_t0_.columns.cols(); }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd> columns) override;
  void refuse_state(const State&) const override;
  void read_frame(const io::RecordedFrame& frame, Eigen::Ref<Eigen::MatrixXd> columns) const override;

  // Each column's key (SceneSensitivity::names), and the parameters of the dynamics among them
  // (the last columns; null without).
  const std::vector<std::string>& names() const { return at_t0_.names; }
  std::shared_ptr<const ParameterDerivatives> parameters() const { return at_t0_.parameters; }

 private:
  SceneSensitivity at_t0_;
};

}  // namespace noether::detail
