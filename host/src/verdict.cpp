// The verdict on a run (docs/user-guide.md, "Verdict"): each check against run.trust.
#include <noether/simulation.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace noether {

void judge(RunSummary& s, const Scene& scene) {
  const TrustThresholds& limit = scene.run.trust;
  const double T0 = s.initial.kinetic_translational + s.initial.kinetic_rotational;
  const double E0 = std::abs(s.initial.energy);
  s.energy_scale = E0 >= 1e-3 * T0 ? "|E0|" : "T0";
  const double scale = E0 >= 1e-3 * T0 ? E0 : T0;
  s.max_rel_energy_error = scale > 0 ? s.max_abs_energy_error / scale : s.max_abs_energy_error;
  Verdict& v = s.verdict;
  v = {};
  char why[256];
  if (s.max_rel_energy_error > limit.energy) {
    std::snprintf(why, sizeof why, "relative energy error %.2e (of %s) > %.0e", s.max_rel_energy_error,
                  s.energy_scale.c_str(), limit.energy);
    v.reasons.push_back(why);
  }
  if (s.conserves_linear_momentum && s.max_rel_linear_momentum_error > limit.momentum) {
    std::snprintf(why, sizeof why, "relative linear momentum error %.2e > %.0e", s.max_rel_linear_momentum_error,
                  limit.momentum);
    v.reasons.push_back(why);
  }
  if (s.conserves_angular_momentum && s.max_rel_angular_momentum_error > limit.momentum) {
    std::snprintf(why, sizeof why, "relative angular momentum error %.2e > %.0e", s.max_rel_angular_momentum_error,
                  limit.momentum);
    v.reasons.push_back(why);
  }
  if (s.max_orthogonality_error > limit.orthogonality) {
    std::snprintf(why, sizeof why, "attitudes left SO(3): ||I - R^T R|| = %.2e > %.0e", s.max_orthogonality_error,
                  limit.orthogonality);
    v.reasons.push_back(why);
  }
  // Bounding spheres inside each other by more than the event's root tolerance (a run stopped
  // by a collision ends at contact, to ~1e-10).
  if (s.min_gap < -1e-6 * s.min_gap_reach) {
    std::snprintf(why, sizeof why, "bodies %s overlapped (bounding spheres %.3g inside each other)",
                  s.min_gap_pair.c_str(), -s.min_gap);
    v.reasons.push_back(why);
  }
  v.trustworthy = v.reasons.empty();
}
}  // namespace noether
