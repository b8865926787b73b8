#include <noether/error.hpp>
#include <noether/mutual_series.hpp>

#include <cmath>
#include <string>

namespace noether {

using multi_index::count;
using multi_index::exponents;
using multi_index::index;

void inverse_distance_derivatives(const Vec3& e, int L, std::vector<double>& D,
                                  std::vector<double>& scratch) {
  // R^{(j)}_{tuv} = ∂x^t ∂y^u ∂z^v g_j with g_j(s) = d^j/ds^j (2s)^{-1/2}, s = r²/2, at r = 1:
  //   R^{(j)}_{000} = (−1)^j (2j−1)!!,  R^{(j)}_{t+1,u,v} = t R^{(j+1)}_{t−1,u,v} + x R^{(j+1)}_{t,u,v}
  const int n = count(L);
  scratch.resize(static_cast<std::size_t>((L + 1) * n));
  auto at = [&](int j, int i) -> double& { return scratch[static_cast<std::size_t>(j * n + i)]; };
  double dfact = 1.0;
  for (int j = 0; j <= L; ++j) {
    at(j, 0) = (j % 2 ? -1.0 : 1.0) * dfact;
    dfact *= 2 * j + 1;
  }
  for (int d = 1; d <= L; ++d)
    for (int j = 0; j <= L - d; ++j)
      for (int i = multi_index::first_of_degree(d); i < multi_index::first_of_degree(d + 1); ++i) {
        const auto [t, u, v] = exponents(i);
        double r;
        if (t > 0)
          r = (t > 1 ? (t - 1) * at(j + 1, index(t - 2, u, v)) : 0.0) + e.x() * at(j + 1, index(t - 1, u, v));
        else if (u > 0)
          r = (u > 1 ? (u - 1) * at(j + 1, index(t, u - 2, v)) : 0.0) + e.y() * at(j + 1, index(t, u - 1, v));
        else
          r = (v > 1 ? (v - 1) * at(j + 1, index(t, u, v - 2)) : 0.0) + e.z() * at(j + 1, index(t, u, v - 1));
        at(j, i) = r;
      }
  D.assign(scratch.begin(), scratch.begin() + n);
}

MutualSeries::MutualSeries(int order) : order_(order), rotation_(order < 0 ? 0 : order) {
  if (order < 0 || order > multi_index::kMaxDegree - 1)
    throw SceneError("mutual series: order " + std::to_string(order) + " is outside 0.." +
                     std::to_string(multi_index::kMaxDegree - 1));
  const int n = count(order);
  pairs_.resize(static_cast<std::size_t>(n));
  for (int b = 0; b < n; ++b) {
    const auto& eb = exponents(b);
    for (int a = 0; a < count(order - multi_index::degree(b)); ++a) {
      const auto& ea = exponents(a);
      const int l = ea[0] + eb[0], m = ea[1] + eb[1], k = ea[2] + eb[2];
      pairs_[static_cast<std::size_t>(b)].push_back(
          {a, index(l, m, k), {index(l + 1, m, k), index(l, m + 1, k), index(l, m, k + 1)}});
    }
  }
  for (int a = 0; a < n; ++a) {
    const auto [l, m, k] = exponents(a);
    sign_over_factorial_.push_back(((l + m + k) % 2 ? -1.0 : 1.0) /
                                   (multi_index::factorial(l) * multi_index::factorial(m) * multi_index::factorial(k)));
  }
  A_.resize(static_cast<std::size_t>(n));
  B_.resize(static_cast<std::size_t>(n));
  L_.resize(static_cast<std::size_t>(n));
}

MutualTerms MutualSeries::evaluate(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB,
                                   const Vec3& R, const Mat3& C) {
  if (TB.order == 0) return evaluate_rotated(G, TA, TB, R);
  InertiaIntegrals cut;
  const InertiaIntegrals* tb = &TB;
  if (TB.order > order_) {  // only degrees ≤ N enter
    cut.order = order_;
    cut.T.assign(TB.T.begin(), TB.T.begin() + count(order_));
    tb = &cut;
  }
  rotation_.apply(C, *tb, rotated_);
  return evaluate_rotated(G, TA, rotated_, R);
}

MutualTerms MutualSeries::evaluate_rotated(double G, const InertiaIntegrals& TA,
                                           const InertiaIntegrals& TB, const Vec3& Rv) {
  const int N = order_;
  const int na = count(std::min(N, TA.order)), nb = count(std::min(N, TB.order));
  const double R = Rv.norm();
  if (!(R > 0.0)) throw Error("mutual series: the two centres of mass coincide");
  const Vec3 e = Rv / R;
  // Everything in units of R (docs/equations.md (12.3)): T^α / R^{|α|}.
  std::fill(A_.begin(), A_.end(), 0.0);
  std::fill(B_.begin(), B_.end(), 0.0);
  double scale = 1.0;
  int deg = 0;
  for (int a = 0; a < na; ++a) {
    if (multi_index::degree(a) != deg) deg = multi_index::degree(a), scale /= R;
    A_[static_cast<std::size_t>(a)] = sign_over_factorial_[static_cast<std::size_t>(a)] * TA.T[static_cast<std::size_t>(a)] * scale;
  }
  scale = 1.0, deg = 0;
  for (int b = 0; b < nb; ++b) {
    if (multi_index::degree(b) != deg) deg = multi_index::degree(b), scale /= R;
    B_[static_cast<std::size_t>(b)] = TB.T[static_cast<std::size_t>(b)] * scale;  // T'^β/R^{|β|}, no 1/β! yet
  }
  inverse_distance_derivatives(e, N + 1, D_, Rj_);

  // L_β = Σ_α A_α D^{α+β},  G_β,i = Σ_α A_α D^{α+β+e_i}   (docs/equations.md (12.2), (12.5))
  double U = 0.0;
  Vec3 grad = Vec3::Zero();
  for (int b = 0; b < nb; ++b) {
    double L = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (const Pair& p : pairs_[static_cast<std::size_t>(b)]) {
      if (p.alpha >= na) break;  // pairs are ordered by α
      const double a = A_[static_cast<std::size_t>(p.alpha)];
      if (a == 0.0) continue;
      L += a * D_[static_cast<std::size_t>(p.gamma)];
      gx += a * D_[static_cast<std::size_t>(p.gamma_e[0])];
      gy += a * D_[static_cast<std::size_t>(p.gamma_e[1])];
      gz += a * D_[static_cast<std::size_t>(p.gamma_e[2])];
    }
    const auto [l, m, k] = exponents(b);
    const double w = 1.0 / (multi_index::factorial(l) * multi_index::factorial(m) * multi_index::factorial(k));
    L_[static_cast<std::size_t>(b)] = L * w;  // ∝ ∂U/∂T'^β
    U += B_[static_cast<std::size_t>(b)] * L * w;
    grad += (B_[static_cast<std::size_t>(b)] * w) * Vec3(gx, gy, gz);
  }
  MutualTerms out;
  out.U = -G * U / R;
  out.dU_dR = (-G / (R * R)) * grad;
  // Torque on B by the in-degree derivative of T' under a small rotation δx = θ × x
  // (docs/equations.md (12.6)): τ_B = −Σ_β ∂U/∂T'^β ∂T'^β/∂θ, with ∂U/∂T'^β = −G L_β /R^{|β|+1}.
  Vec3 tau = Vec3::Zero();
  auto Bv = [&](int l, int m, int k) {
    return (l < 0 || m < 0 || k < 0) ? 0.0 : B_[static_cast<std::size_t>(index(l, m, k))];
  };
  for (int b = 1; b < nb; ++b) {
    const double Lb = L_[static_cast<std::size_t>(b)];
    if (Lb == 0.0) continue;
    const auto [l, m, k] = exponents(b);
    tau.x() += Lb * (k * Bv(l, m + 1, k - 1) - m * Bv(l, m - 1, k + 1));
    tau.y() += Lb * (l * Bv(l - 1, m, k + 1) - k * Bv(l + 1, m, k - 1));
    tau.z() += Lb * (m * Bv(l + 1, m - 1, k) - l * Bv(l - 1, m + 1, k));
  }
  // ∂U/∂T'^β ∂T'^β/∂θ = (−G L_β/R^{|β|+1}) R^{|β|} (…B…) ⇒ τ_B = +G/R Σ L_β (…B…)
  out.torque_B = (G / R) * tau;
  out.torque_A = Rv.cross(out.dU_dR) - out.torque_B;  // Hou et al. 2017 Eq. 2
  return out;
}

}  // namespace noether
