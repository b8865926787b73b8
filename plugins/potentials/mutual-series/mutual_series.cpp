// mutual-series: the mutual potential of every pair of bodies expanded in their inertia
// integrals to total degree N (Hou, Scheeres & Xin 2017; docs/equations.md §13), with the
// analytic force and both torques. Order 0 is the point-mass potential; a point mass paired
// with an extended body gives that body's exterior field to degree N.
//
// Each body's integrals T^{lmn} are computed once from its shape (ellipsoid in closed form,
// polyhedron exactly); in each pair the second body's integrals are rotated into the first's
// frame at every evaluation (docs/equations.md (12.6)).
#include <noether/error.hpp>
#include <noether/mutual_pair.hpp>
#include <noether/mutual_series.hpp>
#include <noether/plugin.hpp>

#include <spdlog/spdlog.h>

#include <sstream>

namespace {

using noether::Forces;
using noether::InertiaIntegrals;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

constexpr int kMaxOrder = 24;

struct Pair : noether::MutualPair {  // a is the frame of the expansion (extended if either is)
  double reach = 0.0;  // radius_a + radius_b: beyond it the series converges for sure
  mutable bool warned = false;
};

class MutualSeriesPotential final : public noether::Potential {
 public:
  MutualSeriesPotential(const System& system, const Params& params)
      : G_(system.G()), series_(order_of(params)) {
    const int N = series_.order();
    for (std::size_t i = 0; i < system.size(); ++i) {
      const noether::Body& body = system.body(i);
      if (body.solid) {
        integrals_.push_back(body.solid->integrals(N));
        radius_.push_back(body.solid->radius);
      } else if (body.rigid) {
        if (N > 2 && !body.shape.is_null())
          throw SceneError(body.shape.here() + "mutual-series: body '" + body.name +
                           "' is a point cluster; its shape is not a solid: use sphere-cluster, "
                           "or give it an ellipsoid or polyhedron shape");
        if (N > 2)
          throw SceneError("mutual-series: body '" + body.name + "' has an inertia but no shape, "
                           "so its integrals beyond degree 2 are unknown and order " +
                           std::to_string(N) + " cannot be evaluated; give it a shape "
                           "(ellipsoid or polyhedron), or use order ≤ 2");
        integrals_.push_back(noether::integrals_from_inertia(body.mass, body.inertia));
        radius_.push_back(0.0);
      } else {
        integrals_.push_back(noether::point_integrals({body.mass}, {Vec3::Zero()}, 0));
        radius_.push_back(0.0);
      }
      names_.push_back(body.name);
    }
    for (std::size_t i = 0; i < system.size(); ++i)
      for (std::size_t j = i + 1; j < system.size(); ++j) {
        // The expansion frame is an extended body's when there is one: then a point mass
        // needs no rotation of its (single) integral.
        const bool swap = integrals_[i].order == 0 && integrals_[j].order > 0;
        const std::size_t a = swap ? j : i, b = swap ? i : j;
        Pair p;
        p.a = a, p.b = b, p.rigid_a = system.rigid_index(a), p.rigid_b = system.rigid_index(b);
        p.reach = radius_[a] + radius_[b];
        pairs_.push_back(p);
      }
  }

  void evaluate(const State& s, Forces& out) const override {
    out.set_zero();
    for (const Pair& p : pairs_) {
      const noether::PairFrame frame = noether::pair_frame(s, p);
      const double R = frame.R.norm();
      if (!(R > 0.0)) {
        std::ostringstream msg;
        msg << "mutual-series: bodies '" << names_[p.a] << "' and '" << names_[p.b]
            << "' are at the same position at t = " << s.t << " (a collision)";
        throw noether::IntegrationError(msg.str(), s.t);
      }
      if (!p.warned && R < p.reach) {
        p.warned = true;
        spdlog::warn("mutual-series: bodies '{}' and '{}' are {:.6g} apart at t = {:.6g}, closer than "
                     "the sum of their radii {:.6g}: the series may converge slowly or not at all",
                     names_[p.a], names_[p.b], R, s.t, p.reach);
      }
      noether::add_mutual_terms(p, frame, series_.evaluate(G_, integrals_[p.a], integrals_[p.b], frame.R, frame.C), out);
    }
  }

  bool needs_attitudes() const override { return true; }

 private:
  static int order_of(const Params& params) {
    if (!params.has("order"))
      throw SceneError(params.here() + "mutual-series needs 'order': the total degree N of the "
                       "expansion (0 = point masses, 2 = quadrupoles, 4 is common)");
    const long N = params.at("order").as_int();
    if (N < 0 || N > kMaxOrder)
      throw SceneError(params.at("order").here() + "mutual-series: order " + std::to_string(N) +
                       " is outside 0.." + std::to_string(kMaxOrder));
    return static_cast<int>(N);
  }

  double G_;
  mutable noether::MutualSeries series_;  // scratch: one evaluation at a time
  std::vector<InertiaIntegrals> integrals_;
  std::vector<double> radius_;
  std::vector<std::string> names_;
  std::vector<Pair> pairs_;
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& params) {
  params.check_keys({"plugin", "order"}, "the mutual-series potential");
  return std::make_unique<MutualSeriesPotential>(system, params);
}

const noether::ParamDoc kParams[] = {
    {"order", "integer", nullptr,
     "total degree N of the inertia-integral expansion, 0..24 (0 = point masses)"}};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "mutual-series",
    "mutual potential of ellipsoids and polyhedra to order N in their inertia integrals (Hou et al. 2017)",
    kParams,
    1,
    &make,
    nullptr};
