#pragma once
// A state's parts as NumPy arrays (copies), as noether.Simulation shows them and as the orbit
// functions return them: positions and momenta (n, 3), velocities γ/m, body-frame angular
// velocities Ω = J⁻¹Π (m, 3), attitudes (m, 3, 3); and complex values as a 1-D array.
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <pybind11/complex.h>
#include <pybind11/numpy.h>

#include <complex>
#include <vector>

namespace noether::python {

// Columns of a 3×n matrix as an (n, 3) array, each row divided by scale[i] if given.
inline pybind11::array_t<double> rows(const Eigen::Matrix3Xd& m, const std::vector<double>* scale = nullptr) {
  pybind11::array_t<double> out({static_cast<pybind11::ssize_t>(m.cols()), pybind11::ssize_t{3}});
  auto v = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int a = 0; a < 3; ++a) v(i, a) = scale ? m(a, i) / (*scale)[static_cast<std::size_t>(i)] : m(a, i);
  return out;
}

inline pybind11::array_t<double> velocities(const System& system, const State& s) {
  std::vector<double> m;
  for (const auto& b : system.bodies()) m.push_back(b.mass);
  return rows(s.p, &m);
}

inline pybind11::array_t<double> angular_velocities(const System& system, const State& s) {
  Eigen::Matrix3Xd omega(3, s.Pi.cols());
  for (Eigen::Index k = 0; k < s.Pi.cols(); ++k)
    omega.col(k) = system.body(system.body_of_rigid(static_cast<std::size_t>(k))).inertia_inverse * s.Pi.col(k);
  return rows(omega);
}

inline pybind11::array_t<double> attitudes(const State& s) {
  pybind11::array_t<double> out({static_cast<pybind11::ssize_t>(s.R.size()), pybind11::ssize_t{3}, pybind11::ssize_t{3}});
  auto v = out.mutable_unchecked<3>();
  for (std::size_t k = 0; k < s.R.size(); ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) v(static_cast<pybind11::ssize_t>(k), r, c) = s.R[k](r, c);
  return out;
}

inline pybind11::array_t<std::complex<double>> complex_array(const std::vector<std::complex<double>>& z) {
  pybind11::array_t<std::complex<double>> out(static_cast<pybind11::ssize_t>(z.size()));
  for (std::size_t i = 0; i < z.size(); ++i) out.mutable_at(static_cast<pybind11::ssize_t>(i)) = z[i];
  return out;
}

}  // namespace noether::python
