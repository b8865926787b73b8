// linear-drag: an out-of-tree force plugin (docs/writing-a-plugin.md, "A force plugin"): a drag
// against every body's velocity and every rigid body's spin, proportional to them,
//   f_i = −k γ_i,   M_k = −k_s Π_k,
// with rates k and k_s (per unit time). It depends on the momenta, so the forced LGVI solves its
// closing kick by iteration (docs/equations.md eq. 33.2). A free body slows as e^(−k t): what
// check_drag.py compares the run with.
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cmath>

namespace {

class LinearDrag final : public noether::ForceModel {
 public:
  explicit LinearDrag(const noether::Params& p)
      : k_(p.at("rate").as_double()), k_spin_(p.at("spin_rate").as_double()) {
    if (!(k_ >= 0) || !(k_spin_ >= 0) || !std::isfinite(k_) || !std::isfinite(k_spin_))
      throw noether::SceneError(p.here() + "linear-drag: rate and spin_rate must be finite and ≥ 0");
  }
  // f = −k γ on every body, M = −k_s Π on every rigid body: every entry overwritten.
  void evaluate(const noether::State& s, noether::Forces& out, noether::Workspace&) const override {
    out.U = 0.0;
    out.f = -k_ * s.p;
    out.M = -k_spin_ * s.Pi;
  }

 private:
  double k_, k_spin_;
};

const noether::ParamDoc params[] = {
    {"rate", "number", nullptr, "k: f = −k γ, per unit time"},
    {"spin_rate", "number", "0", "k_s: M = −k_s Π on rigid bodies, per unit time"},
};

std::unique_ptr<noether::ForceModel> make(const noether::System&, const noether::Params& p) {
  return std::make_unique<LinearDrag>(p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {NOETHER_PLUGIN_API_VERSION,
                             noether::PluginKind::Force,
                             "linear-drag",
                             "a linear drag on velocities and spins (an out-of-tree example)",
                             params,
                             std::size(params),
                             nullptr,
                             nullptr,
                             &make};
