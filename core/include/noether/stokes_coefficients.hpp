#pragma once
// Stokes coefficients: a body's exterior gravity field as spherical harmonics, and their exact
// relation to its inertia integrals T^{lmn} (docs/equations.md §31). The exterior potential is
//     U(r, φ, λ) = (G M / r) Σ_n Σ_m (R/r)^n P_nm(sin φ) (C_nm cos mλ + S_nm sin mλ)
// (φ latitude, λ longitude in the body frame, R the reference radius, P_nm the associated
// Legendre functions without the Condon–Shortley phase), and
//     C_nm + i S_nm = (2 − δ_m0) (n − m)!/(n + m)! / (M R^n) ∫ Q_nm(x) dm,
//     Q_nm = r^n P_nm(cos θ) e^{imλ}, a polynomial of degree n in (x, y, z)     (31.1)
// so each degree's coefficients are linear in that degree's integrals. The converse needs what
// the field does not fix: the integrals of r² times the lower-degree monomials (the traces).
#include <noether/inertia_integrals.hpp>

#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct StokesCoefficients {
  int degree = -1;
  double mass = 0.0;
  double reference_radius = 0.0;
  // Fully normalised (geodesy's 4π normalisation): C̄_nm = C_nm / N_nm,
  // N_nm = √((2 − δ_m0)(2n + 1)(n − m)!/(n + m)!) (31.2).
  bool normalized = false;
  std::vector<double> C, S;  // [n(n + 1)/2 + m], 0 ≤ m ≤ n ≤ degree (S_n0 = 0)

  static int index(int n, int m) { return n * (n + 1) / 2 + m; }
  double c(int n, int m) const { return C[static_cast<std::size_t>(index(n, m))]; }
  double s(int n, int m) const { return S[static_cast<std::size_t>(index(n, m))]; }
};

// N_nm of (31.2).
double stokes_normalization(int n, int m);

// The polynomial Q_nm of (31.1): coefficients of its real (cos mλ) and imaginary (sin mλ) parts
// on the monomials x^l y^m z^k of degree n, in multi_index order within the degree
// (multi_index::index(l, m, k) − multi_index::first_of_degree(n)). Exact integers up to n ≈ 20.
struct SolidHarmonic {
  std::vector<double> re, im;
};
SolidHarmonic solid_harmonic(int n, int m);

// The coefficients to `degree` (≤ T.order) of a body with integrals T about its centre of mass
// (31.1), with reference radius R > 0.
StokesCoefficients stokes_from_integrals(const InertiaIntegrals& T, double reference_radius, int degree,
                                         bool normalized);

// The integrals to cs.degree whose exterior field is cs and whose traces — ∫ r² x^α dm for
// |α| = n − 2 — are trace_source's (31.3): the round trip of stokes_from_integrals when
// trace_source is the body's own integrals. Degrees above trace_source.order take zero traces
// (the exterior field and the mutual potential do not depend on them; the inertia does, through
// degree 2: integrals_from_inertia gives it).
InertiaIntegrals integrals_from_stokes(const StokesCoefficients& cs, const InertiaIntegrals& trace_source);

// The coefficients to `degree` ≤ cs.degree in the normalization asked for (31.2).
StokesCoefficients truncated(const StokesCoefficients& cs, int degree, bool normalized);

// A body known by its field cs (degree ≥ 2) and one more number: ∫ r² dm, the trace of its
// second moment S = ∫ x xᵀ dm, which the field does not fix. From its moment of inertia about
// the body z axis, J_zz = S_xx + S_yy, and the traceless part of S that C_2m give (31.4).
double second_moment_trace(const StokesCoefficients& cs, double polar_moment);

// Its integrals to cs.degree: the field's, with ∫ r² dm = `trace` at degree 2 and zero traces
// above it (31.3; neither the exterior field nor a mutual potential depends on those).
InertiaIntegrals field_integrals(const StokesCoefficients& cs, double trace);

// J = tr(S) I − S from the degree-2 integrals S = ∫ x xᵀ dm (the converse of
// integrals_from_inertia).
Mat3 inertia_of(const InertiaIntegrals& T);

}  // namespace noether

#pragma GCC visibility pop
