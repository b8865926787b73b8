#pragma once
// The binary of a two-body-like scene: the two most massive bodies, when they hold 99 % of
// the mass (a binary, with or without spacecraft). Its orbit is timed in the summary
// (run/mutual_orbit_feature.cpp) and described frame by frame in the output (io/frame_schema.cpp).
#include <noether/system.hpp>

#include <optional>

namespace noether {

struct BinaryPair {
  std::size_t primary = 0, secondary = 0;  // the heavier and the lighter body
};

inline std::optional<BinaryPair> binary_pair(const System& system) {
  if (system.size() < 2) return std::nullopt;
  std::size_t a = 0, b = 1;
  if (system.body(b).mass > system.body(a).mass) std::swap(a, b);
  double total = system.body(0).mass + system.body(1).mass;
  for (std::size_t i = 2; i < system.size(); ++i) {
    const double m = system.body(i).mass;
    total += m;
    if (m > system.body(a).mass) b = a, a = i;
    else if (m > system.body(b).mass) b = i;
  }
  if (system.body(a).mass + system.body(b).mass < 0.99 * total) return std::nullopt;
  return BinaryPair{a, b};
}

}  // namespace noether
