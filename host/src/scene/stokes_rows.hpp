#pragma once
// What the gravity-field readers share (stokes_file.cpp, pds_stokes.cpp): where a message points
// ("file:line: "), a line's fields, numbers and degrees read strictly, and the coefficients as
// read (Rows), checked and built into StokesCoefficients.
#include <noether/error.hpp>
#include <noether/stokes_coefficients.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace noether::detail {

// "file:line: " for messages.
struct Where {
  std::string file;
  std::size_t line = 0;
  std::string operator()() const { return file + ":" + std::to_string(line) + ": "; }
};

inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// Blank- or comma-separated fields.
inline std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (char c : line) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\r') {
      if (!cell.empty()) out.push_back(cell), cell.clear();
    } else {
      cell += c;
    }
  }
  if (!cell.empty()) out.push_back(cell);
  return out;
}

// A number, Fortran's D exponent allowed; the whole cell must be one.
inline double number(std::string cell, const Where& where, const std::string& what) {
  std::replace(cell.begin(), cell.end(), 'D', 'E');
  std::replace(cell.begin(), cell.end(), 'd', 'e');
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw SceneError(where() + what + " '" + cell + "' is not a finite number");
  return v;
}

// Fields of higher degree than this are refused (EGM2008's is 2190; the coefficients of degree N
// take N²/2 pairs of doubles).
inline constexpr int kMaxFileDegree = 2400;

inline int integer(const std::string& cell, const Where& where, const std::string& what) {
  const double v = number(cell, where, what);
  if (v != std::floor(v) || v < 0) throw SceneError(where() + what + " '" + cell + "' is not a degree or order");
  if (v > kMaxFileDegree)
    throw SceneError(where() + what + " " + cell + " is above " + std::to_string(kMaxFileDegree) +
                     ", the highest degree noether reads");
  return static_cast<int>(v);
}

// Coefficients as read, before the degree is known: (n, m) → (C, S, line).
struct Rows {
  std::map<std::pair<int, int>, std::pair<std::pair<double, double>, std::size_t>> values;

  void add(int n, int m, double C, double S, const Where& where) {
    if (m > n) throw SceneError(where() + "order " + std::to_string(m) + " is above degree " + std::to_string(n));
    if (m == 0 && S != 0.0)
      throw SceneError(where() + "S(" + std::to_string(n) + ", 0) is " + std::to_string(S) + "; a zonal term has no sine part");
    const auto [it, fresh] = values.emplace(std::pair{n, m}, std::pair{std::pair{C, S}, where.line});
    if (!fresh)
      throw SceneError(where() + "the coefficients of degree " + std::to_string(n) + ", order " + std::to_string(m) +
                       " are given twice (first on line " + std::to_string(it->second.second) + ")");
  }

  // Into StokesCoefficients to `degree` (the highest present when negative). C00 is 1 when absent;
  // a field about another origin than the centre of mass (degree 1) is refused.
  // The 1σ of each coefficient, where the file gives them (pds_stokes.cpp).
  std::map<std::pair<int, int>, std::pair<double, double>> sigmas;

  StokesCoefficients build(int degree, const std::string& file) const {
    if (values.empty()) throw SceneError(file + ": no coefficients found");
    const int highest = values.rbegin()->first.first;
    if (degree < 0) degree = highest;
    StokesCoefficients cs;
    cs.degree = degree;
    const auto size = static_cast<std::size_t>(StokesCoefficients::index(degree, degree) + 1);
    cs.C.assign(size, 0.0);
    cs.S.assign(size, 0.0);
    cs.C[0] = 1.0;
    for (const auto& [nm, value] : values) {
      const auto [n, m] = nm;
      if (n > degree) continue;
      const auto k = static_cast<std::size_t>(StokesCoefficients::index(n, m));
      cs.C[k] = value.first.first, cs.S[k] = value.first.second;
    }
    if (std::abs(cs.C[0] - 1.0) > 1e-9) {
      std::ostringstream msg;
      msg.precision(17);
      msg << file << ": C(0, 0) is " << cs.C[0] << ", not 1: noether takes the field's mass from its GM (give the "
          << "body's 'mass' to change it) and the coefficients relative to it";
      throw SceneError(msg.str());
    }
    if (degree >= 1) {
      const double c10 = cs.c(1, 0), c11 = cs.c(1, 1), s11 = cs.s(1, 1);
      if (std::max({std::abs(c10), std::abs(c11), std::abs(s11)}) > 1e-12) {
        std::ostringstream msg;
        msg.precision(6);
        msg << file << ": the degree-1 coefficients (C10 " << c10 << ", C11 " << c11 << ", S11 " << s11
            << ") put the field's origin away from the body's centre of mass; noether's bodies are about their "
            << "centres of mass: use a field in a centre-of-mass frame";
        throw SceneError(msg.str());
      }
      cs.C[1] = cs.C[2] = cs.S[2] = 0.0;
    }
    return cs;
  }
};

// A file whose coefficients end below the degree it declares (`declared`, what declares it) is
// refused: a truncated file would load as a smoother field and be called trustworthy.
inline void stops_short(const Rows& rows, int degree, const std::string& file, const std::string& declared) {
  if (rows.values.empty()) return;  // (build says: no coefficients)
  const auto& [last, value] = *rows.values.rbegin();
  if (last.first >= degree) return;
  throw SceneError(file + ": its coefficients stop at degree " + std::to_string(last.first) + " (line " +
                   std::to_string(value.second) + "), short of " + declared + " " + std::to_string(degree) +
                   ": the file is cut short; fetch it whole again");
}

}  // namespace noether::detail
