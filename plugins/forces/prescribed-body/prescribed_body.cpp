// prescribed-body: the gravity of a body that moves on a prescribed conic and is not integrated
// (a planet passing a binary asteroid, the Sun about it; docs/forces.md, docs/equations.md §35).
// Its position is X(t) = c(t) + ρ(t): ρ a Kepler conic (KeplerOrbit) from the relative state
// given at `epoch`, about c — the scene's barycentre where the run stands (default), a body, or
// the origin. Every body i feels it as a point mass M,
//
//   f_i = G M m_i d_i / |d_i|³,   d_i = X − x_i,                                               (35.4)
//
// and with order 2 each rigid body also its quadrupole's share (MacCullagh's potential
// U2 = −(G M / 2)(tr J / d³ − 3 dᵀ J_in d / d⁵), J_in = R J Rᵀ): the force ∂U2/∂d and the
// gravity-gradient torque 3 G M (d_b × J d_b) / d⁵ in the body frame, d_b = Rᵀ d          (35.5)
//
// The prescribed body feels nothing back: the scene's momenta change by what it puts in, which
// the balance records (docs/equations.md eq. 33.3).
#include <noether/error.hpp>
#include <noether/prescribed_conic.hpp>
#include <noether/plugin.hpp>

#include <cmath>
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

class PrescribedBody final : public noether::ForceModel {
 public:
  PrescribedBody(const System& system, const Params& p)
      : system_(system), mass_(positive_mass(p)), conic_(system, p, mass_, "prescribed-body") {
    order_ = static_cast<int>(p.at("order").as_int());
    if (order_ != 0 && order_ != 2) throw SceneError(p.at("order").here() + "prescribed-body: order must be 0 or 2");
  }

  bool depends_on_momenta() const override { return false; }

  void evaluate(const State& s, Forces& out, noether::Workspace&) const override {
    out.set_zero();
    const Vec3 X = conic_.position(s);
    const double GM = system_.G() * mass_;
    for (std::size_t i = 0; i < system_.size(); ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      const Vec3 d = X - Vec3(s.x.col(c));
      const double d2 = d.squaredNorm(), dn = std::sqrt(d2);
      if (!(dn > 0)) throw noether::IntegrationError("prescribed-body: a body reached the prescribed body", s.t);
      Vec3 f = (GM * system_.body(i).mass / (d2 * dn)) * d;  // (35.4)
      const int k = system_.rigid_index(i);
      if (order_ == 2 && k >= 0) {  // (35.5)
        const Mat3& R = s.R[static_cast<std::size_t>(k)];
        const Mat3& J = system_.body(i).inertia;
        const Vec3 db = R.transpose() * d, Jdb = J * db;
        const double d5 = d2 * d2 * dn, dJd = db.dot(Jdb);
        const Vec3 Jd = R * Jdb;
        f += -0.5 * GM * (-3.0 * J.trace() * d / d5 - 6.0 * Jd / d5 + 15.0 * dJd * d / (d5 * d2));
        out.M.col(k) = (3.0 * GM / d5) * db.cross(Jdb);
      }
      out.f.col(c) = f;
    }
  }

 private:
  static double positive_mass(const Params& p) {
    const double m = p.at("mass").as_double();
    if (!(m > 0) || !std::isfinite(m)) throw SceneError(p.at("mass").here() + "prescribed-body: mass must be positive");
    return m;
  }

  System system_;
  double mass_;
  noether::PrescribedConic conic_;
  int order_ = 2;
};

const noether::ParamDoc params[] = {
    {"name", "string", "(none)", "what the summary and the output call it: \"prescribed-body NAME\""},
    {"mass", "number", nullptr, "its mass M, in the scene's unit of mass"},
    {"position", "list", nullptr, "its position at `epoch` relative to `center`, [x, y, z]"},
    {"velocity", "list", nullptr, "its velocity at `epoch` relative to `center`, [vx, vy, vz]"},
    {"epoch", "number", "0", "the time of `position` and `velocity`"},
    {"center", "string", "barycentre",
     "what its conic is relative to: barycentre (the scene's, where the run stands), a body's name, or origin"},
    {"mu", "number", "(G (mass + the center's mass; the scene's total for barycentre))",
     "the gravitational parameter of its conic (required for center: origin)"},
    {"order", "integer", "2", "0: point masses; 2: also each rigid body's quadrupole — force and gravity-gradient torque"},
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
