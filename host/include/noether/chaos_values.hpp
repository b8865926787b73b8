#pragma once
// ChaosValues: the chaos indicators of a run where it stands (run.chaos; docs/derivatives.md,
// docs/equations.md §23): in every output frame (/derivatives/megno, /derivatives/fli) and, the
// last ones, in the run's summary.
#include <limits>

namespace noether {

struct ChaosValues {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double megno = kNaN;     // ⟨Y⟩(t), eq. 23.3: → 2 on a regular orbit, ≈ λ t / 2 on a chaotic one
  double megno_y = kNaN;   // Y(t), eq. 23.2
  double fli = kNaN;       // max over s ≤ t of log10 ‖δ(s)‖ / ‖δ0‖, eq. 23.4
  double lyapunov = kNaN;  // ln(‖δ(t)‖ / ‖δ0‖) / (t − t0), eq. 23.5: → the largest Lyapunov exponent
  double t = kNaN;         // the time of the step they stand at
  bool overflowed = false; // ‖δ‖ left the doubles (a chaotic run): they stopped at t
};

}  // namespace noether
