#pragma once
// DerivedError: the error a run estimates for a number it derives from its trajectory (a period,
// a ΔP, a libration amplitude; docs/user-guide.md "Verdict"), by the run repeated at half the
// step (host/src/run/derived_check.cpp).
#include <cmath>
#include <limits>
#include <string>

namespace noether {

// Q(h) − Q(h/2) times 2^p / (2^p − 1) (Richardson, for the method's order p; an order the
// method does not declare: times 2, the bound for any p ≥ 1).
struct DerivedError {
  double error = std::numeric_limits<double>::quiet_NaN();         // |Q(h) − Q*| estimated; NaN: not
  double at_half_step = std::numeric_limits<double>::quiet_NaN();  // Q(h/2)
  double step = 0.0;  // h
  int order = 0;      // p used (0: not declared: the factor 2)
  std::string why_not;  // when it was not estimated, why (empty when it was, or nothing was derived)
  bool estimated() const { return !std::isnan(error); }
  std::string method() const;  // "the run repeated at half the step, Richardson order 2"
};

}  // namespace noether
