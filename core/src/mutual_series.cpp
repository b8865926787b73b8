#include <noether/error.hpp>
#include <noether/mutual_series.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace noether {

using multi_index::count;
using multi_index::exponents;
using multi_index::index;

MutualSeries::MutualSeries(int order)
    : order_(order), reduction_(order < 0 ? 0 : order), rotation_(order < 0 ? 0 : order) {
  if (order < 0 || order > multi_index::kMaxDegree - 1)
    throw SceneError("mutual series: order " + std::to_string(order) + " is outside 0.." +
                     std::to_string(multi_index::kMaxDegree - 1));
  const int n = count(order);
  // Only the reduced integrals (13.9) enter the sums (13.11): α and β with a power of z ≤ 1.
  for (int b = 0; b < n; ++b)
    if (exponents(b)[2] <= 1) free_.push_back(b);
  for (const int b : free_) {
    const auto& eb = exponents(b);
    auto& pairs = pairs_.emplace_back();
    auto& second = second_.emplace_back();
    for (const int a : free_) {
      if (multi_index::degree(a) > order - multi_index::degree(b)) break;  // free_ is by degree
      const auto& ea = exponents(a);
      const int l = ea[0] + eb[0], m = ea[1] + eb[1], k = ea[2] + eb[2];
      pairs.push_back({a, index(l, m, k), {index(l + 1, m, k), index(l, m + 1, k), index(l, m, k + 1)}});
      second.push_back({index(l + 2, m, k), index(l, m + 2, k), index(l, m, k + 2), index(l + 1, m + 1, k),
                        index(l + 1, m, k + 1), index(l, m + 1, k + 1)});
    }
  }
  for (int a = 0; a < n; ++a) {
    const auto [l, m, k] = exponents(a);
    const double f = multi_index::factorial(l) * multi_index::factorial(m) * multi_index::factorial(k);
    sign_over_factorial_.push_back(((l + m + k) % 2 ? -1.0 : 1.0) / f);
    inverse_factorial_.push_back(1.0 / f);
  }
  // Ô_c: ∂T'^β/∂θ under δx = θ × x within the degree (13.6), then reduced (13.9), on each reduced
  // unit vector; the generator maps classes to classes (r² is invariant), so this is the class's.
  std::vector<double> unit(static_cast<std::size_t>(n)), turned(static_cast<std::size_t>(n));
  for (int c = 0; c < 3; ++c) {
    for (const int s : free_) {
      if (s == 0) continue;
      std::fill(unit.begin(), unit.end(), 0.0);
      std::fill(turned.begin(), turned.end(), 0.0);
      unit[static_cast<std::size_t>(s)] = 1.0;
      const int d = multi_index::degree(s);
      for (int b = multi_index::first_of_degree(d); b < multi_index::first_of_degree(d + 1); ++b) {
        const auto [l, m, k] = exponents(b);
        auto X = [&](int ll, int mm, int kk) {
          return (ll < 0 || mm < 0 || kk < 0) ? 0.0 : unit[static_cast<std::size_t>(index(ll, mm, kk))];
        };
        const double v = c == 0   ? k * X(l, m + 1, k - 1) - m * X(l, m - 1, k + 1)
                         : c == 1 ? l * X(l - 1, m, k + 1) - k * X(l + 1, m, k - 1)
                                  : m * X(l + 1, m - 1, k) - l * X(l - 1, m + 1, k);
        turned[static_cast<std::size_t>(b)] = v;
      }
      reduction_.apply(turned.data(), d);
      for (const int t : free_)
        if (multi_index::degree(t) == d && turned[static_cast<std::size_t>(t)] != 0.0)
          generator_[static_cast<std::size_t>(c)].push_back({t, s, turned[static_cast<std::size_t>(t)]});
    }
    std::stable_sort(generator_[static_cast<std::size_t>(c)].begin(), generator_[static_cast<std::size_t>(c)].end(),
                     [](const GeneratorTerm& x, const GeneratorTerm& y) { return x.target < y.target; });
  }
  for (int d = 0; d <= order + 3; ++d) first_of_degree_.push_back(multi_index::first_of_degree(d));
  for (int i = 1; i < count(order + 2); ++i) {  // to degree N + 2 for the jacobian
    const auto [t, u, v] = exponents(i);
    const int c = t > 0 ? 0 : (u > 0 ? 1 : 2);
    std::array<int, 3> e{t, u, v};
    const int g = e[static_cast<std::size_t>(c)];
    e[static_cast<std::size_t>(c)] -= 1;
    const int m1 = index(e[0], e[1], e[2]);
    int m2 = 0;
    if (g > 1) {
      e[static_cast<std::size_t>(c)] -= 1;
      m2 = index(e[0], e[1], e[2]);
    }
    recurrence_.push_back({i, c, m1, m2, static_cast<double>(g - 1)});
  }
  A_.resize(static_cast<std::size_t>(n));
  S_.resize(static_cast<std::size_t>(n));
  M_.resize(static_cast<std::size_t>(n));
  B_.resize(static_cast<std::size_t>(n));
  L_.resize(static_cast<std::size_t>(n));
  l_.resize(static_cast<std::size_t>(n));
  Rj_.resize(static_cast<std::size_t>((order + 3) * count(order + 2)));
}

const double* MutualSeries::derivatives_at(const Vec3& e, int L) {
  // D^γ(1/r) at the unit vector e, |γ| ≤ L, by the recurrence (13.4):
  //   R^{(j)}_{000} = (−1)^j (2j−1)!!,  R^{(j)}_γ = (γ_c − 1) R^{(j+1)}_{γ−2e_c} + e_c R^{(j+1)}_{γ−e_c}
  const int stride = count(L);
  double* Rj = Rj_.data();
  double dfact = 1.0;
  for (int j = 0; j <= L; ++j) {
    Rj[j * stride] = (j % 2 ? -1.0 : 1.0) * dfact;
    dfact *= 2 * j + 1;
  }
  const double ec[3] = {e.x(), e.y(), e.z()};
  for (int d = 1; d <= L; ++d) {
    const Recurrence* first = recurrence_.data() + first_of_degree_[static_cast<std::size_t>(d)] - 1;
    const Recurrence* last = recurrence_.data() + first_of_degree_[static_cast<std::size_t>(d + 1)] - 1;
    for (int j = 0; j <= L - d; ++j) {
      double* out = Rj + j * stride;
      const double* in = Rj + (j + 1) * stride;
      for (const Recurrence* r = first; r != last; ++r)
        out[r->gamma] = r->factor * in[r->minus2] + ec[r->component] * in[r->minus1];
    }
  }
  return Rj;
}

void MutualSeries::turn_reduced(const std::vector<double>& X, int c, int n, std::vector<double>& out) const {
  out.assign(static_cast<std::size_t>(n), 0.0);
  for (const GeneratorTerm& t : generator_[static_cast<std::size_t>(c)]) {
    if (t.target >= n) break;
    out[static_cast<std::size_t>(t.target)] += t.coefficient * X[static_cast<std::size_t>(t.source)];
  }
}

MutualTerms MutualSeries::jacobian(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB, const Vec3& Rv,
                                   const Mat3& C, MutualJacobian& J) {
  const InertiaIntegrals* B = &TB;
  if (TB.order > 0) {
    rotation_.apply(C, TB, rotated_, order_);
    B = &rotated_;
  }
  // The terms, with D to degree N + 2 (one higher than they need) and, in the scratch, the reduced
  // A_α = (−1)^{|α|} T_A^α/(α! R^{|α|}), B_β = T'^β/R^{|β|}, L_β and l_β,i = Σ_α A_α D^{α+β+e_i}.
  const int N = order_;
  const MutualTerms t = evaluate_scaled(G, TA, *B, Rv, N + 2, true);  // a point mass's class is itself
  const int na = count(std::min(N, TA.order)), nb = count(std::min(N, B->order));
  const double R = Rv.norm();
  const double* D = Rj_.data();
  // h_ij = Σ_β T'^β/β! Σ_α A_α D^{α+β+e_i+e_j} (scaled, (25.1)), over the reduced α, β (13.11).
  Mat3 h = Mat3::Zero();
  for (std::size_t k = 0; k < free_.size() && free_[k] < nb; ++k) {
    const auto b = static_cast<std::size_t>(free_[k]);
    const double Bw = B_[b] * inverse_factorial_[b];
    if (Bw == 0.0) continue;
    double hb[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    const auto& pairs = pairs_[k];
    const auto& second = second_[k];
    for (std::size_t i = 0; i < pairs.size() && pairs[i].alpha < na; ++i) {  // pairs are ordered by α
      const double a = A_[static_cast<std::size_t>(pairs[i].alpha)];
      for (int j = 0; j < 6; ++j) hb[j] += a * D[second[i][static_cast<std::size_t>(j)]];
    }
    h(0, 0) += Bw * hb[0], h(1, 1) += Bw * hb[1], h(2, 2) += Bw * hb[2];
    h(0, 1) += Bw * hb[3], h(0, 2) += Bw * hb[4], h(1, 2) += Bw * hb[5];
  }
  h(1, 0) = h(0, 1), h(2, 0) = h(0, 2), h(2, 1) = h(1, 2);
  J.g_R = (-G / (R * R * R)) * h;  // (25.1)
  // τ_B's derivatives (25.2–25.3): Ô_c B and Ô_d Ô_c B, the in-degree rotation (13.6) once and
  // twice, each reduced (13.11).
  J.tauB_R.setZero();
  J.tauB_phi.setZero();
  if (nb > 1) {
    for (int c = 0; c < 3; ++c) turn_reduced(B_, c, nb, OB_[c]);
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) turn_reduced(OB_[c], d, nb, OOB_[d][c]);
    for (std::size_t k = 1; k < free_.size() && free_[k] < nb; ++k) {
      const auto b = static_cast<std::size_t>(free_[k]);
      const double w = inverse_factorial_[b];
      for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < 3; ++i) J.tauB_R(c, i) += w * l_[b][i] * OB_[c][b];
        for (int d = 0; d < 3; ++d) J.tauB_phi(d, c) += L_[b] * OOB_[d][c][b];
      }
    }
    J.tauB_R *= G / (R * R);
    J.tauB_phi *= G / R;
  }
  J.g_phi = -J.tauB_R.transpose();  // ∂²U/∂R∂φ: g = ∂U/∂R, τ_B = −∂U/∂φ (25.4)
  // τ_A = R × g − τ_B holds for the truncated series (13.7), and so for its derivatives (25.5).
  J.tauA_R = hat(Rv) * J.g_R - hat(t.dU_dR) - J.tauB_R;
  J.tauA_phi = hat(Rv) * J.g_phi - J.tauB_phi;
  return t;
}

MutualTerms MutualSeries::evaluate(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB,
                                   const Vec3& R, const Mat3& C) {
  if (TB.order == 0) return evaluate_scaled(G, TA, TB, R, order_ + 1, true);
  rotation_.apply(C, TB, rotated_, order_);  // B's class (13.10), degrees ≤ N
  return evaluate_scaled(G, TA, rotated_, R, order_ + 1, true);
}

MutualTerms MutualSeries::evaluate_rotated(double G, const InertiaIntegrals& TA,
                                           const InertiaIntegrals& TB, const Vec3& Rv) {
  return evaluate_scaled(G, TA, TB, Rv, order_ + 1, false);
}

MutualTerms MutualSeries::evaluate_scaled(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB,
                                          const Vec3& Rv, int L_max, bool B_is_class) {
  const int N = order_;
  const int oa = std::min(N, TA.order), ob = std::min(N, TB.order);
  const int na = count(oa), nb = count(ob);
  const double R = Rv.norm();
  if (!(R > 0.0)) throw Error("mutual series: the two centres of mass coincide");
  const Vec3 e = Rv / R;
  // Everything in units of R (docs/equations.md (13.3)): T^α / R^{|α|}.
  double scale = 1.0;
  for (int d = 0, a = 0; d <= N; ++d, scale /= R)
    for (; a < first_of_degree_[static_cast<std::size_t>(d + 1)]; ++a) {
      S_[static_cast<std::size_t>(a)] = a < na ? TA.T[static_cast<std::size_t>(a)] * scale : 0.0;  // T_A^α/R^{|α|}
      B_[static_cast<std::size_t>(a)] = a < nb ? TB.T[static_cast<std::size_t>(a)] * scale : 0.0;  // T'^β/R^{|β|}
      M_[static_cast<std::size_t>(a)] = 0.0;
    }
  // Both bodies' classes modulo traces (13.9): only those enter (13.11).
  reduction_.apply(S_.data(), oa);
  if (!B_is_class) reduction_.apply(B_.data(), ob);
  for (const int a : free_) A_[static_cast<std::size_t>(a)] = sign_over_factorial_[static_cast<std::size_t>(a)] * S_[static_cast<std::size_t>(a)];

  const double* D = derivatives_at(e, L_max);

  // L_β = Σ_α A_α D^{α+β},  G_β,i = Σ_α A_α D^{α+β+e_i}   (docs/equations.md (13.2), (13.5)),
  // and for A's torque M_α = Σ_β (T'^β/β!) D^{α+β} (∝ ∂U/∂T_A^α), over the reduced α, β (13.11).
  double U = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
  const bool torque_A = na > 1;
  for (std::size_t k = 0; k < free_.size() && free_[k] < nb; ++k) {
    const auto b = static_cast<std::size_t>(free_[k]);
    double Lb = 0.0, lx = 0.0, ly = 0.0, lz = 0.0;
    const double w = inverse_factorial_[b];
    const double Bw = B_[b] * w;
    for (const Pair& p : pairs_[k]) {
      if (p.alpha >= na) break;  // pairs are ordered by α
      const double a = A_[static_cast<std::size_t>(p.alpha)];
      const double d = D[p.gamma];
      Lb += a * d;
      lx += a * D[p.gamma_e[0]];
      ly += a * D[p.gamma_e[1]];
      lz += a * D[p.gamma_e[2]];
      if (torque_A) M_[static_cast<std::size_t>(p.alpha)] += Bw * d;
    }
    L_[b] = Lb * w;  // ∝ ∂U/∂T'^β
    l_[b] = Vec3(lx, ly, lz);  // for the jacobian (25.2)
    U += Bw * Lb;
    gx += Bw * lx, gy += Bw * ly, gz += Bw * lz;
  }
  MutualTerms out;
  out.U = -G * U / R;
  out.dU_dR = (-G / (R * R)) * Vec3(gx, gy, gz);
  // Torque on B by the in-degree derivative of T' under a small rotation δx = θ × x
  // (docs/equations.md (13.6)): τ_B = −Σ_β ∂U/∂T'^β ∂T'^β/∂θ, with ∂U/∂T'^β = −G L_β /R^{|β|+1}
  // and ∂T'^β/∂θ = R^{|β|} (…B…) ⇒ τ_B = +G/R Σ_β L_β (…B…); L_β pairs with a harmonic tensor, so
  // the turned class Ô_c B serves (13.11): τ_B,c = G/R Σ_t L_t Σ_s (Ô_c)_ts B_s.
  double tau[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (const GeneratorTerm& t : generator_[static_cast<std::size_t>(c)]) {
      if (t.target >= nb) break;
      sum += t.coefficient * L_[static_cast<std::size_t>(t.target)] * B_[static_cast<std::size_t>(t.source)];
    }
    tau[c] = sum;
  }
  out.torque_B = (G / R) * Vec3(tau[0], tau[1], tau[2]);
  // Torque on A the same way from A's own integrals (13.7): a rotation of A changes T_A^α
  // within its degree, ∂U/∂T_A^α = −G (−1)^{|α|}/α! M_α / R^{|α|+1}. Equal to R × ∂U/∂R − τ_B
  // (Hou et al. 2017 Eq. 2) but without its cancellation, which loses a far pair's torque.
  double tau_a[3] = {0.0, 0.0, 0.0};
  if (torque_A)
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (const GeneratorTerm& t : generator_[static_cast<std::size_t>(c)]) {
        if (t.target >= na) break;
        const auto a = static_cast<std::size_t>(t.target);
        sum += t.coefficient * sign_over_factorial_[a] * M_[a] * S_[static_cast<std::size_t>(t.source)];
      }
      tau_a[c] = sum;
    }
  out.torque_A = (G / R) * Vec3(tau_a[0], tau_a[1], tau_a[2]);
  return out;
}

}  // namespace noether
