#pragma once
// The progress line of `noether run` on stderr, fed by RunOptions::progress.
#include <chrono>
#include <cstdio>
#include <unistd.h>

namespace noether::app {

using Clock = std::chrono::steady_clock;

// Prints "t = … / t_end (…%)" on stderr once a run has taken a few seconds: in place on a
// terminal, as a line every ten seconds otherwise.
class Progress {
 public:
  Progress() : tty_(isatty(STDERR_FILENO) != 0) {}
  // RunOptions::progress: t within the call integrating from t0 to t_end.
  void operator()(double t, double t0, double t_end) {
    t0_ = t0, t_end_ = t_end;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double interval = tty_ ? 0.5 : 10.0;
    if (elapsed < 3.0 || std::chrono::duration<double>(now - last_).count() < interval) return;
    last_ = now;
    const double fraction = (t - t0_) / (t_end_ - t0_);
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "%st = %.6g / %.6g (%3.0f%%), %.1f s elapsed, about %.1f s left%s",
                 tty_ ? "\r" : "", t, t_end_, 100.0 * fraction, elapsed, eta, tty_ ? "" : "\n");
    printed_ = true;
  }
  ~Progress() {
    if (printed_ && tty_) std::fprintf(stderr, "\n");
  }

 private:
  bool tty_;
  double t0_ = 0.0, t_end_ = 1.0;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
  bool printed_ = false;
};

}  // namespace noether::app
