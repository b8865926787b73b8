#pragma once
// Potential: a gravitational model U(x_1..x_n, R_1..R_n) and its derivatives (docs/equations.md §2).
#include <noether/export.hpp>
#include <noether/forces.hpp>
#include <noether/state.hpp>

#include <memory>
#include <string>
#include <vector>

namespace noether {

class NOETHER_API Potential {
 public:
  virtual ~Potential() = default;
  // Fills U, f_i = −∂U/∂x_i and, for rigid bodies, the body-frame moments M_k.
  // `forces` is already sized for the system; implementations overwrite every entry.
  virtual void evaluate(const State& state, Forces& forces) const = 0;
  // Whether U depends on the attitudes (a point-mass model does not).
  virtual bool needs_attitudes() const = 0;
};

// The sum of several models: U = Σ U_m, forces and moments add.
class NOETHER_API SumPotential final : public Potential {
 public:
  explicit SumPotential(std::vector<std::shared_ptr<const Potential>> terms);
  void evaluate(const State& state, Forces& forces) const override;
  bool needs_attitudes() const override;

 private:
  std::vector<std::shared_ptr<const Potential>> terms_;
  mutable Forces scratch_;
};

}  // namespace noether
