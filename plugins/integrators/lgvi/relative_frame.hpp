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

namespace lgvi {

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
  // U and its reduced derivatives at (X, R): one potential evaluation, at x1 = X, x2 = 0,
  // R1 = R, R2 = I (U depends on the relative configuration only).
  void evaluate(const Reduced& r, ReducedForces& f);
  // The inertial forces of a reduced evaluation (f rotated by R2; body-frame M unchanged).
  void inertial_forces(const Reduced& r, const ReducedForces& rf, Forces& f) const;

  double m1, m2, m;         // masses and reduced mass
  Mat3 J1, J2, Jd2;         // body inertia (J1 in body 1's frame)
  std::string name1, name2;

 private:
  System system_;
  noether::PotentialEvaluator& evaluate_;
  State canonical_;  // scratch
};

}  // namespace lgvi
