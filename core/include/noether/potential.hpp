#pragma once
// Potential: a gravitational model U(x_1..x_n, R_1..R_n) and its derivatives (docs/equations.md §2).
#include <noether/export.hpp>
#include <noether/forces.hpp>
#include <noether/state.hpp>

#include <memory>
#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// What a model chose for one pair of bodies, and whether the run stayed where the choice
// holds (tolerance-driven models; docs/equations.md §15).
struct PairModel {
  std::string body_a, body_b;
  std::string model;             // e.g. "point masses", "series order 6"
  int order = 0;
  double tolerance = 0.0;        // the error bound asked for (15.1)
  double estimated_error = 0.0;  // the estimate (15.2) at `separation`
  double separation = 0.0;       // the closest separation the choice was made for
  // Set when the bodies came closer than `separation` and the estimate there exceeded the
  // tolerance (the first time).
  bool exceeded = false;
  double exceeded_time = 0.0, exceeded_separation = 0.0, exceeded_error = 0.0;
};

class NOETHER_API Potential {
 public:
  virtual ~Potential();
  // Fills U, f_i = −∂U/∂x_i and, for rigid bodies, the body-frame moments M_k.
  // `forces` is already sized for the system; implementations overwrite every entry.
  virtual void evaluate(const State& state, Forces& forces) const = 0;
  // The model chosen for each pair, for models that choose (none by default).
  virtual std::vector<PairModel> pair_models() const;
  // Optional: the Hessian ∂²U/∂x∂x of U in the body positions (3n × 3n, body-major), for the
  // variational equations of periodic orbits (docs/equations.md §9). Returns false (the
  // default) when the model does not provide it; callers then difference the forces.
  virtual bool position_hessian(const State& state, Eigen::MatrixXd& hessian) const;
};

// The sum of several models: U = Σ U_m, forces and moments add.
class NOETHER_API SumPotential final : public Potential {
 public:
  explicit SumPotential(std::vector<std::shared_ptr<const Potential>> terms);
  void evaluate(const State& state, Forces& forces) const override;
  std::vector<PairModel> pair_models() const override;
  bool position_hessian(const State& state, Eigen::MatrixXd& hessian) const override;

 private:
  std::vector<std::shared_ptr<const Potential>> terms_;
  mutable Forces scratch_;
};

}  // namespace noether

#pragma GCC visibility pop
