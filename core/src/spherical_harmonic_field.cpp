// Cunningham's recursion for a spherical-harmonic gravity field (spherical_harmonic_field.hpp;
// docs/equations.md §32; Montenbruck & Gill 2000, eqs. 3.29–3.33).
#include <noether/error.hpp>
#include <noether/spherical_harmonic_field.hpp>

#include <cmath>
#include <string>

namespace noether {

namespace {
inline std::size_t at(int n, int m) { return static_cast<std::size_t>(StokesCoefficients::index(n, m)); }
constexpr std::array<std::array<int, 2>, 6> kPairs{{{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}};
}  // namespace

// (32.2): R ∂/∂x, R ∂/∂y and R ∂/∂z of C V_nm + S W_nm are sums of the harmonics of degree n + 1
// (Montenbruck & Gill 2000, eq. 3.33, read term by term).
SphericalHarmonicField::Sum SphericalHarmonicField::derivative(const Sum& in, int axis) {
  Sum out;
  out.degree = in.degree + 1;
  out.C.assign(at(out.degree, out.degree) + 1, 0.0);
  out.S.assign(out.C.size(), 0.0);
  for (int n = 0; n <= in.degree; ++n)
    for (int m = 0; m <= n; ++m) {
      const double C = in.C[at(n, m)], S = in.S[at(n, m)];
      if (C == 0.0 && S == 0.0) continue;
      if (axis == 2) {
        out.C[at(n + 1, m)] -= (n - m + 1) * C;
        out.S[at(n + 1, m)] -= (n - m + 1) * S;
      } else if (m == 0) {  // S_n0 multiplies W_n0 = 0
        (axis == 0 ? out.C : out.S)[at(n + 1, 1)] -= C;
      } else {
        const double f = (n - m + 2) * (n - m + 1);
        if (axis == 0) {
          out.C[at(n + 1, m + 1)] -= 0.5 * C, out.S[at(n + 1, m + 1)] -= 0.5 * S;
          out.C[at(n + 1, m - 1)] += 0.5 * f * C, out.S[at(n + 1, m - 1)] += 0.5 * f * S;
        } else {
          out.C[at(n + 1, m + 1)] += 0.5 * S, out.S[at(n + 1, m + 1)] -= 0.5 * C;
          out.C[at(n + 1, m - 1)] += 0.5 * f * S, out.S[at(n + 1, m - 1)] -= 0.5 * f * C;
        }
      }
    }
  for (int n = 0; n <= out.degree; ++n) out.S[at(n, 0)] = 0.0;  // W_n0 = 0
  return out;
}

SphericalHarmonicField::SphericalHarmonicField(const StokesCoefficients& cs, double G)
    : degree_(cs.degree), R_(cs.reference_radius), GM_(G * cs.mass) {
  if (degree_ < 0 || degree_ > multi_index::kMaxDegree)
    throw Error("SphericalHarmonicField: degree " + std::to_string(degree_) + " outside 0.." +
                std::to_string(multi_index::kMaxDegree));
  if (!(R_ > 0.0)) throw Error("SphericalHarmonicField: the reference radius must be positive");
  const StokesCoefficients plain = truncated(cs, degree_, false);
  field_ = Sum{degree_, plain.C, plain.S};
  for (int a = 0; a < 3; ++a) gradient_[static_cast<std::size_t>(a)] = derivative(field_, a);
  for (std::size_t k = 0; k < kPairs.size(); ++k)
    hessian_[k] = derivative(gradient_[static_cast<std::size_t>(kPairs[k][0])], kPairs[k][1]);
  V_.assign(at(degree_ + 2, degree_ + 2) + 1, 0.0);
  W_.assign(V_.size(), 0.0);
}

double SphericalHarmonicField::evaluate(const Sum& sum) const {
  double total = 0.0;
  for (std::size_t k = 0; k < sum.C.size(); ++k) total += sum.C[k] * V_[k] + sum.S[k] * W_[k];
  return total;
}

SphericalHarmonicField::Value SphericalHarmonicField::operator()(const Vec3& r, bool with_hessian) {
  const int top = degree_ + (with_hessian ? 2 : 1);
  const double r2 = r.squaredNorm(), rho = R_ * R_ / r2;
  const double x0 = R_ * r.x() / r2, y0 = R_ * r.y() / r2, z0 = R_ * r.z() / r2;
  // (32.1): V_mm, W_mm along the diagonal, then each column m upwards in n.
  V_[0] = R_ / std::sqrt(r2);
  W_[0] = 0.0;
  for (int m = 0; m <= top; ++m) {
    if (m > 0) {
      const double v = V_[at(m - 1, m - 1)], w = W_[at(m - 1, m - 1)];
      V_[at(m, m)] = (2 * m - 1) * (x0 * v - y0 * w);
      W_[at(m, m)] = (2 * m - 1) * (x0 * w + y0 * v);
    }
    for (int n = m + 1; n <= top; ++n) {
      const double a = (2 * n - 1) * z0 / (n - m), b = (n + m - 1) * rho / (n - m);
      V_[at(n, m)] = a * V_[at(n - 1, m)] - (n >= m + 2 ? b * V_[at(n - 2, m)] : 0.0);
      W_[at(n, m)] = a * W_[at(n - 1, m)] - (n >= m + 2 ? b * W_[at(n - 2, m)] : 0.0);
    }
  }
  Value out;
  out.potential = GM_ / R_ * evaluate(field_);
  for (int a = 0; a < 3; ++a) out.acceleration[a] = GM_ / (R_ * R_) * evaluate(gradient_[static_cast<std::size_t>(a)]);
  if (with_hessian)
    for (std::size_t k = 0; k < kPairs.size(); ++k) {
      const auto [a, b] = kPairs[k];
      out.hessian(a, b) = out.hessian(b, a) = GM_ / (R_ * R_ * R_) * evaluate(hessian_[k]);
    }
  return out;
}

}  // namespace noether
