#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>

#include <cmath>

namespace noether {

ContinuousEquations::~ContinuousEquations() = default;

namespace {

// What every form holds: the system, the potential with this form's own workspace, and the
// count of evaluations.
class Form : public ContinuousEquations {
 public:
  Form(const System& system, std::shared_ptr<const Potential> potential)
      : system_(system), evaluate_(std::move(potential)) {
    forces_.resize(system_);
  }
  void forces(const State& state, Forces& forces) override {
    forces.resize(system_);
    evaluate_(state, forces);
  }
  std::int64_t evaluations() const override { return evaluations_; }
  const System& system() const override { return system_; }
  PotentialEvaluator& evaluator() override { return evaluate_; }

 protected:
  // One counted evaluation into forces_.
  void evaluate_counted(const State& state) {
    evaluate_(state, forces_);
    ++evaluations_;
  }
  System system_;
  PotentialEvaluator evaluate_;
  Forces forces_;
  std::int64_t evaluations_ = 0;
};

using Map3 = Eigen::Map<Vec3>;
using CMap3 = Eigen::Map<const Vec3>;
using MapM = Eigen::Map<Mat3>;
using CMapM = Eigen::Map<const Mat3>;

// Inertial frame, any number of bodies. Layout: [x (3n) | γ or v (3n) | R (9 per rigid body) |
// Π or Ω (3 per rigid body)].
class Inertial final : public Form {
 public:
  Inertial(const System& system, std::shared_ptr<const Potential> potential, bool lagrangian)
      : Form(system, std::move(potential)), lagrangian_(lagrangian),
        n_(system.size()), nr_(system.rigid_count()), scratch_(State::zeros(system)) {}
  std::size_t size() const override { return 6 * n_ + 12 * nr_; }

  void pack(const State& s, double* y) const override {
    for (std::size_t i = 0; i < n_; ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      Map3(y + 3 * i) = s.x.col(c);
      Map3(y + 3 * n_ + 3 * i) = lagrangian_ ? Vec3(s.p.col(c) / system_.body(i).mass) : Vec3(s.p.col(c));
    }
    for (std::size_t k = 0; k < nr_; ++k) {
      MapM(y + 6 * n_ + 9 * k) = s.R[k];
      const Vec3 Pi = s.Pi.col(static_cast<Eigen::Index>(k));
      Map3(y + 6 * n_ + 9 * nr_ + 3 * k) =
          lagrangian_ ? Vec3(system_.body(system_.body_of_rigid(k)).inertia_inverse * Pi) : Pi;
    }
  }

  void unpack(const double* y, double t, State& s) const override {
    s.t = t;
    s.x.resize(3, static_cast<Eigen::Index>(n_));
    s.p.resize(3, static_cast<Eigen::Index>(n_));
    s.R.resize(nr_);
    s.Pi.resize(3, static_cast<Eigen::Index>(nr_));
    for (std::size_t i = 0; i < n_; ++i) {
      const auto c = static_cast<Eigen::Index>(i);
      s.x.col(c) = CMap3(y + 3 * i);
      const Vec3 w = CMap3(y + 3 * n_ + 3 * i);
      s.p.col(c) = lagrangian_ ? Vec3(system_.body(i).mass * w) : w;
    }
    for (std::size_t k = 0; k < nr_; ++k) {
      s.R[k] = CMapM(y + 6 * n_ + 9 * k);
      const Vec3 w = CMap3(y + 6 * n_ + 9 * nr_ + 3 * k);
      s.Pi.col(static_cast<Eigen::Index>(k)) =
          lagrangian_ ? Vec3(system_.body(system_.body_of_rigid(k)).inertia * w) : w;
    }
  }

  void rhs(double t, const double* y, double* dydt) override {
    unpack(y, t, scratch_);
    evaluate_counted(scratch_);
    for (std::size_t i = 0; i < n_; ++i) {
      const double m = system_.body(i).mass;
      const Vec3 f = forces_.f.col(static_cast<Eigen::Index>(i));
      const Vec3 w = CMap3(y + 3 * n_ + 3 * i);
      Map3(dydt + 3 * i) = lagrangian_ ? w : Vec3(w / m);      // ẋ = v = γ/m      (27), (31)
      Map3(dydt + 3 * n_ + 3 * i) = lagrangian_ ? Vec3(f / m) : f;  // m v̇ = γ̇ = −∂U/∂x (25), (29)
    }
    for (std::size_t k = 0; k < nr_; ++k) {
      const Body& b = system_.body(system_.body_of_rigid(k));
      const Vec3 M = forces_.M.col(static_cast<Eigen::Index>(k));
      const Vec3 w = CMap3(y + 6 * n_ + 9 * nr_ + 3 * k);
      const Vec3 Omega = lagrangian_ ? w : Vec3(b.inertia_inverse * w);
      MapM(dydt + 6 * n_ + 9 * k) = scratch_.R[k] * hat(Omega);  // Ṙ = R S(Ω)   (28), (32)
      if (lagrangian_)
        Map3(dydt + 6 * n_ + 9 * nr_ + 3 * k) =
            b.inertia_inverse * (Vec3(b.inertia * Omega).cross(Omega) + M);  // (26)
      else
        Map3(dydt + 6 * n_ + 9 * nr_ + 3 * k) = w.cross(Omega) + M;        // (30)
    }
  }

  std::vector<std::size_t> rotation_offsets() const override {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < nr_; ++k) out.push_back(6 * n_ + 9 * k);
    return out;
  }

 private:
  bool lagrangian_;
  std::size_t n_, nr_;
  State scratch_;
};

// Relative frame, two rigid bodies. Layout: [X | Γ or V | R (9) | Π or ω | Π2 or Ω2 |
// x2 | γ2 or v2 | R2 (9)].
class Relative final : public Form {
 public:
  enum : std::size_t { kX = 0, kG = 3, kR = 6, kPi = 15, kPi2 = 18, kx2 = 21, kg2 = 24, kR2 = 27, kSize = 36 };

  Relative(const System& system, std::shared_ptr<const Potential> potential, bool lagrangian)
      : Form(system, std::move(potential)), lagrangian_(lagrangian),
        canonical_(State::zeros(system)) {
    if (system.size() != 2 || system.rigid_count() != 2)
      throw SceneError("frame: relative needs exactly two rigid bodies (the full two-body "
                       "problem); this scene has " + std::to_string(system.size()) + " bodies, " +
                       std::to_string(system.rigid_count()) + " rigid. Use frame: inertial");
    m1_ = system.body(0).mass;
    m2_ = system.body(1).mass;
    m_ = m1_ * m2_ / (m1_ + m2_);
    J1_ = system.body(0).inertia;
    J2_ = system.body(1).inertia;
  }
  std::size_t size() const override { return kSize; }

  void pack(const State& s, double* y) const override {
    const Mat3 R2 = s.R[1], R2t = R2.transpose();
    const Mat3 R = R2t * s.R[0];
    const Vec3 Gamma = m_ * (R2t * Vec3(s.p.col(0) / m1_ - s.p.col(1) / m2_));
    const Vec3 Pi = R * Vec3(s.Pi.col(0)), Pi2 = s.Pi.col(1);
    Map3(y + kX) = R2t * Vec3(s.x.col(0) - s.x.col(1));
    Map3(y + kG) = lagrangian_ ? Vec3(Gamma / m_) : Gamma;
    MapM(y + kR) = R;
    Map3(y + kPi) = lagrangian_ ? Vec3((R * J1_ * R.transpose()).ldlt().solve(Pi)) : Pi;
    Map3(y + kPi2) = lagrangian_ ? Vec3(J2_.ldlt().solve(Pi2)) : Pi2;
    Map3(y + kx2) = s.x.col(1);
    Map3(y + kg2) = lagrangian_ ? Vec3(s.p.col(1) / m2_) : Vec3(s.p.col(1));
    MapM(y + kR2) = R2;
  }

  void unpack(const double* y, double t, State& s) const override {
    const Mat3 R = CMapM(y + kR), R2 = CMapM(y + kR2);
    const Vec3 X = CMap3(y + kX), x2 = CMap3(y + kx2);
    const Vec3 Gamma = lagrangian_ ? Vec3(m_ * CMap3(y + kG)) : Vec3(CMap3(y + kG));
    const Vec3 gamma2 = lagrangian_ ? Vec3(m2_ * CMap3(y + kg2)) : Vec3(CMap3(y + kg2));
    const Vec3 Pi = lagrangian_ ? Vec3(R * J1_ * R.transpose() * CMap3(y + kPi)) : Vec3(CMap3(y + kPi));
    const Vec3 Pi2 = lagrangian_ ? Vec3(J2_ * CMap3(y + kPi2)) : Vec3(CMap3(y + kPi2));
    s = State::zeros(system_);
    s.t = t;
    s.x.col(1) = x2;
    s.p.col(1) = gamma2;
    s.R[1] = R2;
    s.x.col(0) = x2 + R2 * X;
    s.p.col(0) = m1_ * (gamma2 / m2_ + R2 * Gamma / m_);
    s.R[0] = R2 * R;
    s.Pi.col(0) = R.transpose() * Pi;
    s.Pi.col(1) = Pi2;
  }

  void rhs(double t, const double* y, double* dydt) override {
    const Vec3 X = CMap3(y + kX);
    const Mat3 R = CMapM(y + kR), R2 = CMapM(y + kR2);
    // U and its reduced derivatives at x1 = X, x2 = 0, R1 = R, R2 = I.
    canonical_.t = t;
    canonical_.x.col(0) = X;
    canonical_.x.col(1).setZero();
    canonical_.R[0] = R;
    canonical_.R[1].setIdentity();
    evaluate_counted(canonical_);
    const Vec3 dU_dX = -forces_.f.col(0);
    const Vec3 M = R * Vec3(forces_.M.col(0));
    const Vec3 M2 = forces_.M.col(1);  // = X × ∂U/∂X − M, evaluated without cancellation
    const Mat3 JR = R * J1_ * R.transpose();
    const Vec3 w = CMap3(y + kPi), w2 = CMap3(y + kPi2), g = CMap3(y + kG), g2 = CMap3(y + kg2);
    const Vec3 omega = lagrangian_ ? w : Vec3(JR.ldlt().solve(w));
    const Vec3 Omega2 = lagrangian_ ? w2 : Vec3(J2_.ldlt().solve(w2));
    const Vec3 V = lagrangian_ ? g : Vec3(g / m_);
    Map3(dydt + kX) = V + X.cross(Omega2);                                 // (58)
    Map3(dydt + kG) = lagrangian_ ? Vec3(V.cross(Omega2) - dU_dX / m_)     // (55)
                                  : Vec3(g.cross(Omega2) - dU_dX);
    MapM(dydt + kR) = (hat(omega) - hat(Omega2)) * R;                      // (59)
    if (lagrangian_) {
      Map3(dydt + kPi) = JR.ldlt().solve(Vec3(M - omega.cross(JR * omega))) - Omega2.cross(omega);  // (56)
      Map3(dydt + kPi2) = J2_.ldlt().solve(Vec3(M2 - Omega2.cross(J2_ * Omega2)));                  // (57)
    } else {
      Map3(dydt + kPi) = w.cross(Omega2) + M;
      Map3(dydt + kPi2) = w2.cross(Omega2) + M2;
    }
    Map3(dydt + kx2) = lagrangian_ ? g2 : Vec3(g2 / m2_);                  // (61)
    Map3(dydt + kg2) = lagrangian_ ? Vec3(R2 * dU_dX / m2_) : Vec3(R2 * dU_dX);  // (60)
    MapM(dydt + kR2) = R2 * hat(Omega2);                                   // (62)
  }

  std::vector<std::size_t> rotation_offsets() const override { return {kR, kR2}; }

 private:
  bool lagrangian_;
  double m1_, m2_, m_;
  Mat3 J1_, J2_;
  State canonical_;
};

}  // namespace

std::unique_ptr<ContinuousEquations> make_continuous_equations(
    const System& system, std::shared_ptr<const Potential> potential, const std::string& frame,
    const std::string& form) {
  if (form != "hamiltonian" && form != "lagrangian")
    throw SceneError("form must be hamiltonian or lagrangian, not '" + form + "'");
  const bool lagrangian = form == "lagrangian";
  if (frame == "inertial") return std::make_unique<Inertial>(system, std::move(potential), lagrangian);
  if (frame == "relative") return std::make_unique<Relative>(system, std::move(potential), lagrangian);
  throw SceneError("frame must be inertial or relative, not '" + frame + "'");
}

}  // namespace noether
