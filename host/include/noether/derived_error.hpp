#pragma once
// DerivedError: the error a run estimates for a number it derives from its trajectory (a period,
// a ΔP, a libration amplitude; docs/user-guide.md "Verdict"), by the run repeated finer
// (host/src/run/derived_check.cpp).
#include <cmath>
#include <limits>
#include <string>

namespace noether {

// A fixed-step method: Q(h) − Q(h/2) times 2^p / (2^p − 1) (Richardson, for the method's order
// p; an order the method does not declare: times 2, the bound for any p ≥ 1).
// A method that chooses its steps under a tolerance: Q(tol) − Q(tol/10) divided by
// 1 − 10^−q, q = p / (p + 1) (an error-per-step control takes steps ~ tol^(1/(p+1)), so the
// global error goes as tol^q; not declared: times 2, the bound for any q ≥ 0.3); where tol/10 is
// below 1e-14, which double precision does not meet, Q(10 tol) − Q(tol) itself, an upper bound.
struct DerivedError {
  double error = std::numeric_limits<double>::quiet_NaN();         // |Q − Q*| estimated; NaN: not
  double at_half_step = std::numeric_limits<double>::quiet_NaN();  // Q at h/2 (or at the other tolerance)
  double step = 0.0;              // h (0: a method that chooses its steps)
  double tolerance = 0.0;         // the run's rtol, for such a method
  double tolerance_factor = 0.0;  // the other run's rtol over it: 0.1 or 10
  int order = 0;                  // p used (0: not declared)
  std::string why_not;  // when it was not estimated, why (empty when it was, or nothing was derived)
  bool estimated() const { return !std::isnan(error); }
  // "the run repeated at half the step, Richardson order 2", "the run repeated at a tenfold
  // tighter tolerance, order 8"
  std::string method() const;
  // The exponent q of the error's law in what is refined: p for a step, p / (p + 1) for a
  // tolerance; where p is not declared, 1 and 0.5 (a step or tolerance small enough for any
  // larger q).
  double exponent() const;
};

}  // namespace noether
