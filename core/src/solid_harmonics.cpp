#include <noether/error.hpp>
#include <noether/gravity_field.hpp>
#include <noether/solid_harmonics.hpp>
#include <noether/stokes_coefficients.hpp>

#include <cmath>
#include <string>

namespace noether {

namespace harmonic {
int degree(int j) { return static_cast<int>(std::sqrt(static_cast<double>(j) + 0.5)); }
}  // namespace harmonic

namespace {

using harmonic::index;

void check_degree(int degree, const char* what) {
  if (degree < 0 || degree > harmonic::kMaxDegree) {
    std::string msg = what;
    msg += ": degree ";
    msg += std::to_string(degree);
    msg += " outside 0..";
    msg += std::to_string(harmonic::kMaxDegree);
    throw Error(msg);
  }
}

// Schmidt's factor √((2 − δ_m0)(n+m)!(n−m)!) that takes R_n^m = r^n P_n^m e^{imφ}/(n+m)! of the
// recursion (37.2) to the semi-normalised harmonic (37.1), for every j.
const std::vector<double>& schmidt_factors() {
  static const std::vector<double> factors = [] {
    std::vector<double> f(static_cast<std::size_t>(harmonic::count(harmonic::kMaxDegree)));
    for (int n = 0; n <= harmonic::kMaxDegree; ++n)
      for (int m = 0; m <= n; ++m) {
        const double s = std::sqrt((m == 0 ? 1.0 : 2.0) * multi_index::factorial(n + m) * multi_index::factorial(n - m));
        f[static_cast<std::size_t>(index(n, m, false))] = s;
        if (m > 0) f[static_cast<std::size_t>(index(n, m, true))] = s;
      }
    return f;
  }();
  return factors;
}

// The recursion (37.2) for R_n^m = r^n P_n^m(cos θ) e^{imφ}/(n+m)!: real parts in C, imaginary
// parts in S, both at index(n, m, false).
void recurse(int N, const Vec3& x, std::vector<double>& C, std::vector<double>& S) {
  auto at = [](int n, int m) { return static_cast<std::size_t>(index(n, m, false)); };
  const double r2 = x.squaredNorm();
  C[0] = 1.0, S[0] = 0.0;
  for (int m = 1; m <= N; ++m) {  // R_m^m = −(x + iy) R_{m−1}^{m−1} / (2m)
    const double c = C[at(m - 1, m - 1)], s = S[at(m - 1, m - 1)], k = -1.0 / (2.0 * m);
    C[at(m, m)] = k * (x.x() * c - x.y() * s);
    S[at(m, m)] = k * (x.x() * s + x.y() * c);
  }
  for (int m = 0; m < N; ++m)  // R_{m+1}^m = z R_m^m
    C[at(m + 1, m)] = x.z() * C[at(m, m)], S[at(m + 1, m)] = x.z() * S[at(m, m)];
  for (int m = 0; m <= N; ++m)  // (n+m)(n−m) R_n^m = (2n−1) z R_{n−1}^m − r² R_{n−2}^m
    for (int n = m + 2; n <= N; ++n) {
      const double k = 1.0 / ((n + m) * (n - m));
      C[at(n, m)] = k * ((2 * n - 1) * x.z() * C[at(n - 1, m)] - r2 * C[at(n - 2, m)]);
      S[at(n, m)] = k * ((2 * n - 1) * x.z() * S[at(n - 1, m)] - r2 * S[at(n - 2, m)]);
    }
}

}  // namespace

void solid_harmonic_values(const Vec3& x, int N, double* values) {
  check_degree(N, "solid harmonics");
  thread_local std::vector<double> C, S;
  const auto count = static_cast<std::size_t>(harmonic::count(N));
  C.resize(count), S.resize(count);
  recurse(N, x, C, S);
  const std::vector<double>& f = schmidt_factors();
  for (int n = 0; n <= N; ++n)
    for (int m = 0; m <= n; ++m) {
      const auto c = static_cast<std::size_t>(index(n, m, false));
      values[c] = f[c] * C[c];
      if (m > 0) values[c + 1] = f[c] * S[c];
    }
}

SolidHarmonicPolynomials solid_harmonic_polynomials(int N) {
  check_degree(N, "solid harmonic polynomials");
  // From Q_nm = r^n P_nm e^{imλ} without the Condon–Shortley phase (stokes_coefficients.hpp):
  // R_n^m = (−1)^m Q_nm / (n+m)!.
  SolidHarmonicPolynomials out;
  out.degree = N;
  out.coefficients.resize(static_cast<std::size_t>(harmonic::count(N)));
  const std::vector<double>& f = schmidt_factors();
  for (int n = 0; n <= N; ++n)
    for (int m = 0; m <= n; ++m) {
      const auto c = static_cast<std::size_t>(index(n, m, false));
      const double k = f[c] * (m % 2 == 0 ? 1.0 : -1.0) / multi_index::factorial(n + m);
      SolidHarmonic q = solid_harmonic(n, m);
      for (double& v : q.re) v *= k;
      out.coefficients[c] = std::move(q.re);
      if (m > 0) {
        for (double& v : q.im) v *= k;
        out.coefficients[c + 1] = std::move(q.im);
      }
    }
  return out;
}

SolidHarmonicMoments solid_harmonic_moments(const InertiaIntegrals& T, double a,
                                            const SolidHarmonicPolynomials& polynomials) {
  const int N = polynomials.degree;
  if (T.order < N) throw Error("solid harmonic moments: the inertia integrals stop below the harmonics' degree");
  // T'(α) = T(α) / a^|α|: the integrals of ξ = x/a.
  auto Ts = [&](int l, int m, int k) {
    if (l < 0 || m < 0 || k < 0) return 0.0;
    return T(l, m, k) / std::pow(a, l + m + k);
  };
  SolidHarmonicMoments out;
  out.degree = N, out.radius = a;
  const int J = harmonic::count(N);
  out.mass.setZero(J), out.gradient.setZero(3, J), out.moment.setZero(3, J);
  for (int j = 0; j < J; ++j) {
    const int n = harmonic::degree(j), first = multi_index::first_of_degree(n);
    const std::vector<double>& c = polynomials.coefficients[static_cast<std::size_t>(j)];
    double mass = 0.0;
    Vec3 gradient = Vec3::Zero(), moment = Vec3::Zero();
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (c[i] == 0.0) continue;
      const auto& [l, m, k] = multi_index::exponents(first + static_cast<int>(i));
      mass += c[i] * Ts(l, m, k);
      // ∇ξ^α = (l ξ^{α−e₀}, m ξ^{α−e₁}, k ξ^{α−e₂}); ξ × ∇ξ^α (37.4)
      gradient += c[i] * Vec3(l * Ts(l - 1, m, k), m * Ts(l, m - 1, k), k * Ts(l, m, k - 1));
      moment += c[i] * Vec3(k * Ts(l, m + 1, k - 1) - m * Ts(l, m - 1, k + 1),
                            l * Ts(l - 1, m, k + 1) - k * Ts(l + 1, m, k - 1),
                            m * Ts(l + 1, m - 1, k) - l * Ts(l - 1, m + 1, k));
    }
    out.mass[j] = mass;
    out.gradient.col(j) = gradient / a;  // ∇_x = ∇_ξ / a
    out.moment.col(j) = moment;          // x × ∇_x = ξ × ∇_ξ
  }
  return out;
}

SphereProjection::SphereProjection(int N) : degree_(N) {
  check_degree(N, "sphere projection");
  // The unit sphere's rule of (14.7): Gauss–Legendre in u = cos θ with N + 2 nodes integrates
  // R_i R_j (degree ≤ 2N) exactly, and 2N + 2 values of φ integrate cos(mφ) cos(m'φ) for
  // m + m' ≤ 2N exactly (37.3). On the unit sphere n dS = ξ dΩ, so the weight is ξ · (n dS).
  SurfaceRule sphere = ellipsoid_surface_rule(Vec3::Ones(), N + 2, 2 * N + 2);
  nodes_ = std::move(sphere.points);
  std::vector<double> weight;
  for (std::size_t k = 0; k < nodes_.size(); ++k) weight.push_back(nodes_[k].dot(sphere.areas[k]));
  const int J = harmonic::count(N), K = static_cast<int>(nodes_.size());
  Eigen::MatrixXd values(J, K);
  for (int k = 0; k < K; ++k) solid_harmonic_values(nodes_[static_cast<std::size_t>(k)], N, values.col(k).data());
  projection_.resize(J, K);
  for (int j = 0; j < J; ++j) {
    double gram = 0.0;  // ∮ R_j² dΩ by the same rule
    for (int k = 0; k < K; ++k) gram += weight[static_cast<std::size_t>(k)] * values(j, k) * values(j, k);
    for (int k = 0; k < K; ++k) projection_(j, k) = weight[static_cast<std::size_t>(k)] * values(j, k) / gram;
  }
}

}  // namespace noether
