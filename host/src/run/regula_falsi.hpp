#pragma once
// The Illinois variant of regula falsi (Dowell & Jarratt 1971; docs/equations.md eq. 16.3), for
// the time where a gap function turns from positive to ≤ 0 inside a step: events (stepping.cpp)
// and particles landing (particles.cpp).
#include <algorithm>
#include <cmath>

namespace noether::detail {

// The root of g in [a, b], where g(a) = ga > 0 ≥ g(b) = gb, to `relative` of max(1, |b|) (at most
// 200 iterations): the end of the last bracket where g ≤ 0 (the time at which the gap is closed).
// A bracket whose positive end is not positive is bisected.
template <class Gap>
double illinois_root(const Gap& g, double a, double b, double ga, double gb, double relative) {
  int side = 0;
  for (int it = 0; it < 200 && b - a > relative * std::max(1.0, std::abs(b)); ++it) {
    const double c = ga > 0.0 && gb < ga ? (a * gb - b * ga) / (gb - ga) : 0.5 * (a + b);
    const double gc = g(c);
    if (gc > 0) {
      a = c, ga = gc;
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = c, gb = gc;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  return b;
}

}  // namespace noether::detail
