#include <noether/error.hpp>
#include <noether/order_selection.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace noether {

double mutual_error(const MutualTerms& approx, const MutualTerms& exact, double separation) {
  const double F = exact.dU_dR.norm();
  if (!(F > 0.0)) return 0.0;
  const double torque = separation * F;
  return std::max({(approx.dU_dR - exact.dU_dR).norm() / F, (approx.torque_A - exact.torque_A).norm() / torque,
                   (approx.torque_B - exact.torque_B).norm() / torque});
}

MutualSeries& SeriesBank::at(int order) {
  auto& s = series_[order];
  if (!s) s = std::make_unique<MutualSeries>(order);
  return *s;
}

double series_error_estimate(SeriesBank& bank, int order, double G, const InertiaIntegrals& TA,
                             const InertiaIntegrals& TB, double radius_A, double radius_B, const Vec3& R,
                             const Mat3& C) {
  const MutualTerms low = bank.at(order).evaluate(G, TA, TB, R, C);
  const MutualTerms high = bank.at(order + 2).evaluate(G, TA, TB, R, C);
  const double ratio = (radius_A + radius_B) / R.norm();
  const double safety = ratio > 0.8 ? 3.0 : 2.0;  // the estimate under-reads near contact
  return safety * mutual_error(low, high, R.norm());
}

OrderChoice choose_series_order(SeriesBank& bank, double G, const InertiaIntegrals& TA,
                                const InertiaIntegrals& TB, double radius_A, double radius_B, double separation,
                                const Vec3& direction, const Mat3& C, const OrderSelection& options) {
  auto enough = [&](const InertiaIntegrals& T, double radius) {
    return radius == 0.0 || T.order >= options.max_order + 2;  // a point mass is complete at order 0
  };
  if (!enough(TA, radius_A) || !enough(TB, radius_B))
    throw Error("choose_series_order: integrals of order max_order + 2 are needed");
  OrderChoice choice;
  if (radius_A == 0.0 && radius_B == 0.0) {  // two point masses: order 0 is exact
    choice.met = true;
    return choice;
  }
  // Configurations: the given one and random directions and relative attitudes (uniform on
  // the sphere and on SO(3)), all at the separation.
  std::vector<std::pair<Vec3, Mat3>> samples{{separation * direction.normalized(), C}};
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal;
  for (int k = 1; k < options.samples; ++k) {
    // Drawn one by one: the order in which a constructor's arguments are evaluated is
    // unspecified (g++ went right to left, clang left to right, giving other samples and
    // estimates up to 77 % apart). This is g++'s former order, so the measured tables hold.
    const double dz = normal(rng), dy = normal(rng), dx = normal(rng);
    const double qz = normal(rng), qy = normal(rng), qx = normal(rng), qw = normal(rng);
    const Vec3 d(dx, dy, dz);
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    samples.emplace_back(separation * d.normalized(), q.normalized().toRotationMatrix());
  }
  choice.estimated_error = std::numeric_limits<double>::infinity();
  for (int N = 0; N <= options.max_order; ++N) {
    double worst = 0.0;
    for (const auto& [R, Cs] : samples)
      worst = std::max(worst, series_error_estimate(bank, N, G, TA, TB, radius_A, radius_B, R, Cs));
    if (worst <= options.tolerance) {
      choice.order = N;
      choice.estimated_error = worst;
      choice.met = true;
      return choice;
    }
    if (worst < choice.estimated_error) choice.order = N, choice.estimated_error = worst;
  }
  return choice;  // not met: the best order found and its estimate
}

}  // namespace noether
