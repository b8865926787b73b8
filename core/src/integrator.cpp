#include <noether/error.hpp>
#include <noether/integrator.hpp>

#include <cmath>
#include <sstream>

namespace noether {

std::int64_t whole_steps(double interval, double h, const char* what, const char* plugin) {
  const double n = std::round(interval / h);
  if (n < 1 || std::abs(n * h - interval) > 1e-9 * interval) {
    std::ostringstream msg;
    msg << plugin << ": " << what << " = " << interval << " is not a whole number of steps of "
        << h << " (" << interval / h << " steps); choose integrator.step = (" << what << ")/N";
    throw SceneError(msg.str());
  }
  return static_cast<std::int64_t>(n);
}

std::vector<double> output_times(double t0, double t_end, double output_every) {
  if (!(output_every > 0.0) || !(t_end > t0))
    throw Error("output times need t_end > t0 and output_every > 0");
  std::vector<double> times{t0};
  for (std::int64_t k = 1;; ++k) {
    const double t = t0 + static_cast<double>(k) * output_every;
    if (t >= t_end - 1e-12 * std::abs(t_end)) break;
    times.push_back(t);
  }
  times.push_back(t_end);
  return times;
}

}  // namespace noether
