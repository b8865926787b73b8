// mutual-series: the mutual potential of every pair of bodies expanded in their inertia
// integrals to total degree N (Hou, Scheeres & Xin 2017; docs/equations.md §12–13), with the
// analytic force and both torques. Order 0 is the point-mass potential; a point mass paired
// with an extended body gives that body's exterior field to degree N.
//
// The order is given (`order`), or chosen per pair from a `tolerance` on the relative error
// of force and torques (docs/equations.md §15): the lowest order whose next-terms estimate
// meets it at the closest separation the pair is expected to reach from the scene's initial
// state (so a continued run models each pair as the run from t0 did), fixed for the whole run
// and watched: when the pair comes closer, the estimate is taken again there and a tolerance
// exceeded is reported (or stops the run, `on_exceed: stop`).
//
// Each body's integrals T^{lmn} are computed once from its shape (ellipsoid in closed form,
// polyhedron exactly) or its Stokes coefficients (a body given by its gravity field); in each
// pair the second body's integrals are rotated into the first's frame at every evaluation
// (docs/equations.md (12.6)).
#include <noether/body_integrals.hpp>
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/mutual_pair.hpp>
#include <noether/order_selection.hpp>
#include <noether/plugin.hpp>

#include <spdlog/spdlog.h>

#include <cmath>
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
};

// What one run of a pair writes: its order (chosen from a tolerance at the scene's initial state,
// or at the first evaluation of a model never told it, or the fixed one), the watch on that
// choice and what is reported.
struct PairRun {
  int order = 0;
  double check_below = 0.0;  // estimate again when the separation drops below this
  noether::PairModel report;
  bool warned_reach = false;
};

struct SeriesWorkspace final : noether::Workspace {
  noether::SeriesBank bank;  // the series evaluators, by order (scratch)
  std::vector<PairRun> pairs;
  bool chosen = false;
  // An evaluation on several threads (noether::evaluation_threads()): each thread's evaluators,
  // and each pair's share of the forces, summed on the calling thread in pair order afterwards.
  std::vector<noether::SeriesBank> thread_banks;
  std::vector<noether::PairShare> shares;
  // A force Jacobian on several threads: each pair's frame, terms and second derivatives (§25),
  // added into K on the calling thread in pair order afterwards.
  struct PairJacobian {
    noether::PairFrame frame;
    noether::MutualTerms t;
    noether::MutualJacobian J;
  };
  std::vector<PairJacobian> jacobians;
};

class MutualSeriesPotential final : public noether::Potential {
 public:
  MutualSeriesPotential(const System& system, const Params& params) : G_(system.G()) {
    read_params(params);
    const int T_order = tolerance_ > 0.0 ? max_order_ + 2 : fixed_order_;
    for (std::size_t i = 0; i < system.size(); ++i) {
      const noether::Body& body = system.body(i);
      integrals_.push_back(noether::body_integrals(body, T_order, "mutual-series", tolerance_ > 0.0));
      radius_.push_back(noether::integrals_radius(body));
      names_.push_back(body.name);
      mass_.push_back(body.mass);
    }
    for (std::size_t i = 0; i < system.size(); ++i)
      for (std::size_t j = i + 1; j < system.size(); ++j) {
        // The expansion frame is an extended body's when there is one: then a point mass
        // needs no rotation of its (single) integral.
        const bool swap = radius_[i] == 0.0 && radius_[j] > 0.0;
        Pair p;
        p.a = swap ? j : i, p.b = swap ? i : j;
        p.rigid_a = system.rigid_index(p.a), p.rigid_b = system.rigid_index(p.b);
        p.reach = radius_[p.a] + radius_[p.b];
        pairs_.push_back(p);
      }
  }

  std::unique_ptr<noether::Workspace> make_workspace() const override {
    auto w = std::make_unique<SeriesWorkspace>();
    w->pairs.resize(pairs_.size());
    for (PairRun& run : w->pairs) run.order = fixed_order_;
    if (!chosen_.empty()) w->pairs = chosen_, w->chosen = true;
    return w;
  }

  // The pairs' terms summed in pair order: on one thread as they come, or computed on several
  // (each pair independent of the others) and then summed in the same order, so that the result
  // is the same bit for bit for any number of threads.
  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<SeriesWorkspace>(workspace, "mutual-series");
    if (tolerance_ > 0.0 && !w.chosen) choose(s, w.bank, w.pairs), w.chosen = true;
    out.set_zero();
    const int threads = noether::evaluation_threads();
    if (threads <= 1 || pairs_.size() < 2) {
      for (std::size_t k = 0; k < pairs_.size(); ++k) {
        const noether::PairFrame frame = noether::pair_frame(s, pairs_[k]);
        noether::add_mutual_terms(pairs_[k], frame, pair_terms(s, pairs_[k], w.pairs[k], w.bank, frame), out);
      }
      return;
    }
    w.shares.resize(pairs_.size());
    if (w.thread_banks.size() < static_cast<std::size_t>(threads)) w.thread_banks.resize(static_cast<std::size_t>(threads));
    noether::parallel_for_each(pairs_.size(), threads, [&](std::size_t k, int thread) {
      const noether::PairFrame frame = noether::pair_frame(s, pairs_[k]);
      w.shares[k] = noether::pair_share(
          frame, pair_terms(s, pairs_[k], w.pairs[k], w.thread_banks[static_cast<std::size_t>(thread)], frame));
    });
    for (std::size_t k = 0; k < pairs_.size(); ++k) noether::add_pair_share(pairs_[k], w.shares[k], out);
  }

  // One pair's terms (13.7) in its frame, with its checks: coincident bodies, the series' reach,
  // and the tolerance's watch (what a run of the pair writes, `run`, is the pair's own).
  noether::MutualTerms pair_terms(const State& s, const Pair& p, PairRun& run, noether::SeriesBank& bank,
                                  const noether::PairFrame& frame) const {
    const double R = frame.R.norm();
    if (!(R > 0.0)) {
      std::ostringstream msg;
      msg << "mutual-series: bodies '" << names_[p.a] << "' and '" << names_[p.b]
          << "' are at the same position at t = " << s.t << " (a collision)";
      throw noether::IntegrationError(msg.str(), s.t);
    }
    if (!run.warned_reach && R < p.reach) {
      run.warned_reach = true;
      spdlog::warn("mutual-series: bodies '{}' and '{}' are {:.6g} apart at t = {:.6g}, closer than "
                   "the sum of their radii {:.6g}: the series may converge slowly or not at all",
                   names_[p.a], names_[p.b], R, s.t, p.reach);
    }
    if (tolerance_ > 0.0 && R < run.check_below) watch(p, run, bank, frame, s.t);
    if (run.order != 0) return bank.at(run.order).evaluate(G_, integrals_[p.a], integrals_[p.b], frame.R, frame.C);
    noether::MutualTerms t;  // point masses: one term
    t.U = -G_ * mass_[p.a] * mass_[p.b] / R;
    t.dU_dR = (-t.U / (R * R)) * frame.R;
    return t;
  }

  // K = ∂(f, M)/∂(x, θ) pair by pair from the series' second derivatives (docs/equations.md §25),
  // on evaluation_threads() threads like evaluate: the pairs' blocks are added in pair order, so K
  // is the same bit for bit for any number of threads.
  bool force_jacobian(const State& s, Eigen::MatrixXd& K, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<SeriesWorkspace>(workspace, "mutual-series");
    if (tolerance_ > 0.0 && !w.chosen) choose(s, w.bank, w.pairs), w.chosen = true;
    const int threads = noether::evaluation_threads();
    if (threads <= 1 || pairs_.size() < 2) {
      SeriesWorkspace::PairJacobian one;
      for (std::size_t k = 0; k < pairs_.size(); ++k) {
        pair_jacobian(s, pairs_[k], w.pairs[k].order, w.bank, one);
        noether::add_mutual_jacobian(pairs_[k], one.frame, one.t, one.J, mass_.size(), K);
      }
      return true;
    }
    w.jacobians.resize(pairs_.size());
    if (w.thread_banks.size() < static_cast<std::size_t>(threads)) w.thread_banks.resize(static_cast<std::size_t>(threads));
    noether::parallel_for_each(pairs_.size(), threads, [&](std::size_t k, int thread) {
      pair_jacobian(s, pairs_[k], w.pairs[k].order, w.thread_banks[static_cast<std::size_t>(thread)], w.jacobians[k]);
    });
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const SeriesWorkspace::PairJacobian& one = w.jacobians[k];
      noether::add_mutual_jacobian(pairs_[k], one.frame, one.t, one.J, mass_.size(), K);
    }
    return true;
  }

  // One pair's frame, terms and their derivatives J (25.1)–(25.5).
  void pair_jacobian(const State& s, const Pair& p, int order, noether::SeriesBank& bank,
                     SeriesWorkspace::PairJacobian& out) const {
    out.frame = noether::pair_frame(s, p);
    const double R = out.frame.R.norm();
    if (!(R > 0.0)) throw noether::IntegrationError("mutual-series: bodies '" + names_[p.a] + "' and '" + names_[p.b] +
                                                    "' are at the same position (a collision)", s.t);
    out.J = noether::MutualJacobian{};
    if (order == 0) {  // point masses: g = G m_a m_b R/R³, ∂g/∂R = G m_a m_b (I − 3 R̂R̂ᵀ)/R³
      const double Gmm = G_ * mass_[p.a] * mass_[p.b];
      const Vec3 e = out.frame.R / R;
      out.t = noether::MutualTerms{};
      out.t.U = -Gmm / R;
      out.t.dU_dR = (Gmm / (R * R)) * e;
      out.J.g_R = (Gmm / (R * R * R)) * (noether::Mat3::Identity() - 3.0 * e * e.transpose());
      out.J.tauA_R = noether::hat(out.frame.R) * out.J.g_R - noether::hat(out.t.dU_dR);
      return;
    }
    out.t = bank.at(order).jacobian(G_, integrals_[p.a], integrals_[p.b], out.frame.R, out.frame.C, out.J);
  }

  // A tolerance's orders at the scene's initial state, which every workspace then starts from.
  void choose_models(const State& initial) override {
    if (!(tolerance_ > 0.0)) return;
    noether::SeriesBank bank;
    chosen_.resize(pairs_.size());
    choose(initial, bank, chosen_);
  }

  std::vector<noether::PairModel> pair_models(const noether::Workspace& workspace) const override {
    const auto& w = noether::workspace_as<SeriesWorkspace>(workspace, "mutual-series");
    std::vector<noether::PairModel> out;
    if (w.chosen)
      for (const PairRun& run : w.pairs) out.push_back(run.report);
    return out;
  }

 private:
  void read_params(const Params& params) {
    if (params.has("order") == params.has("tolerance"))
      throw SceneError(params.here() + "mutual-series needs either 'order' (the total degree N of the "
                       "expansion: 0 = point masses, 2 = quadrupoles, 4 is common) or 'tolerance' (the "
                       "relative error of force and torques per pair; noether picks each pair's order)");
    if (params.has("order")) {
      const long N = params.at("order").as_int();
      if (N < 0 || N > kMaxOrder)
        throw SceneError(params.at("order").here() + "mutual-series: order " + std::to_string(N) +
                         " is outside 0.." + std::to_string(kMaxOrder));
      for (const char* key : {"min_separation", "max_order", "on_exceed"})
        if (given(params, key))
          throw SceneError(params.at(key).here() + "mutual-series: '" + key + "' goes with 'tolerance', not with a fixed 'order'");
      fixed_order_ = static_cast<int>(N);
      return;
    }
    tolerance_ = params.at("tolerance").as_double();
    if (!(tolerance_ > 0.0 && tolerance_ < 1.0))
      throw SceneError(params.at("tolerance").here() + "mutual-series: tolerance must be between 0 and 1 "
                       "(a relative error), not " + params.at("tolerance").as_string());
    const long M = params.at("max_order").as_int();
    if (M < 0 || M > kMaxOrder - 2)
      throw SceneError(params.at("max_order").here() + "mutual-series: max_order must be 0.." +
                       std::to_string(kMaxOrder - 2));
    max_order_ = static_cast<int>(M);
    if (params.has("min_separation")) {
      min_separation_ = params.at("min_separation").as_double();
      if (!(min_separation_ > 0.0))
        throw SceneError(params.at("min_separation").here() + "mutual-series: min_separation must be positive");
    }
    const std::string on_exceed = params.at("on_exceed").as_string();
    if (on_exceed != "warn" && on_exceed != "stop")
      throw SceneError(params.at("on_exceed").here() + "mutual-series: on_exceed must be 'warn' or 'stop', not '" +
                       on_exceed + "'");
    stop_on_exceed_ = on_exceed == "stop";
  }

  // The closest separation a pair is expected to reach (docs/equations.md (15.4)): the
  // scene's min_separation, or 0.9 × the periapsis of the pair's osculating two-body orbit.
  double expected_separation(const Pair& p, const State& s) const {
    if (min_separation_ > 0.0) return min_separation_;
    const Vec3 r = s.x.col(static_cast<Eigen::Index>(p.b)) - s.x.col(static_cast<Eigen::Index>(p.a));
    const Vec3 v = s.p.col(static_cast<Eigen::Index>(p.b)) / mass_[p.b] - s.p.col(static_cast<Eigen::Index>(p.a)) / mass_[p.a];
    const double mu = G_ * (mass_[p.a] + mass_[p.b]);
    const Vec3 h = r.cross(v);
    const double e = (v.cross(h) / mu - r.normalized()).norm();
    const double periapsis = h.squaredNorm() / (mu * (1.0 + e));
    if (!std::isfinite(periapsis) || !(periapsis > 1e-12 * r.norm())) {
      std::ostringstream msg;
      msg << "mutual-series: bodies '" << names_[p.a] << "' and '" << names_[p.b] << "' "
          << (std::isfinite(periapsis) ? "fall straight towards each other (their osculating orbit is radial: periapsis 0)"
                                       : "have a separation or relative velocity that overflows a double")
          << ", so the tolerance cannot choose the series order for the closest separation they reach; give "
          << "potential.min_separation (the closest they come), or use a fixed order or mutual-exact";
      throw SceneError(msg.str());
    }
    return 0.9 * periapsis;
  }

  // Each pair's order from the tolerance at the closest separation expected from `s` (15.4).
  void choose(const State& s, noether::SeriesBank& bank, std::vector<PairRun>& runs) const {
    noether::OrderSelection options;
    options.tolerance = tolerance_;
    options.max_order = max_order_;
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const Pair& p = pairs_[k];
      PairRun& run = runs[k];
      const noether::PairFrame frame = noether::pair_frame(s, p);
      const double separation = expected_separation(p, s);
      const noether::OrderChoice choice = noether::choose_series_order(
          bank, G_, integrals_[p.a], integrals_[p.b], radius_[p.a], radius_[p.b], separation, frame.R, frame.C, options);
      if (!choice.met) {
        std::ostringstream msg;
        msg << "mutual-series: no order up to max_order " << max_order_ << " meets the tolerance " << tolerance_
            << " for bodies '" << names_[p.a] << "' and '" << names_[p.b] << "' at separation " << separation
            << " (the sum of their radii is " << p.reach << "; the best, order " << choice.order
            << ", is estimated at " << choice.estimated_error << "). Raise max_order, loosen the tolerance, "
            << "give a larger min_separation if the bodies never come that close, or use mutual-exact";
        throw SceneError(msg.str());
      }
      run.order = choice.order;
      run.check_below = separation;
      run.report.body_a = names_[std::min(p.a, p.b)];
      run.report.body_b = names_[std::max(p.a, p.b)];
      run.report.order = run.order;
      run.report.model = run.order == 0 ? "point masses" : "series order " + std::to_string(run.order);
      run.report.tolerance = tolerance_;
      run.report.estimated_error = choice.estimated_error;
      run.report.separation = separation;
    }
  }

  // The pair is closer than its order was chosen for: estimate the error here (15.2).
  void watch(const Pair& p, PairRun& run, noether::SeriesBank& bank, const noether::PairFrame& frame,
             double t) const {
    const double R = frame.R.norm();
    run.check_below = 0.99 * R;  // again only once they are 1 % closer
    if (run.report.exceeded) return;
    const double estimate = noether::series_error_estimate(bank, run.order, G_, integrals_[p.a], integrals_[p.b],
                                                           radius_[p.a], radius_[p.b], frame.R, frame.C);
    if (estimate <= tolerance_) return;
    run.report.exceeded = true;
    run.report.exceeded_time = t, run.report.exceeded_separation = R, run.report.exceeded_error = estimate;
    std::ostringstream msg;
    msg << "mutual-series: at t = " << t << " bodies '" << names_[p.a] << "' and '" << names_[p.b] << "' are "
        << R << " apart, closer than the " << run.report.separation << " their order " << run.order
        << " was chosen for, and its estimated error " << estimate << " exceeds the tolerance " << tolerance_;
    if (stop_on_exceed_) throw noether::IntegrationError(msg.str() + " (on_exceed: stop)", t);
    spdlog::warn("{}; the run goes on with order {} (on_exceed: stop would stop it; a smaller min_separation "
                 "would choose a higher order)", msg.str(), run.order);
  }

  double G_;
  int fixed_order_ = 0, max_order_ = 12;
  double tolerance_ = 0.0, min_separation_ = 0.0;
  bool stop_on_exceed_ = false;
  std::vector<InertiaIntegrals> integrals_;
  std::vector<double> radius_, mass_;
  std::vector<std::string> names_;
  std::vector<Pair> pairs_;
  std::vector<PairRun> chosen_;  // at the scene's initial state (choose_models), or empty
};

std::unique_ptr<noether::Potential> make(const System& system, const Params& params) {
  params.check_keys({"plugin", "order", "tolerance", "min_separation", "max_order", "on_exceed"},
                    "the mutual-series potential");
  return std::make_unique<MutualSeriesPotential>(system, params);
}

const noether::ParamDoc kParams[] = {
    {"order", "integer", "(give order or tolerance)",
     "total degree N of the inertia-integral expansion, 0..24 (0 = point masses); or give 'tolerance'"},
    {"tolerance", "number", "(give order or tolerance)",
     "relative error of force and torques per pair; noether picks each pair's lowest sufficient order"},
    {"min_separation", "number", "(0.9 x osculating periapsis)",
     "with tolerance: the closest separation the orders must hold for"},
    {"max_order", "integer", "12", "with tolerance: the highest order to consider"},
    {"on_exceed", "string", "warn",
     "with tolerance: warn, or stop (exit 3), when a pair comes closer and the estimate exceeds the tolerance"}};

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "mutual-series",
    "mutual potential of ellipsoids and polyhedra to order N in their inertia integrals (Hou et al. 2017), "
    "or to a tolerance",
    kParams,
    5,
    &make,
    nullptr};
