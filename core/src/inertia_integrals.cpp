#include <noether/error.hpp>
#include <noether/inertia_integrals.hpp>

#include <cmath>
#include <string>

namespace noether {

namespace multi_index {

namespace {
struct Tables {
  std::vector<std::array<int, 3>> exponents;
  std::vector<int> degree;
  std::vector<double> factorial;
  Tables() {
    for (int d = 0; d <= kMaxDegree; ++d)
      for (int l = d; l >= 0; --l)
        for (int m = d - l; m >= 0; --m) {
          exponents.push_back({l, m, d - l - m});
          degree.push_back(d);
        }
    factorial.push_back(1.0);
    for (int n = 1; n <= 2 * kMaxDegree + 3; ++n) factorial.push_back(factorial.back() * n);
  }
};
const Tables& tables() {
  static const Tables t;
  return t;
}
}  // namespace

const std::array<int, 3>& exponents(int index) { return tables().exponents[static_cast<std::size_t>(index)]; }
int degree(int index) { return tables().degree[static_cast<std::size_t>(index)]; }
double factorial(int n) { return tables().factorial[static_cast<std::size_t>(n)]; }

}  // namespace multi_index

using multi_index::count;
using multi_index::exponents;
using multi_index::factorial;

namespace {

void check_order(int order) {
  if (order < 0 || order > multi_index::kMaxDegree)
    throw SceneError("inertia integrals: order " + std::to_string(order) + " is outside 0.." +
                     std::to_string(multi_index::kMaxDegree));
}

InertiaIntegrals zeros(int order) {
  check_order(order);
  InertiaIntegrals t;
  t.order = order;
  t.T.assign(static_cast<std::size_t>(count(order)), 0.0);
  return t;
}

double double_factorial(int n) {  // n!!, with (−1)!! = 1
  double r = 1.0;
  for (int k = n; k > 1; k -= 2) r *= k;
  return r;
}

// Powers p[k] = x^k, k ≤ N.
void powers(double x, int N, double* p) {
  p[0] = 1.0;
  for (int k = 1; k <= N; ++k) p[k] = p[k - 1] * x;
}

}  // namespace

Mat3 InertiaIntegrals::second_moment() const {
  using multi_index::index;
  Mat3 S;
  S << (*this)(2, 0, 0), (*this)(1, 1, 0), (*this)(1, 0, 1),  //
      (*this)(1, 1, 0), (*this)(0, 2, 0), (*this)(0, 1, 1),   //
      (*this)(1, 0, 1), (*this)(0, 1, 1), (*this)(0, 0, 2);
  return S;
}

InertiaIntegrals ellipsoid_integrals(double mass, const Vec3& semi_axes, int order) {
  InertiaIntegrals t = zeros(order);
  std::vector<double> pa(static_cast<std::size_t>(order + 1)), pb(pa.size()), pc(pa.size());
  powers(semi_axes.x(), order, pa.data());
  powers(semi_axes.y(), order, pb.data());
  powers(semi_axes.z(), order, pc.data());
  for (int i = 0; i < count(order); ++i) {
    const auto [l, m, n] = exponents(i);
    if (l % 2 || m % 2 || n % 2) continue;
    // Hou et al. 2017 Eq. 26, docs/equations.md (12.3).
    t.T[static_cast<std::size_t>(i)] = 3.0 * mass * double_factorial(l - 1) * double_factorial(m - 1) *
                                       double_factorial(n - 1) * pa[static_cast<std::size_t>(l)] *
                                       pb[static_cast<std::size_t>(m)] * pc[static_cast<std::size_t>(n)] /
                                       double_factorial(l + m + n + 3);
  }
  return t;
}

InertiaIntegrals polyhedron_integrals(const Mesh& mesh, double density, int order) {
  InertiaIntegrals t = zeros(order);
  const int n = count(order);
  // Pairs (β, γ) with |β| + |γ| ≤ N and the index of β + γ: the convolution below.
  struct Pair {
    int b, c, sum;
  };
  std::vector<Pair> pairs;
  for (int b = 0; b < n; ++b)
    for (int c = 0; c < n; ++c) {
      const auto& eb = exponents(b);
      const auto& ec = exponents(c);
      if (multi_index::degree(b) + multi_index::degree(c) > order) continue;
      pairs.push_back({b, c, multi_index::index(eb[0] + ec[0], eb[1] + ec[1], eb[2] + ec[2])});
    }
  // Monomial coefficients of (ℓ·v)^k: P_v(β) = |β|!/β! v^β.
  std::vector<double> coef(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto [l, m, k] = exponents(i);
    coef[static_cast<std::size_t>(i)] = factorial(l + m + k) / (factorial(l) * factorial(m) * factorial(k));
  }
  std::vector<double> P[3], S1(static_cast<std::size_t>(n)), S(static_cast<std::size_t>(n));
  std::vector<double> px(static_cast<std::size_t>(order + 1)), py(px.size()), pz(px.size());
  for (auto& p : P) p.resize(static_cast<std::size_t>(n));
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  for (const auto& f : mesh.faces) {
    Mat3 J;
    J << mesh.vertices.col(f[0]), mesh.vertices.col(f[1]), mesh.vertices.col(f[2]);
    const double det = J.determinant();  // 6 × the signed volume of (0, v1, v2, v3)
    for (int v = 0; v < 3; ++v) {
      powers(J(0, v), order, px.data());
      powers(J(1, v), order, py.data());
      powers(J(2, v), order, pz.data());
      for (int i = 0; i < n; ++i) {
        const auto [l, m, k] = exponents(i);
        P[v][static_cast<std::size_t>(i)] = coef[static_cast<std::size_t>(i)] * px[static_cast<std::size_t>(l)] *
                                           py[static_cast<std::size_t>(m)] * pz[static_cast<std::size_t>(k)];
      }
    }
    std::fill(S1.begin(), S1.end(), 0.0);
    std::fill(S.begin(), S.end(), 0.0);
    for (const auto& p : pairs) S1[static_cast<std::size_t>(p.sum)] += P[0][static_cast<std::size_t>(p.b)] * P[1][static_cast<std::size_t>(p.c)];
    for (const auto& p : pairs) S[static_cast<std::size_t>(p.sum)] += S1[static_cast<std::size_t>(p.b)] * P[2][static_cast<std::size_t>(p.c)];
    for (int i = 0; i < n; ++i) sum[static_cast<std::size_t>(i)] += det * S[static_cast<std::size_t>(i)];
  }
  // ∫_tet x^α = 3! V α!/(|α|+3)! Σ_{β1+β2+β3=α} Π_v |β_v|!/β_v! v^β_v  (docs/equations.md (12.4))
  for (int i = 0; i < n; ++i) {
    const auto [l, m, k] = exponents(i);
    t.T[static_cast<std::size_t>(i)] = density * sum[static_cast<std::size_t>(i)] * factorial(l) * factorial(m) *
                                       factorial(k) / factorial(l + m + k + 3);
  }
  return t;
}

InertiaIntegrals point_integrals(const std::vector<double>& masses, const std::vector<Vec3>& positions,
                                 int order) {
  InertiaIntegrals t = zeros(order);
  std::vector<double> px(static_cast<std::size_t>(order + 1)), py(px.size()), pz(px.size());
  for (std::size_t p = 0; p < masses.size(); ++p) {
    powers(positions[p].x(), order, px.data());
    powers(positions[p].y(), order, py.data());
    powers(positions[p].z(), order, pz.data());
    for (int i = 0; i < count(order); ++i) {
      const auto [l, m, k] = exponents(i);
      t.T[static_cast<std::size_t>(i)] += masses[p] * px[static_cast<std::size_t>(l)] * py[static_cast<std::size_t>(m)] *
                                          pz[static_cast<std::size_t>(k)];
    }
  }
  return t;
}

InertiaIntegrals integrals_from_inertia(double mass, const Mat3& J) {
  InertiaIntegrals t = zeros(2);
  const Mat3 S = 0.5 * J.trace() * Mat3::Identity() - J;
  using multi_index::index;
  t.T[0] = mass;
  t.T[static_cast<std::size_t>(index(2, 0, 0))] = S(0, 0);
  t.T[static_cast<std::size_t>(index(0, 2, 0))] = S(1, 1);
  t.T[static_cast<std::size_t>(index(0, 0, 2))] = S(2, 2);
  t.T[static_cast<std::size_t>(index(1, 1, 0))] = S(0, 1);
  t.T[static_cast<std::size_t>(index(1, 0, 1))] = S(0, 2);
  t.T[static_cast<std::size_t>(index(0, 1, 1))] = S(1, 2);
  return t;
}

// ---- rotation ---------------------------------------------------------------------------

void rotate_low_degrees(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int order) {
  out.order = order;
  out.T.resize(static_cast<std::size_t>(count(order)));
  out.T[0] = T.T[0];
  if (order >= 1) {  // degree 1: C t
    const Vec3 t1 = C * Vec3(T.T[1], T.T[2], T.T[3]);
    out.T[1] = t1.x(), out.T[2] = t1.y(), out.T[3] = t1.z();
  }
  if (order == 2) {  // degree 2: C S Cᵀ
    const Mat3 S = C * T.second_moment() * C.transpose();
    const double s[6] = {S(0, 0), S(0, 1), S(0, 2), S(1, 1), S(1, 2), S(2, 2)};  // index order
    for (int i = 0; i < 6; ++i) out.T[static_cast<std::size_t>(4 + i)] = s[i];
  }
}

namespace {
// Index of (l, m, n) within its degree.
int local(int l, int m, int n) { return multi_index::index(l, m, n) - multi_index::first_of_degree(l + m + n); }
}  // namespace

IntegralRotation::IntegralRotation(int order) : order_(order) {
  check_order(order);
  K_.resize(static_cast<std::size_t>(order + 1));
  plus_.resize(static_cast<std::size_t>(order + 1));
  lower_.resize(static_cast<std::size_t>(order + 1));
  for (int d = 0; d <= order; ++d) {
    const int nd = multi_index::count_of_degree(d);
    K_[static_cast<std::size_t>(d)].assign(static_cast<std::size_t>(nd * nd), 0.0);
    for (int a = 0; a < nd; ++a) {
      const auto e = exponents(multi_index::first_of_degree(d) + a);
      plus_[static_cast<std::size_t>(d)].push_back(
          {local(e[0] + 1, e[1], e[2]), local(e[0], e[1] + 1, e[2]), local(e[0], e[1], e[2] + 1)});
      if (d > 0) {
        const int k = e[0] > 0 ? 0 : (e[1] > 0 ? 1 : 2);
        auto f = e;
        --f[static_cast<std::size_t>(k)];
        lower_[static_cast<std::size_t>(d)].emplace_back(local(f[0], f[1], f[2]), k);
      }
    }
  }
  K_[0][0] = 1.0;
}

void IntegralRotation::apply(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int max_degree) {
  const int order = max_degree < 0 ? T.order : std::min(T.order, max_degree);
  if (order > order_)
    throw Error("IntegralRotation: integrals of order " + std::to_string(order) +
                " exceed the rotation's order " + std::to_string(order_));
  if (order <= 2) return rotate_low_degrees(C, T, out, order);  // no monomial tables needed
  out.order = order;
  out.T.resize(static_cast<std::size_t>(count(order)));
  out.T[0] = T.T[0];
  for (int d = 1; d <= order; ++d) {
    const int nd = multi_index::count_of_degree(d), np = multi_index::count_of_degree(d - 1);
    auto& K = K_[static_cast<std::size_t>(d)];
    const auto& Kp = K_[static_cast<std::size_t>(d - 1)];
    const auto& plus = plus_[static_cast<std::size_t>(d - 1)];
    std::fill(K.begin(), K.end(), 0.0);
    // y^α = y_k y^{α−e_k}, y_k = Σ_j C_kj x_j  (docs/equations.md (12.6))
    for (int a = 0; a < nd; ++a) {
      const auto [ap, k] = lower_[static_cast<std::size_t>(d)][static_cast<std::size_t>(a)];
      const double c0 = C(k, 0), c1 = C(k, 1), c2 = C(k, 2);
      double* row = &K[static_cast<std::size_t>(a * nd)];
      const double* prow = &Kp[static_cast<std::size_t>(ap * np)];
      for (int b = 0; b < np; ++b) {
        const double v = prow[b];
        if (v == 0.0) continue;
        const auto& p = plus[static_cast<std::size_t>(b)];
        row[p[0]] += c0 * v;
        row[p[1]] += c1 * v;
        row[p[2]] += c2 * v;
      }
    }
    const double* Td = &T.T[static_cast<std::size_t>(multi_index::first_of_degree(d))];
    double* Od = &out.T[static_cast<std::size_t>(multi_index::first_of_degree(d))];
    for (int a = 0; a < nd; ++a) {
      const double* row = &K[static_cast<std::size_t>(a * nd)];
      double s = 0.0;
      for (int b = 0; b < nd; ++b) s += row[b] * Td[b];
      Od[a] = s;
    }
  }
}

}  // namespace noether
