// prescribed-body: the gravity of a body that moves on a prescribed conic and is not integrated
// (a planet passing a binary asteroid, the Sun about it; docs/forces.md, docs/equations.md §35).
// Its position is X(t) = c(t) + ρ(t): ρ a Kepler conic (KeplerOrbit) from the relative state
// given at `epoch`, about c — the scene's barycentre where the run stands (default), a body, or
// the origin. Every point mass i feels it as a point mass M,
//
//   f_i = G M m_i d_i / |d_i|³,   d_i = X − x_i,                                               (35.4)
//
// and every rigid body through the mutual series of order N between the point mass and the body's
// inertia integrals (§13; order 2 is MacCullagh's quadrupole force and gravity-gradient torque,
// (35.5)): the force ∂U/∂R and the torque on the body, in its frame, at R = Rᵀ d. N is `order`, or
// the lowest order meeting `tolerance` at the closest the conic comes to the body (35.6), chosen
// per body at the scene's initial state as mutual-series chooses per pair (§15), and reported
// (pair_models: the summary's and the output's pair models).
//
// The prescribed body feels nothing back: the scene's momenta change by what it puts in, which
// the balance records (docs/equations.md eq. 33.3). Massless particles feel it as a point mass.
// With a `radius` it is a sphere: a particle that reaches it lands on it, and a body whose
// bounding sphere meets it stops the run (an impact noether does not model).
#include <noether/body_integrals.hpp>
#include <noether/error.hpp>
#include <noether/mutual_series.hpp>
#include <noether/order_selection.hpp>
#include <noether/plugin.hpp>
#include <noether/prescribed_conic.hpp>

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using noether::Forces;
using noether::Mat3;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using noether::Vec3;

// Per body: the series order (0: a point mass) and, with a tolerance, the separation below which
// it is watched — chosen at the scene's initial state (or, in a model never told it, at the
// workspace's first evaluation).
struct Choice {
  std::vector<int> order;
  std::vector<double> check_below;
  std::vector<noether::PairModel> report;  // per rigid body, with a tolerance
};
struct SeriesWorkspace final : noether::Workspace {
  noether::SeriesBank bank;  // the series evaluators, by order (scratch)
  Choice choice;
  bool chosen = false;
};

class PrescribedBody final : public noether::ForceModel {
 public:
  PrescribedBody(const System& system, const Params& p)
      : system_(system), mass_(positive_mass(p)), conic_(system, p, mass_, "prescribed-body"),
        point_(noether::point_integrals({mass_}, {Vec3::Zero()}, 0)),
        name_(p.has("name") ? p.at("name").as_string() : std::string()) {
    if (p.has("radius")) {
      surface_radius_ = p.at("radius").as_double();
      if (!(surface_radius_ > 0.0) || !std::isfinite(surface_radius_))
        throw SceneError(p.at("radius").here() + "prescribed-body: radius must be positive (leave it out for a point)");
    }
    const bool tolerance = p.has("tolerance");
    if (tolerance && noether::given(p, "order"))
      throw SceneError(p.at("order").here() + "prescribed-body: give 'order' or 'tolerance', not both");
    for (const char* key : {"max_order", "min_separation"})
      if (!tolerance && noether::given(p, key))
        throw SceneError(p.at(key).here() + "prescribed-body: '" + key + "' goes with 'tolerance', not with a fixed 'order'");
    order_ = static_cast<int>(p.at("order").as_int());
    if (order_ < 0 || order_ > 12) throw SceneError(p.at("order").here() + "prescribed-body: order must be in 0..12");
    int integrals_order = order_;
    if (tolerance) {
      selection_.tolerance = p.at("tolerance").as_double();
      if (!(selection_.tolerance > 0.0 && selection_.tolerance < 1.0))
        throw SceneError(p.at("tolerance").here() + "prescribed-body: tolerance must be between 0 and 1 (a relative error)");
      if (p.has("max_order")) {
        selection_.max_order = static_cast<int>(p.at("max_order").as_int());
        if (selection_.max_order < 0 || selection_.max_order > 12)
          throw SceneError(p.at("max_order").here() + "prescribed-body: max_order must be in 0..12");
      }
      if (p.has("min_separation")) {
        min_separation_ = p.at("min_separation").as_double();
        if (!(min_separation_ > 0.0))
          throw SceneError(p.at("min_separation").here() + "prescribed-body: min_separation must be positive");
      }
      integrals_order = selection_.max_order + 2;
      tolerance_where_ = p.at("tolerance").here();
    }
    for (const auto& body : system.bodies()) {
      integrals_.push_back(body.rigid && integrals_order > 0
                               ? noether::body_integrals(body, integrals_order, "prescribed-body", tolerance)
                               : noether::InertiaIntegrals{});
      radius_.push_back(noether::integrals_radius(body));
    }
  }

  bool depends_on_momenta() const override { return false; }
  // Massless particles feel it as the point mass it is, (35.4) per unit mass.
  bool pull_particles(const State& s, std::vector<noether::PointPull>& pulls) const override {
    pulls.push_back({system_.G() * mass_, conic_.position(s), conic_.velocity(s), surface_radius_});
    return true;
  }

  std::unique_ptr<noether::Workspace> make_workspace() const override {
    auto w = std::make_unique<SeriesWorkspace>();
    for (const auto& body : system_.bodies()) w->choice.order.push_back(body.rigid ? order_ : 0);
    w->choice.check_below.assign(system_.size(), 0.0);
    w->chosen = selection_.tolerance == 0.0;
    if (chosen_) w->choice = *chosen_, w->chosen = true;
    return w;
  }

  void choose_models(const State& initial) override {
    if (selection_.tolerance == 0.0) return;
    noether::SeriesBank bank;
    Choice c;
    c.order.assign(system_.size(), 0);
    c.check_below.assign(system_.size(), 0.0);
    choose(initial, bank, c);
    chosen_ = std::move(c);
  }

  std::vector<noether::PairModel> pair_models() const override {
    return chosen_ ? chosen_->report : std::vector<noether::PairModel>{};
  }

  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<SeriesWorkspace>(workspace, "prescribed-body");
    if (!w.chosen) choose(s, w.bank, w.choice), w.chosen = true;
    out.set_zero();
    const Vec3 X = conic_.position(s);
    const double G = system_.G();
    for (std::size_t i = 0; i < system_.size(); ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      const Vec3 d = X - Vec3(s.x.col(c));
      const double d2 = d.squaredNorm(), dn = std::sqrt(d2);
      if (!(dn > surface_radius_ + system_.body(i).radius)) collision(i, dn, s.t);
      const int order = w.choice.order[i];
      if (order == 0) {
        out.f.col(c) = (G * mass_ * system_.body(i).mass / (d2 * dn)) * d;  // (35.4)
        continue;
      }
      const auto k = static_cast<std::size_t>(system_.rigid_index(i));
      const Mat3& R = s.R[k];
      const Vec3 d_body = R.transpose() * d;
      if (dn < w.choice.check_below[i]) watch(i, d_body, w, s.t);
      // (35.5): the series of §13 with the body as A, the prescribed point mass as B, in A's frame.
      const noether::MutualTerms terms = w.bank.at(order).evaluate(G, integrals_[i], point_, d_body, Mat3::Identity());
      out.f.col(c) = R * terms.dU_dR;
      out.M.col(static_cast<Eigen::Index>(k)) = terms.torque_A;
    }
  }

 private:
  // Each rigid body's order from the tolerance at the closest the conic comes to it (35.6): the
  // conic's periapsis about its center less the body's distance from the center at `s`, × 0.9 —
  // or min_separation.
  void choose(const State& s, noether::SeriesBank& bank, Choice& c) const {
    const double periapsis = conic_.orbit().periapsis();
    const Vec3 center = conic_.center(s);
    for (std::size_t i = 0; i < system_.size(); ++i) {
      if (!system_.body(i).rigid) continue;
      const double offset = (Vec3(s.x.col(static_cast<Eigen::Index>(i))) - center).norm();
      const double closest = min_separation_ > 0.0 ? min_separation_ : 0.9 * (periapsis - offset);
      const std::string& name = system_.body(i).name;
      if (!(closest > radius_[i])) {
        std::ostringstream msg;
        msg << tolerance_where_ << "prescribed-body: its conic comes within " << closest << " of body '" << name
            << "' (radius " << radius_[i] << "), where the series need not converge: give min_separation if it "
            << "never comes that close, a fixed order, or integrate the body with mutual-exact";
        throw SceneError(msg.str());
      }
      const noether::OrderChoice choice = noether::choose_series_order(
          bank, system_.G(), integrals_[i], point_, radius_[i], 0.0, closest, Vec3::UnitX(), Mat3::Identity(), selection_);
      if (!choice.met) {
        std::ostringstream msg;
        msg << tolerance_where_ << "prescribed-body: no order up to max_order " << selection_.max_order
            << " meets the tolerance " << selection_.tolerance << " for body '" << name << "' at " << closest
            << " (estimated at " << choice.estimated_error
            << "): raise max_order, loosen the tolerance, or give min_separation if it never comes that close";
        throw SceneError(msg.str());
      }
      c.order[i] = choice.order;
      c.check_below[i] = closest;
      noether::PairModel report;
      report.body_a = name;
      report.body_b = "prescribed-body" + (name_.empty() ? std::string() : " " + name_);
      report.order = choice.order;
      report.model = choice.order == 0 ? "point masses" : "series order " + std::to_string(choice.order);
      report.tolerance = selection_.tolerance;
      report.estimated_error = choice.estimated_error;
      report.separation = closest;
      c.report.push_back(std::move(report));
    }
  }

  // Closer than its order was chosen for: the error estimate (15.2) here, which must still meet the
  // tolerance, or the run stops.
  void watch(std::size_t i, const Vec3& d_body, SeriesWorkspace& w, double t) const {
    const double dn = d_body.norm();
    w.choice.check_below[i] = 0.99 * dn;  // again only once it is 1 % closer
    const double estimate = noether::series_error_estimate(w.bank, w.choice.order[i], system_.G(), integrals_[i], point_,
                                                           radius_[i], 0.0, d_body, Mat3::Identity());
    if (estimate <= selection_.tolerance) return;
    std::ostringstream msg;
    msg << "prescribed-body: it came within " << dn << " of body '" << system_.body(i).name
        << "', where the error of series order " << w.choice.order[i] << " is estimated at " << estimate
        << ", above the tolerance " << selection_.tolerance
        << ": give a smaller min_separation (the closest it comes) or a fixed order";
    throw noether::IntegrationError(msg.str(), t);
  }

  // Body i's bounding sphere meets the prescribed body's (a point when it has no radius).
  [[noreturn]] void collision(std::size_t i, double distance, double t) const {
    std::ostringstream msg;
    msg << "prescribed-body" << (name_.empty() ? "" : " " + name_) << ": body '" << system_.body(i).name
        << "' came within " << distance << " of its centre";
    if (surface_radius_ > 0.0 || system_.body(i).radius > 0.0)
      msg << ", less than its radius " << surface_radius_ << " and the body's " << system_.body(i).radius;
    msg << ": the bodies collide, which noether does not model (check the conic's position and velocity)";
    throw noether::IntegrationError(msg.str(), t);
  }

  static double positive_mass(const Params& p) {
    const double m = p.at("mass").as_double();
    if (!(m > 0) || !std::isfinite(m)) throw SceneError(p.at("mass").here() + "prescribed-body: mass must be positive");
    return m;
  }

  System system_;
  double mass_;
  noether::PrescribedConic conic_;
  noether::InertiaIntegrals point_;                // the prescribed body's: a point mass M
  int order_ = 2;                                  // the fixed order (rigid bodies)
  noether::OrderSelection selection_{0.0, 12, 24, 1};  // tolerance 0: a fixed order
  double min_separation_ = 0.0;
  std::string name_;
  double surface_radius_ = 0.0;  // `radius` (0: a point)
  std::string tolerance_where_;
  std::vector<noether::InertiaIntegrals> integrals_;  // per body (rigid: to the order needed)
  std::vector<double> radius_;                        // per body (integrals_radius)
  std::optional<Choice> chosen_;                      // at the scene's initial state (choose_models)
};

const noether::ParamDoc params[] = {
    {"name", "string", "(none)", "what the summary and the output call it: \"prescribed-body NAME\""},
    {"mass", "number", nullptr, "its mass M, in the scene's unit of mass"},
    {"radius", "number", "(none: a point)",
     "its radius R: massless particles that reach it land on it, and a body whose bounding sphere meets it stops the run"},
    {"position", "list", nullptr, "its position at `epoch` relative to `center`, [x, y, z]"},
    {"velocity", "list", nullptr, "its velocity at `epoch` relative to `center`, [vx, vy, vz]"},
    {"epoch", "number", "0", "the time of `position` and `velocity`"},
    {"center", "string", "barycentre",
     "what its conic is relative to: barycentre (the scene's, where the run stands), a body's name, or origin"},
    {"mu", "number", "(G (mass + the center's mass; the scene's total for barycentre))",
     "the gravitational parameter of its conic (required for center: origin)"},
    {"order", "integer", "2",
     "the mutual series' order N on rigid bodies, 0..12: 0 point masses, 2 quadrupoles (force and gravity-gradient "
     "torque); or give 'tolerance'"},
    {"tolerance", "number", "(none)",
     "choose each rigid body's order instead: the lowest whose estimated relative error of force and torque meets it "
     "at the closest the conic comes to the body (docs/forces.md)"},
    {"max_order", "integer", "12", "with tolerance: the highest order it may choose"},
    {"min_separation", "number", "(0.9 × (the conic's periapsis − the body's distance from its center))",
     "with tolerance: the closest the prescribed body comes to any rigid body"},
};

std::unique_ptr<noether::ForceModel> make(const System& system, const Params& p) {
  return std::make_unique<PrescribedBody>(system, p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Force,
    "prescribed-body",
    "the gravity of a body on a prescribed Kepler conic, not integrated (a planetary flyby, the Sun)",
    params,
    std::size(params),
    nullptr,
    nullptr,
    &make};
