// Stokes coefficients ↔ inertia integrals (docs/equations.md §31).
#include <noether/error.hpp>
#include <noether/stokes_coefficients.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <string>

namespace noether {

namespace {

using multi_index::count_of_degree;
using multi_index::first_of_degree;

// Position of x^l y^m z^k within its degree.
int within(int l, int m, int k) { return multi_index::index(l, m, k) - first_of_degree(l + m + k); }

// A complex polynomial of one degree: real and imaginary coefficients on its monomials.
struct Poly {
  int n = 0;
  std::vector<double> re, im;
  explicit Poly(int degree) : n(degree), re(static_cast<std::size_t>(count_of_degree(degree)), 0.0), im(re) {}
};

// p · (a x + b y + c z)-like products: p times one variable (0 x, 1 y, 2 z).
Poly times_variable(const Poly& p, int variable) {
  Poly out(p.n + 1);
  const int first = first_of_degree(p.n);
  for (int j = 0; j < count_of_degree(p.n); ++j) {
    auto e = multi_index::exponents(first + j);
    ++e[static_cast<std::size_t>(variable)];
    const auto k = static_cast<std::size_t>(within(e[0], e[1], e[2]));
    out.re[k] += p.re[static_cast<std::size_t>(j)];
    out.im[k] += p.im[static_cast<std::size_t>(j)];
  }
  return out;
}

Poly times_r2(const Poly& p) {
  Poly out(p.n + 2);
  for (int v = 0; v < 3; ++v) {
    const Poly term = times_variable(times_variable(p, v), v);
    for (std::size_t k = 0; k < out.re.size(); ++k) out.re[k] += term.re[k], out.im[k] += term.im[k];
  }
  return out;
}

}  // namespace

double stokes_normalization(int n, int m) {
  return std::sqrt((m == 0 ? 1.0 : 2.0) * (2 * n + 1) * multi_index::factorial(n - m) / multi_index::factorial(n + m));
}

SolidHarmonic solid_harmonic(int n, int m) {
  if (m < 0 || m > n || n > multi_index::kMaxDegree)
    throw Error("solid_harmonic: need 0 ≤ m ≤ n ≤ " + std::to_string(multi_index::kMaxDegree));
  // Q_mm = (2m − 1)!! (x + i y)^m, then (n − m) Q_nm = (2n − 1) z Q_{n−1,m} − (n + m − 1) r² Q_{n−2,m}.
  Poly sectoral(0);
  sectoral.re[0] = 1.0;
  for (int k = 1; k <= m; ++k) {  // × (2k − 1)(x + i y)
    const Poly px = times_variable(sectoral, 0), py = times_variable(sectoral, 1);
    Poly next(k);
    for (std::size_t j = 0; j < next.re.size(); ++j) {
      next.re[j] = (2 * k - 1) * (px.re[j] - py.im[j]);
      next.im[j] = (2 * k - 1) * (px.im[j] + py.re[j]);
    }
    sectoral = next;
  }
  Poly before(0), current = sectoral;  // Q_{n−2,m}, Q_{n−1,m} as the loop goes
  bool has_before = false;
  for (int d = m + 1; d <= n; ++d) {
    Poly next = times_variable(current, 2);
    for (std::size_t j = 0; j < next.re.size(); ++j) next.re[j] *= (2 * d - 1), next.im[j] *= (2 * d - 1);
    if (has_before) {
      const Poly r2 = times_r2(before);
      for (std::size_t j = 0; j < next.re.size(); ++j)
        next.re[j] -= (d + m - 1) * r2.re[j], next.im[j] -= (d + m - 1) * r2.im[j];
    }
    for (std::size_t j = 0; j < next.re.size(); ++j) next.re[j] /= (d - m), next.im[j] /= (d - m);
    before = current, current = next, has_before = true;
  }
  return {current.re, current.im};
}

StokesCoefficients stokes_from_integrals(const InertiaIntegrals& T, double reference_radius, int degree,
                                         bool normalized) {
  if (degree < 0 || degree > T.order)
    throw Error("stokes_from_integrals: degree " + std::to_string(degree) + " beyond the integrals' order " +
                std::to_string(T.order));
  if (!(reference_radius > 0)) throw Error("stokes_from_integrals: the reference radius must be positive");
  StokesCoefficients cs;
  cs.degree = degree;
  cs.mass = T.mass();
  cs.reference_radius = reference_radius;
  cs.normalized = normalized;
  const auto size = static_cast<std::size_t>(StokesCoefficients::index(degree, degree) + 1);
  cs.C.assign(size, 0.0);
  cs.S.assign(size, 0.0);
  for (int n = 0; n <= degree; ++n) {
    const double scale = 1.0 / (cs.mass * std::pow(reference_radius, n));
    const std::size_t first = static_cast<std::size_t>(first_of_degree(n));
    for (int m = 0; m <= n; ++m) {
      const SolidHarmonic Q = solid_harmonic(n, m);
      double c = 0, s = 0;
      for (std::size_t j = 0; j < Q.re.size(); ++j) c += Q.re[j] * T.T[first + j], s += Q.im[j] * T.T[first + j];
      // (31.1), then (31.2)
      const double f = (m == 0 ? 1.0 : 2.0) * multi_index::factorial(n - m) / multi_index::factorial(n + m) * scale /
                       (normalized ? stokes_normalization(n, m) : 1.0);
      cs.C[static_cast<std::size_t>(StokesCoefficients::index(n, m))] = f * c;
      cs.S[static_cast<std::size_t>(StokesCoefficients::index(n, m))] = m == 0 ? 0.0 : f * s;
    }
  }
  return cs;
}

InertiaIntegrals integrals_from_stokes(const StokesCoefficients& cs, const InertiaIntegrals& trace_source) {
  InertiaIntegrals T;
  T.order = cs.degree;
  T.T.assign(static_cast<std::size_t>(multi_index::count(cs.degree)), 0.0);
  // (31.3): per degree n, the moment functional is known on a basis of the degree-n polynomials —
  // Re Q_nm, Im Q_nm (the field's 2n + 1) and r² x^α, |α| = n − 2 (the traces) — so its values
  // on the monomials solve one linear system. Rows are scaled to unit length.
  for (int n = 0; n <= cs.degree; ++n) {
    const int d = count_of_degree(n);
    Eigen::MatrixXd B(d, d);
    Eigen::VectorXd v(d);
    int row = 0;
    const double moment_scale = cs.mass * std::pow(cs.reference_radius, n);
    for (int m = 0; m <= n; ++m) {
      const SolidHarmonic Q = solid_harmonic(n, m);
      const double f = (m == 0 ? 1.0 : 2.0) * multi_index::factorial(n - m) / multi_index::factorial(n + m) /
                       (cs.normalized ? stokes_normalization(n, m) : 1.0);
      for (int part = 0; part < (m == 0 ? 1 : 2); ++part) {
        const std::vector<double>& q = part == 0 ? Q.re : Q.im;
        const double coefficient = part == 0 ? cs.c(n, m) : cs.s(n, m);
        const double norm = Eigen::Map<const Eigen::VectorXd>(q.data(), d).norm();
        B.row(row) = Eigen::Map<const Eigen::VectorXd>(q.data(), d).transpose() / norm;
        v[row] = coefficient * moment_scale / f / norm;  // ∫ Q dm from (31.1)
        ++row;
      }
    }
    if (n >= 2) {
      const int first_lower = first_of_degree(n - 2);
      for (int j = 0; j < count_of_degree(n - 2); ++j, ++row) {
        const auto& a = multi_index::exponents(first_lower + j);
        B.row(row).setZero();
        double trace = 0.0;
        for (int k = 0; k < 3; ++k) {
          auto e = a;
          e[static_cast<std::size_t>(k)] += 2;
          B(row, within(e[0], e[1], e[2])) = 1.0 / std::sqrt(3.0);
          if (n <= trace_source.order) trace += trace_source(e[0], e[1], e[2]);
        }
        v[row] = trace / std::sqrt(3.0);
      }
    }
    const Eigen::VectorXd t = B.fullPivLu().solve(v);
    for (int j = 0; j < d; ++j) T.T[static_cast<std::size_t>(first_of_degree(n) + j)] = t[j];
  }
  return T;
}

StokesCoefficients truncated(const StokesCoefficients& cs, int degree, bool normalized) {
  if (degree < 0 || degree > cs.degree)
    throw Error("truncated: degree " + std::to_string(degree) + " beyond the field's " + std::to_string(cs.degree));
  StokesCoefficients out = cs;
  out.degree = degree;
  out.normalized = normalized;
  const auto size = static_cast<std::size_t>(StokesCoefficients::index(degree, degree) + 1);
  out.C.resize(size);
  out.S.resize(size);
  if (normalized != cs.normalized)
    for (int n = 0; n <= degree; ++n)
      for (int m = 0; m <= n; ++m) {
        const double N = stokes_normalization(n, m), f = normalized ? 1.0 / N : N;  // (31.2)
        const auto k = static_cast<std::size_t>(StokesCoefficients::index(n, m));
        out.C[k] *= f, out.S[k] *= f;
      }
  return out;
}

double second_moment_trace(const StokesCoefficients& cs, double polar_moment) {
  if (cs.degree < 2) throw Error("second_moment_trace: the field needs degree 2");
  // (31.4): with zero trace the degree-2 integrals are S₀, the traceless part of S; S = S₀ + (t/3) I
  // gives J_zz = S₀_xx + S₀_yy + 2t/3.
  InertiaIntegrals none = integrals_from_inertia(cs.mass, Mat3::Zero());
  const Mat3 S0 = integrals_from_stokes(truncated(cs, 2, cs.normalized), none).second_moment();
  return 1.5 * (polar_moment - S0(0, 0) - S0(1, 1));
}

InertiaIntegrals field_integrals(const StokesCoefficients& cs, double trace) {
  // A trace source with S = (trace/3) I: integrals_from_inertia of J = tr(S) I − S = (2 trace/3) I.
  return integrals_from_stokes(cs, integrals_from_inertia(cs.mass, (2.0 * trace / 3.0) * Mat3::Identity()));
}

Mat3 inertia_of(const InertiaIntegrals& T) {
  const Mat3 S = T.second_moment();
  return S.trace() * Mat3::Identity() - S;
}

}  // namespace noether
