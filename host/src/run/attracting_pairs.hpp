#pragma once
// Which body each body orbits, at a state, one per pair, the lighter about the heavier. Two rules:
// the body that attracts it most (largest G m_j / r²: attracting_pairs), the orbits the verdict
// judges on their own energy scale (RunSummary::orbits); and the body, at least as heavy, about
// which its two-body orbit is bound with the smallest semi-major axis (bound_pairs): the orbits
// whose periods are timed (orbit_periods_feature.cpp) — a moon's about its planet, though the
// Sun pulls it harder (KW4's Beta: 8.9e7 against 3.5e5 in m_j / r²). Scenes of more than 64 bodies
// have none (O(n²)).
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <algorithm>
#include <vector>

namespace noether {

struct AttractingPair {
  std::size_t body = 0, about = 0;  // the lighter body, and the heavier one it orbits
};

inline constexpr std::size_t kAttractingPairsMostBodies = 64;

inline std::vector<AttractingPair> attracting_pairs(const System& system, const State& state) {
  std::vector<AttractingPair> out;
  const auto n = static_cast<std::size_t>(state.x.cols());
  if (n < 2 || n > kAttractingPairsMostBodies) return out;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t best = n;
    double strongest = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double r2 = (state.x.col(static_cast<Eigen::Index>(i)) - state.x.col(static_cast<Eigen::Index>(j))).squaredNorm();
      const double pull = system.body(j).mass / r2;
      if (r2 > 0 && pull > strongest) strongest = pull, best = j;
    }
    if (best == n) continue;
    const bool lighter = system.body(i).mass <= system.body(best).mass;
    const AttractingPair pair{lighter ? i : best, lighter ? best : i};
    const bool seen = std::any_of(out.begin(), out.end(), [&](const AttractingPair& p) {
      return (p.body == pair.body && p.about == pair.about) || (p.body == pair.about && p.about == pair.body);
    });
    if (!seen) out.push_back(pair);
  }
  return out;
}

inline std::vector<AttractingPair> bound_pairs(const System& system, const State& state) {
  std::vector<AttractingPair> out;
  const auto n = static_cast<std::size_t>(state.x.cols());
  if (n < 2 || n > kAttractingPairsMostBodies) return out;
  for (std::size_t i = 0; i < n; ++i) {
    const double m = system.body(i).mass;
    std::size_t best = n;
    double smallest = 0.0;  // the semi-major axis
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i || system.body(j).mass < m) continue;
      const auto I = static_cast<Eigen::Index>(i), J = static_cast<Eigen::Index>(j);
      const double mu = system.G() * (m + system.body(j).mass), r = (state.x.col(I) - state.x.col(J)).norm();
      const double v2 = (state.p.col(I) / m - state.p.col(J) / system.body(j).mass).squaredNorm();
      const double energy = 0.5 * v2 - mu / r;  // per unit reduced mass
      if (!(r > 0) || !(energy < 0)) continue;
      const double a = -mu / (2 * energy);
      if (best == n || a < smallest) smallest = a, best = j;
    }
    if (best == n) continue;
    const bool seen = std::any_of(out.begin(), out.end(), [&](const AttractingPair& p) {
      return (p.body == i && p.about == best) || (p.body == best && p.about == i);
    });
    if (!seen) out.push_back({i, best});
  }
  return out;
}

}  // namespace noether
