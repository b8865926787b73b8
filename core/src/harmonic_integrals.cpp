#include <noether/error.hpp>
#include <noether/harmonic_integrals.hpp>

#include <algorithm>
#include <array>
#include <string>

namespace noether {

using multi_index::count;
using multi_index::index;

namespace {
void check_order(int order, const char* who) {
  if (order < 0 || order > multi_index::kMaxDegree)
    throw SceneError(std::string(who) + ": order " + std::to_string(order) + " is outside 0.." +
                     std::to_string(multi_index::kMaxDegree));
}
}  // namespace

TraceReduction::TraceReduction(int order) {
  check_order(order, "trace reduction");
  end_of_degree_.assign(static_cast<std::size_t>(order + 1), 0);
  for (int d = 2; d <= order; ++d) {
    // (13.9): z² → −(x² + y²) in p(u) = Σ_β T^β u^β/β!; on T^β = β! τ^β the weights become the factors.
    for (int n = d; n >= 2; --n)
      for (int m = 0; m <= d - n; ++m) {
        const int l = d - n - m;
        const double nn = static_cast<double>(n * (n - 1));
        steps_.push_back({index(l, m, n), index(l + 2, m, n - 2), index(l, m + 2, n - 2),
                          static_cast<double>((l + 2) * (l + 1)) / nn, static_cast<double>((m + 2) * (m + 1)) / nn});
      }
    end_of_degree_[static_cast<std::size_t>(d)] = steps_.size();
  }
}

void TraceReduction::apply(double* X, int order) const {
  if (order < 2) return;
  if (static_cast<std::size_t>(order) >= end_of_degree_.size())
    throw Error("TraceReduction: integrals of order " + std::to_string(order) + " exceed the reduction's order " +
                std::to_string(end_of_degree_.size() - 1));
  const std::size_t end = end_of_degree_[static_cast<std::size_t>(order)];
  for (std::size_t s = 0; s < end; ++s) {
    const Step& st = steps_[s];
    const double v = X[st.from];
    X[st.to_x] -= st.f_x * v;
    X[st.to_y] -= st.f_y * v;
    X[st.from] = 0.0;
  }
}

// Free local indices of degree q (13.10): j ≤ q is (q − j, j, 0); j = q + 1 + b is (q − 1 − b, b, 1).
HarmonicRotation::HarmonicRotation(int order) : order_(order), reduction_(order) {
  check_order(order, "harmonic rotation");
  const auto Q = static_cast<std::size_t>(order + 1);
  global_.resize(Q), factorial_.resize(Q), parent_.resize(Q), axis_.resize(Q), K_.resize(Q);
  auto local = [](int l, int m, int n) { return n == 0 ? m : (l + m + 1) + 1 + m; };  // q = l + m + n
  for (int q = 0; q <= order; ++q) {
    const auto qq = static_cast<std::size_t>(q);
    for (int j = 0; j < 2 * q + 1; ++j) {
      std::array<int, 3> e = j <= q ? std::array<int, 3>{q - j, j, 0} : std::array<int, 3>{2 * q - j, j - q - 1, 1};
      global_[qq].push_back(index(e[0], e[1], e[2]));
      factorial_[qq].push_back(multi_index::factorial(e[0]) * multi_index::factorial(e[1]) * multi_index::factorial(e[2]));
      if (q == 0) continue;
      const int k = e[0] > 0 ? 0 : (e[1] > 0 ? 1 : 2);  // γ − e_k stays free
      --e[static_cast<std::size_t>(k)];
      axis_[qq].push_back(k);
      parent_[qq].push_back(local(e[0], e[1], e[2]));
    }
    K_[qq].assign(static_cast<std::size_t>((2 * q + 1) * (2 * q + 1)), 0.0);
  }
  K_[0][0] = 1.0;
}

void HarmonicRotation::apply(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int max_degree) {
  const int order = max_degree < 0 ? T.order : std::min(T.order, max_degree);
  if (order > order_)
    throw Error("HarmonicRotation: integrals of order " + std::to_string(order) + " exceed the rotation's order " +
                std::to_string(order_));
  const auto n_all = static_cast<std::size_t>(count(order));
  if (order <= 2) {  // C t and C S Cᵀ, then reduced: the tables cost more than this
    rotate_low_degrees(C, T, out, order);
    reduction_.apply(out.T.data(), order);
    return;
  }
  reduced_.assign(T.T.begin(), T.T.begin() + static_cast<std::ptrdiff_t>(n_all));
  reduction_.apply(reduced_.data(), order);
  out.order = order;
  out.T.assign(n_all, 0.0);
  out.T[0] = reduced_[0];
  for (int q = 1; q <= order; ++q) {
    const auto qq = static_cast<std::size_t>(q);
    const int n = 2 * q + 1, np = 2 * q - 1;
    double* K = K_[qq].data();
    const double* Kp = K_[qq - 1].data();
    std::fill(K, K + n * n, 0.0);
    // Column j: ℓ_k(u) P_{γ−e_k}(u) reduced, ℓ_k(u) = Σ_i C_ik u_i = (Cᵀu)_k  (13.10).
    for (int j = 0; j < n; ++j) {
      const int k = axis_[qq][static_cast<std::size_t>(j)];
      const double cx = C(0, k), cy = C(1, k), cz = C(2, k);
      const double* v = Kp + parent_[qq][static_cast<std::size_t>(j)] * np;
      double* col = K + j * n;
      for (int b = 0; b < q; ++b) {  // (q−1−b, b, 0) × u_x, u_y, u_z
        col[b] += cx * v[b];
        col[b + 1] += cy * v[b];
        col[q + 1 + b] += cz * v[b];
      }
      for (int b = 0; b + 1 < q; ++b) {  // (q−2−b, b, 1) × u_x, u_y; × u_z = (…, 2) → −(q−b, b, 0) − (q−2−b, b+2, 0)
        const double w = v[q + b];
        col[q + 1 + b] += cx * w;
        col[q + 2 + b] += cy * w;
        col[b] -= cz * w;
        col[b + 2] -= cz * w;
      }
    }
    const int* g = global_[qq].data();
    const double* f = factorial_[qq].data();
    double tau[2 * multi_index::kMaxDegree + 1];
    for (int d = 0; d < n; ++d) tau[d] = 0.0;
    for (int j = 0; j < n; ++j) {
      const double t = reduced_[static_cast<std::size_t>(g[j])] / f[j];
      const double* col = K + j * n;
      for (int d = 0; d < n; ++d) tau[d] += col[d] * t;
    }
    for (int d = 0; d < n; ++d) out.T[static_cast<std::size_t>(g[d])] = f[d] * tau[d];
  }
}

}  // namespace noether
