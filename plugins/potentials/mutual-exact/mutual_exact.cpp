// mutual-exact: the exact mutual potential, force and torques of every pair of bodies: one
// body's exact exterior field (Werner–Scheeres polyhedron, MacMillan ellipsoid, or a point
// mass) integrated over the other's surface, refined until two quadrature levels agree to
// `tolerance` (docs/equations.md §14). Slow; the oracle of the series, and a model for close
// encounters of coarse shapes. Bodies must not overlap.
#include <noether/error.hpp>
#include <noether/exact_mutual.hpp>
#include <noether/plugin.hpp>

#include <sstream>

namespace {

using noether::Forces;
using noether::Mat3;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

struct Pair {
  std::size_t a, b;
  int rigid_a, rigid_b;
  std::unique_ptr<noether::ExactMutual> exact;
};

class MutualExactPotential final : public noether::Potential {
 public:
  MutualExactPotential(const System& system, const Params& params) : names_() {
    noether::ExactMutualOptions options;
    options.tolerance = params.get("tolerance", 1e-12);
    options.max_level = static_cast<int>(params.get("max_level", 7L));
    if (!(options.tolerance > 0.0))
      throw SceneError(params.at("tolerance").here() + "mutual-exact: tolerance must be positive");
    if (options.max_level < 1 || options.max_level > 9)
      throw SceneError(params.at("max_level").here() + "mutual-exact: max_level must be 1..9");
    for (std::size_t i = 0; i < system.size(); ++i) {
      const noether::Body& body = system.body(i);
      if (body.rigid && !body.solid)
        throw SceneError((body.shape.is_null() ? std::string() : body.shape.here()) +
                         "mutual-exact: body '" + body.name +
                         "' is rigid but has no ellipsoid or polyhedron shape, so its exact "
                         "field is unknown");
      names_.push_back(body.name);
    }
    for (std::size_t i = 0; i < system.size(); ++i)
      for (std::size_t j = i + 1; j < system.size(); ++j)
        pairs_.push_back({i, j, system.rigid_index(i), system.rigid_index(j),
                          std::make_unique<noether::ExactMutual>(system.G(), system.body(i).solid,
                                                                 system.body(i).mass, system.body(j).solid,
                                                                 system.body(j).mass, options)});
  }

  void evaluate(const State& s, Forces& out) const override {
    out.set_zero();
    for (const Pair& p : pairs_) {
      const Mat3 RA = p.rigid_a >= 0 ? s.R[static_cast<std::size_t>(p.rigid_a)] : Mat3::Identity();
      const Mat3 RB = p.rigid_b >= 0 ? s.R[static_cast<std::size_t>(p.rigid_b)] : Mat3::Identity();
      const Vec3 R = RA.transpose() * (s.x.col(static_cast<Eigen::Index>(p.b)) - s.x.col(static_cast<Eigen::Index>(p.a)));
      noether::MutualTerms t;
      try {
        t = p.exact->evaluate(R, RA.transpose() * RB);
      } catch (const noether::Error& e) {
        std::ostringstream msg;
        msg << "mutual-exact: bodies '" << names_[p.a] << "' and '" << names_[p.b] << "' at t = " << s.t
            << ", separation " << R.norm() << ": " << e.what();
        throw noether::IntegrationError(msg.str(), s.t);
      }
      out.U += t.U;
      const Vec3 f = RA * t.dU_dR;
      out.f.col(static_cast<Eigen::Index>(p.a)) += f;
      out.f.col(static_cast<Eigen::Index>(p.b)) -= f;
      if (p.rigid_a >= 0) out.M.col(p.rigid_a) += t.torque_A;
      if (p.rigid_b >= 0) out.M.col(p.rigid_b) += RB.transpose() * (RA * t.torque_B);
    }
  }

  bool needs_attitudes() const override { return true; }

 private:
  std::vector<std::string> names_;
  std::vector<Pair> pairs_;
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& params) {
  params.check_keys({"plugin", "tolerance", "max_level"}, "the mutual-exact potential");
  return std::make_unique<MutualExactPotential>(system, params);
}

const noether::ParamDoc kParams[] = {
    {"tolerance", "number", "1e-12",
     "relative change of U, force and torques between two quadrature levels at which to stop"},
    {"max_level", "integer", "7",
     "finest quadrature level (polyhedra 2,3,4,6,8,12,16,24,32,48 points a side; ellipsoids 12(k+1) x 24(k+1))"}};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "mutual-exact",
    "exact mutual potential of ellipsoids, polyhedra and point masses by surface quadrature (slow; the reference)",
    kParams,
    2,
    &make,
    nullptr};
