// mutual-exact: the exact mutual potential, force and torques of every pair of bodies: one
// body's exact exterior field (Werner–Scheeres polyhedron, MacMillan ellipsoid, or a point
// mass) integrated over the other's surface, refined until two quadrature levels agree to
// `tolerance` (docs/equations.md §14) — or, where the surface body's circumscribed sphere is far
// enough from the other body, sampled on that sphere and expanded in solid harmonics until two
// degrees agree (§37) — and its force Jacobian from the same numbers (§26). The oracle of the
// series, and a model for close encounters of coarse shapes. Bodies must not overlap.
#include <noether/error.hpp>
#include <noether/exact_mutual.hpp>
#include <noether/mutual_pair.hpp>
#include <noether/plugin.hpp>

#include <sstream>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;

using Pair = noether::MutualPair;

// The reference evaluators of every pair: each keeps the surface rules it has built and the
// quadrature level it last reached, so they are one thread's.
struct Evaluators final : noether::Workspace {
  std::vector<noether::ExactMutual> of_pair;
};

class MutualExactPotential final : public noether::Potential {
 public:
  MutualExactPotential(const System& system, const Params& params) : names_() {
    noether::ExactMutualOptions options;
    options.tolerance = params.at("tolerance").as_double();
    options.max_level = static_cast<int>(params.at("max_level").as_int());
    const std::string method = params.at("method").as_string();
    if (method == "automatic") options.method = noether::ExactMutualOptions::Method::Automatic;
    else if (method == "quadrature") options.method = noether::ExactMutualOptions::Method::Quadrature;
    else if (method == "expansion") options.method = noether::ExactMutualOptions::Method::Expansion;
    else {
      std::string msg = params.at("method").here();
      msg += "mutual-exact: method must be automatic, quadrature or expansion, not '";
      msg += method;
      msg += "'";
      throw SceneError(msg);
    }
    if (!(options.tolerance > 0.0))
      throw SceneError(params.at("tolerance").here() + "mutual-exact: tolerance must be positive");
    if (options.max_level < 1 || options.max_level > 9)
      throw SceneError(params.at("max_level").here() + "mutual-exact: max_level must be 1..9");
    for (std::size_t i = 0; i < system.size(); ++i) {
      const noether::Body& body = system.body(i);
      if (body.rigid && !body.solid)
        throw SceneError((body.shape.is_null() ? std::string() : body.shape.here()) +
                         "mutual-exact: body '" + body.name +
                         "' is rigid but has no ellipsoid or polyhedron shape, so its exact " +
                         (body.field ? "interior field is unknown (its Stokes coefficients give the field outside "
                                       "its Brillouin sphere only: use mutual-series)"
                                     : std::string("field is unknown")));
      names_.push_back(body.name);
    }
    for (std::size_t i = 0; i < system.size(); ++i)
      for (std::size_t j = i + 1; j < system.size(); ++j) {
        Pair p;
        p.a = i, p.b = j, p.rigid_a = system.rigid_index(i), p.rigid_b = system.rigid_index(j);
        pairs_.push_back(p);
      }
    G_ = system.G();
    options_ = options;
    for (const auto& body : system.bodies()) solid_.push_back(body.solid), mass_.push_back(body.mass);
    make_workspace();  // checks the pairs can be evaluated (the constructor's errors) now
  }

  std::unique_ptr<noether::Workspace> make_workspace() const override {
    auto w = std::make_unique<Evaluators>();
    for (const Pair& p : pairs_)
      w->of_pair.emplace_back(G_, solid_[p.a], mass_[p.a], solid_[p.b], mass_[p.b], options_);
    return w;
  }

  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& exact = noether::workspace_as<Evaluators>(workspace, "mutual-exact").of_pair;
    out.set_zero();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const Pair& p = pairs_[k];
      const noether::PairFrame frame = noether::pair_frame(s, p);
      noether::add_mutual_terms(p, frame, guarded(p, frame, s.t, [&] { return exact[k].evaluate(frame.R, frame.C); }), out);
    }
  }

  // K = ∂(f, M)/∂(x, θ) pair by pair from the same surface quadrature, differentiated
  // (docs/equations.md §26): the field's gradient where the other body is a surface, its
  // gradient tensor where the other body is a point mass.
  bool force_jacobian(const State& s, Eigen::MatrixXd& K, noether::Workspace& workspace) const override {
    auto& exact = noether::workspace_as<Evaluators>(workspace, "mutual-exact").of_pair;
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const Pair& p = pairs_[k];
      const noether::PairFrame frame = noether::pair_frame(s, p);
      noether::MutualJacobian J;
      const noether::MutualTerms t = guarded(p, frame, s.t, [&] { return exact[k].jacobian(frame.R, frame.C, J); });
      noether::add_mutual_jacobian(p, frame, t, J, mass_.size(), K);
    }
    return true;
  }

 private:
  // The evaluation of one pair, its errors named by the pair, the time and the separation.
  template <class Evaluate>
  noether::MutualTerms guarded(const Pair& p, const noether::PairFrame& frame, double t, Evaluate&& evaluate) const {
    try {
      return evaluate();
    } catch (const noether::Error& e) {
      std::ostringstream msg;
      msg << "mutual-exact: bodies '" << names_[p.a] << "' and '" << names_[p.b] << "' at t = " << t
          << ", separation " << frame.R.norm() << ": " << e.what();
      throw noether::IntegrationError(msg.str(), t);
    }
  }

  std::vector<std::string> names_;
  std::vector<Pair> pairs_;
  double G_ = 1.0;
  noether::ExactMutualOptions options_;
  std::vector<std::shared_ptr<const noether::Solid>> solid_;
  std::vector<double> mass_;
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& params) {
  params.check_keys({"plugin", "tolerance", "max_level", "method"}, "the mutual-exact potential");
  return std::make_unique<MutualExactPotential>(system, params);
}

const noether::ParamDoc kParams[] = {
    {"tolerance", "number", "1e-12",
     "relative change of U, force and torques between two quadrature levels at which to stop"},
    {"max_level", "integer", "7",
     "finest quadrature level (polyhedra 2,3,4,6,8,12,16,24,32,48 points a side; ellipsoids 12(k+1) x 24(k+1))"},
    {"method", "string", "automatic",
     "automatic: the solid-harmonic expansion of the field over the surface body's circumscribed sphere where it "
     "converges by degree 40 and is the faster (far pairs of polyhedra: ~100x on KW4's meshes), else the surface "
     "quadrature; quadrature; "
     "expansion (an error where it does not converge)"}};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "mutual-exact",
    "exact mutual potential of ellipsoids, polyhedra and point masses by surface quadrature or its solid-harmonic "
    "expansion (the reference)",
    kParams,
    3,
    &make,
    nullptr};
