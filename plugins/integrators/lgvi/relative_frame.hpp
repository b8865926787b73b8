#pragma once
// The relative (reduced) variables of the full two-body problem (Lee, Leok & McClamroch 2007 §3.2, §4.2;
// docs/equations.md §5), all in the frame of body 2:
//   X = R2ᵀ(x1 − x2),  Γ = m R2ᵀ(v1 − v2) with m = m1 m2/(m1 + m2),  R = R2ᵀ R1,
//   Π = R Π1 (body 1's angular momentum seen from body 2),  Π2,
// plus body 2's inertial (x2, γ2, R2) for reconstruction.
//
// Sign convention (differs from Lee et al. (2007), whose relative M is the negative of ours): M = R M1
// is the gravitational moment on body 1 expressed in body 2's frame, and the moment on body 2
// is M2 = X × ∂U/∂X − M. Derivation: under R2 → R2 exp(ε S(η)), X → X − ε η × X and
// R → exp(−ε S(η)) R, so −dU/dε = η · (X × ∂U/∂X − R M1).
#include "discrete_flow.hpp"
#include "tangent_map.hpp"

namespace lgvi {

class ForcingKicks;

struct Reduced {
  double t = 0;
  Vec3 X, Gamma, Pi, Pi2;
  Mat3 R;
  Vec3 x2, gamma2;
  Mat3 R2;
};

// The reduced variables as 37 doubles and back (checkpoints), in the order of the struct.
void pack(const Reduced& r, std::vector<double>& out);
Reduced unpack(const std::vector<double>& in, std::size_t offset = 0);
constexpr std::size_t kReducedSize = 37;

struct ReducedForces {
  double U = 0;
  Vec3 dU_dX;  // ∂U/∂X
  Vec3 M;      // R M1: moment on body 1, body-2 frame
  Vec3 M2;     // = X × ∂U/∂X − M: moment on body 2, body-2 frame   ((121), (124))
  Forces inertial;  // at the canonical configuration x2 = 0, R2 = I (scratch)
};

class RelativeFrame {
 public:
  RelativeFrame(const System& system, noether::PotentialEvaluator& evaluate);
  Reduced reduce(const State& s) const;
  void reconstruct(const Reduced& r, State& s) const;
  // x1 = x2 + R2 X and x2, as the columns of a 3 × 2 matrix.
  static Eigen::Matrix3Xd positions(const Reduced& r);
  // U and its reduced derivatives at (X, R): one potential evaluation, at x1 = X, x2 = 0,
  // R1 = R, R2 = I (U depends on the relative configuration only).
  void evaluate(const Reduced& r, ReducedForces& f);
  // The inertial forces of a reduced evaluation (f rotated by R2; body-frame M unchanged).
  void inertial_forces(const Reduced& r, const ReducedForces& rf, Forces& f) const;

  const System& system() const { return system_; }

  double m1, m2, m;         // masses and reduced mass
  Mat3 J1, J2, Jd2;         // body inertia (J1 in body 1's frame)
  std::string name1, name2;

 private:
  System system_;
  noether::PotentialEvaluator& evaluate_;
  State canonical_;  // scratch
};

// The tangent map of a relative-frame step. The relative forms reduce the inertial map by its
// symmetry and reproduce it for the same h (docs/equations.md §5), so the map z_k → z_{k+1} of
// the reconstructed inertial states is the inertial Hamiltonian form's, and so is its derivative:
// the tangent, in the inertial coordinates (21.1), is carried by (21.2)–(21.8) with that step's
// inertial F_k (body 1: R_kᵀ F R_k; body 2: F2_k), w_k and force Jacobians at the reconstructed
// states; with forces beyond the potential, the kicks' maps (33.6)–(33.7) around it, as in the
// inertial forms (the reduced kicks (33.11) are the inertial kicks in other variables).
class RelativeTangent {
 public:
  bool carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) {
    return carrier_.carry_parameters(std::move(parameters));
  }
  bool carried() const { return V_.size() > 0; }
  const Eigen::MatrixXd& tangent() const { return V_; }
  // At a start (or a restore): the tangent `s` carries, and K (and G) at the reduced state.
  void start(const State& s, const Reduced& r, const RelativeFrame& frame, noether::PotentialEvaluator& evaluate,
             noether::WorkCounters& work);
  // Before the step from r_k (forces fk) with the step's relative F (body 1) and F2: F_k and w_k.
  void before(const Reduced& r, const ReducedForces& fk, const Mat3& F, const Mat3& F2, double h);
  // At r_{k+1}, after the step's evaluation there: K (and G) at the reconstructed state. May
  // throw; nothing is then changed but scratch.
  void at_next(const Reduced& next, const RelativeFrame& frame, noether::PotentialEvaluator& evaluate,
               noether::WorkCounters& work);
  // V ← (∂z_{k+1}/∂z_k) V, once the step from r_k to r_{k+1} is taken.
  void advance(const Reduced& r_k, const Reduced& next, const System& system, double h);
  // With forces beyond the potential (relative_kicks.hpp): the kicks' tangent maps (33.6)–(33.7)
  // at r's reconstructed state — before the opening kick at r_k, after the closing kick at r_{k+1}.
  void open_kick(ForcingKicks& kicks, const Reduced& r, const RelativeFrame& frame, double h);
  void close_kick(ForcingKicks& kicks, const Reduced& r, const RelativeFrame& frame, double h);
  // Sets V back (a failed step).
  void set_tangent(const Eigen::MatrixXd& V) { V_ = V; }

 private:
  TangentCarrier carrier_;
  Eigen::MatrixXd V_;
  State inertial_;  // scratch: a reconstructed state carrying V (the carrier evaluates only when it has one)
  std::vector<Mat3> F_{2};
  Eigen::Matrix3Xd w_ = Eigen::Matrix3Xd::Zero(3, 2);
};

}  // namespace lgvi
