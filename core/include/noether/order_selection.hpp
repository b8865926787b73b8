#pragma once
// Choosing the order of the mutual series from a tolerance (docs/equations.md §15): the error
// measure the tolerance bounds, its next-terms estimate, and the lowest order that meets it
// at the closest separation a pair is expected to reach.
#include <noether/inertia_integrals.hpp>
#include <noether/mutual_series.hpp>

#include <map>
#include <memory>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The error of `approx` against `exact` that a tolerance bounds (15.1): the largest of the
// relative force error |ΔF|/|F| and the torque errors |Δτ_A|, |Δτ_B| against the pair's
// torque scale R|F| (the moment of its force at its separation R).
double mutual_error(const MutualTerms& approx, const MutualTerms& exact, double separation);

// Series evaluators of every order, made on demand (each keeps its scratch).
class SeriesBank {
 public:
  MutualSeries& at(int order);

 private:
  std::map<int, std::unique_ptr<MutualSeries>> series_;
};

struct OrderSelection {
  double tolerance = 1e-6;
  int max_order = 12;
  int samples = 24;     // relative attitudes and directions sampled at the separation
  unsigned seed = 1;
};

struct OrderChoice {
  int order = 0;                 // the lowest N whose estimate meets the tolerance (0: point masses)
  double estimated_error = 0.0;  // its estimate (15.2), worst over the samples
  bool met = false;              // false: no order up to max_order met the tolerance
};

// The next-terms estimate of the error of order N at one configuration (15.2):
// s · mutual_error(U_N, U_{N+2}) with the safety factor s = 2, or 3 when (ρ_A + ρ_B)/R > 0.8.
// The integrals must reach order N + 2.
double series_error_estimate(SeriesBank& bank, int order, double G, const InertiaIntegrals& TA,
                                         const InertiaIntegrals& TB, double radius_A, double radius_B,
                                         const Vec3& R, const Mat3& C);

// The lowest order meeting the tolerance at separation `separation`, worst case over the
// given configuration (direction of R and relative attitude C) and `samples − 1` random ones
// (15.3). Integrals of order max_order + 2 are needed.
OrderChoice choose_series_order(SeriesBank& bank, double G, const InertiaIntegrals& TA,
                                            const InertiaIntegrals& TB, double radius_A, double radius_B,
                                            double separation, const Vec3& direction, const Mat3& C,
                                            const OrderSelection& options);

}  // namespace noether

#pragma GCC visibility pop
