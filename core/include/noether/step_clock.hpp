#pragma once
// StepClock: the time of a fixed-step integrator, t = t0 + k h — whole multiples of the step
// since the last restart, not a sum of steps (which drifts by ε per step and would not land on
// the output grid). Kept in the integrator's checkpoint (Integrator::checkpoint): a run continued
// from a step's end then steps through the uninterrupted run's times to the bit, where a clock
// restarted there (t + j h) would round differently — which forces that depend on time (a
// prescribed body's conic, docs/forces.md) would see.
#include <noether/error.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The next step: its size, the time it ends at, and whether it is a whole step h.
struct ClockStep {
  double dt = 0.0, t_next = 0.0;
  bool whole = true;
};

class StepClock {
 public:
  static constexpr std::size_t kCheckpointSize = 2;  // t0 and k

  void start(double t, double h) { t0_ = t_ = t, h_ = h, k_ = 0; }
  double time() const { return t_; }

  // The step towards t_max: a whole step h unless t_max is clearly closer. t = t0 + k h and t_max
  // carry rounding of order ε|t|, which over 10^7 steps exceeds 1e-9 h: a shortened last step
  // there would make a continued run differ from an uninterrupted one in the last bits.
  ClockStep next(double t_max) const {
    const double remaining = t_max - t_;
    if (remaining >= h_ * (1.0 - 1e-9) - 16 * std::numeric_limits<double>::epsilon() * std::abs(t_max))
      return {h_, t0_ + static_cast<double>(k_ + 1) * h_, true};
    return {remaining, t_max, false};
  }
  // The clock at the end of `step` (once it is taken): a shortened step restarts it there.
  void advance(const ClockStep& step) {
    t_ = step.t_next;
    if (step.whole) {
      ++k_;
    } else {
      t0_ = step.t_next, k_ = 0;
    }
  }

  void checkpoint(std::vector<double>& out) const {
    out.push_back(t0_);
    out.push_back(static_cast<double>(k_));
  }
  // The clock from a checkpoint's kCheckpointSize numbers, at a state of time t (started with step
  // h): throws Error, naming `who`, unless they give t.
  void restore(double t, double h, const double* clock, const char* who) {
    const double t0 = clock[0];
    const auto k = static_cast<std::int64_t>(clock[1]);
    if (!(static_cast<double>(k) == clock[1]) || t0 + static_cast<double>(k) * h != t) {
      std::ostringstream msg;
      msg.precision(17);
      msg << who << ": the checkpoint's clock t0 + k h = " << t0 << " + " << clock[1] << " × " << h
          << " is not the state's time " << t << " (a checkpoint of another state or step)";
      throw Error(msg.str());
    }
    t0_ = t0, t_ = t, h_ = h, k_ = k;
  }

 private:
  double t0_ = 0.0, t_ = 0.0, h_ = 0.0;
  std::int64_t k_ = 0;
};

}  // namespace noether

#pragma GCC visibility pop
