// The run summary's structured rows: JSON and text (run/summary_sections.hpp).
#include "run/summary_sections.hpp"

#include "io/json_text.hpp"

#include <cmath>
#include <cstdio>

namespace noether::detail {

namespace {
std::string vector(const Vec3& v) {
  return "[" + json_number(v.x()) + ", " + json_number(v.y()) + ", " + json_number(v.z()) + "]";
}
std::string flag(bool value) { return value ? "true" : "false"; }
std::string printed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}
}  // namespace

std::string forces_json(const RunSummary& s) {
  std::string out = "[";
  for (const ForceSummary& f : s.forces)
    out += std::string(out.size() > 1 ? ", " : "") + "{\"name\": " + json_string(f.name) + ", \"work\": " +
           json_number(f.work) + ", \"linear_momentum\": " + vector(f.linear_momentum) +
           ", \"angular_momentum\": " + vector(f.angular_momentum) + "}";
  return out + "]";
}

std::string forces_lines(const SummaryRow&, const RunSummary& s) {  // docs/forces.md: what each force put in
  std::string out;
  char line[512];
  for (const ForceSummary& f : s.forces) {
    std::snprintf(line, sizeof line, "force %-23s work %+.6g%s, angular momentum put in (%.4g, %.4g, %.4g)%s\n",
                  f.name.c_str(), f.work, summary_unit(s.energy_unit).c_str(), f.angular_momentum.x(),
                  f.angular_momentum.y(), f.angular_momentum.z(),
                  s.energy_unit.empty() ? "" : (" " + s.angular_momentum_unit).c_str());
    out += line;
  }
  return out;
}

std::string particles_json(const RunSummary& s) {  // docs/user-guide.md, "Particles"
  const ParticleSummary& p = s.particles;
  std::string landed = "{";
  for (std::size_t b = 0; b < p.bodies.size(); ++b)
    landed += (b ? ", " : "") + json_string(p.bodies[b]) + ": " + std::to_string(p.impacts[b]);
  std::string fields = "[";
  for (const std::string& f : p.fields) fields += (fields.size() > 1 ? ", " : "") + json_string(f);
  return "{\"count\": " + std::to_string(p.count) + ", \"in_flight\": " + std::to_string(p.in_flight) +
         ", \"escaped\": " + std::to_string(p.escaped) + ", \"landed\": " + landed +
         "}, \"verlet_steps\": " + std::to_string(p.steps) + ", \"seconds\": " + json_number(p.seconds) +
         ", \"fields\": " + fields + "], \"check\": {\"checked\": " + std::to_string(p.check.checked) +
         ", \"fates_differ\": " + std::to_string(p.check.fates_differ) + ", \"position\": " + json_number(p.check.position) +
         ", \"landing_point\": " + json_number(p.check.landing_point) +
         ", \"landing_time\": " + json_number(p.check.landing_time) + ", \"verlet_steps\": " + std::to_string(p.check.steps) +
         "}}";
}

std::string particles_lines(const SummaryRow& row, const RunSummary& s) {
  const ParticleSummary& p = s.particles;
  if (p.count == 0) return "";
  std::string landed;
  for (std::size_t b = 0; b < p.impacts.size(); ++b)
    if (p.impacts[b] > 0) landed += ", " + std::to_string(p.impacts[b]) + " landed on " + p.bodies[b];
  char text[512];
  std::snprintf(text, sizeof text, "%zu: %zu in flight, %zu escaped%s; %.3g us a particle-step", p.count, p.in_flight,
                p.escaped, landed.c_str(),
                p.steps > 0 ? 1e6 * p.seconds / static_cast<double>(p.steps + p.check.steps) : 0.0);
  std::string out = summary_line(row.label, text);
  if (const ParticleCheck& c = p.check; c.checked > 0) {
    std::snprintf(text, sizeof text,
                  "%zu checked: %zu fates differ; in flight moved <= %.2g of their distance, landing points <= %.2g of "
                  "the radius, times <= %.2g%s",
                  c.checked, c.fates_differ, c.position, c.landing_point, c.landing_time,
                  summary_time_unit(s).c_str());
    out += summary_line("particles at half the step", text);
  }
  return out;
}

namespace {
std::string error_json(const DerivedError& e) { return json_number(e.error); }
// How the errors were estimated, or why not ("" when nothing was asked).
std::string error_method(const PeriodChange& c) {
  const DerivedError& e = c.change_error;
  return e.estimated() ? e.method() : e.why_not;
}
}  // namespace

std::string closest_approaches_json(const RunSummary& s) {  // docs/user-guide.md, "Closest approaches"
  std::string out = "[";
  for (const ClosestApproach& c : s.closest_approaches) {
    const DerivedError& e = c.distance_error;
    const std::string method = e.estimated() ? e.method() : e.why_not;
    out += std::string(out.size() > 1 ? ", " : "") + "{\"pair\": " + json_string(c.pair) + ", \"distance\": " +
           json_number(c.distance) + ", \"t\": " + json_number(c.t) + ", \"where\": " + json_string(c.where_text()) +
           ", \"distance_error\": " + error_json(c.distance_error) + ", \"time_error\": " + error_json(c.time_error) +
           ", \"frames_error\": " + json_number(c.frames_error) +
           ", \"frames_time_error\": " + json_number(c.frames_time_error) +
           ", \"error_method\": " + (method.empty() ? "null" : json_string(method)) + "}";
  }
  return out + "]";
}

std::string closest_approaches_lines(const SummaryRow& row, const RunSummary& s) {
  constexpr std::size_t kShown = 10;  // the closest pairs; JSON has them all
  std::string out;
  const std::string length = summary_unit(s.length_unit), time = summary_time_unit(s);
  for (std::size_t k = 0; k < s.closest_approaches.size() && k < kShown; ++k) {
    const ClosestApproach& c = s.closest_approaches[k];
    auto error = [](const DerivedError& e) { return e.estimated() ? " ± " + printed("%.3g", e.error) : std::string(); };
    const char* where = c.where == ClosestApproach::Where::kStart ? ", the start (receding from there)"
                        : c.where == ClosestApproach::Where::kEnd ? ", the end (still closing)"
                                                                  : "";
    out += summary_line(row.label, printed("%.6g", c.distance) + error(c.distance_error) + length + " (" + c.pair +
                                       ") at t = " + printed("%.6g", c.t) + error(c.time_error) + time + where);
  }
  if (s.closest_approaches.size() > kShown)
    out += summary_line("", std::to_string(s.closest_approaches.size() - kShown) +
                                " farther pairs in the JSON summary (closest_approaches)");
  return out;
}

std::string orbit_periods_json(const RunSummary& s) {  // docs/user-guide.md, "Orbit periods"
  std::string out = "[";
  for (const OrbitPeriod& o : s.orbit_periods) {
    const std::string method = o.error.estimated() ? o.error.method() : o.error.why_not;
    out += std::string(out.size() > 1 ? ", " : "") + "{\"body\": " + json_string(o.body) +
           ", \"about\": " + json_string(o.about) + ", \"period\": " + json_number(o.period) +
           ", \"revolutions\": " + std::to_string(o.revolutions) + ", \"undersampled\": " + flag(o.undersampled) +
           ", \"radial\": " + flag(o.radial) + ", \"period_error\": " + error_json(o.error) +
           ", \"error_method\": " + (method.empty() ? "null" : json_string(method)) + "}";
  }
  return out + "]";
}

std::string orbit_periods_lines(const SummaryRow& row, const RunSummary& s) {
  constexpr std::size_t kShown = 10;  // JSON has them all
  std::string out;
  std::size_t shown = 0, measured = 0;
  for (const OrbitPeriod& o : s.orbit_periods) {
    if (o.revolutions < 1 && !o.undersampled) continue;  // less than a revolution (JSON: NaN)
    if (++measured > kShown) continue;
    ++shown;
    const std::string pair = o.body + " about " + o.about + ": ";
    if (o.undersampled) {
      out += summary_line(row.label, pair + "not measured: the frames are more than a third of a turn of its orbit apart "
                                            "(lower run.output_every)");
      continue;
    }
    const DerivedError& e = o.error;
    const std::string error = e.estimated() ? " ± " + printed("%.3g", e.error) : std::string();
    out += summary_line(row.label, pair + printed("%.10g", o.period) + error + " " + s.time_unit +
                                       summary_hours(o.period, s.time_unit) + " (" +
                                       std::to_string(o.revolutions) + " revolution" + (o.revolutions == 1 ? "" : "s") +
                                       ")");
    if (!e.estimated() && !e.why_not.empty()) out += summary_line("", "its error not estimated: " + e.why_not);
  }
  if (measured > shown)
    out += summary_line("", std::to_string(measured - shown) + " more in the JSON summary (orbit_periods)");
  return out;
}

std::string period_changes_json(const RunSummary& s) {  // docs/user-guide.md, "Impulses"
  std::string out = "[";
  for (const PeriodChange& c : s.period_changes)
    out += std::string(out.size() > 1 ? ", " : "") + "{\"t\": " + json_number(c.t) + ", \"before\": " +
           json_number(c.before) + ", \"revolutions_before\": " + std::to_string(c.revolutions_before) +
           ", \"after\": " + json_number(c.after) + ", \"revolutions_after\": " + std::to_string(c.revolutions_after) +
           ", \"change\": " + json_number(c.change()) + ", \"before_error\": " + error_json(c.before_error) +
           ", \"after_error\": " + error_json(c.after_error) + ", \"change_error\": " + error_json(c.change_error) +
           ", \"error_method\": " + (error_method(c).empty() ? "null" : json_string(error_method(c))) + "}";
  return out + "]";
}

std::string period_changes_lines(const SummaryRow& row, const RunSummary& s) {
  std::string out;
  const char* unit = s.time_unit.c_str();
  char text[512];
  for (const PeriodChange& c : s.period_changes) {
    std::snprintf(text, sizeof text, "%s at t = %.6g %s", std::string(row.label).c_str(), c.t, unit);
    const std::string label = text;
    if (!c.measured()) {
      std::snprintf(text, sizeof text,
                    "not measured: %d whole revolution%s timed before it, %d after (a longer stretch on each side?)",
                    c.revolutions_before, c.revolutions_before == 1 ? "" : "s", c.revolutions_after);
      out += summary_line(label, text);
      continue;
    }
    auto error = [&](const DerivedError& e) { return e.estimated() ? " ± " + printed("%.3g", e.error) : std::string(); };
    const std::string minutes = s.time_unit == "s" ? printed(" = %+.6g min", c.change() / 60.0) : "";
    std::snprintf(text, sizeof text, "%.10g%s %s (%d rev.) → %.10g%s %s (%d rev.): ΔP = %+.6g%s %s%s", c.before,
                  error(c.before_error).c_str(), unit, c.revolutions_before, c.after, error(c.after_error).c_str(), unit,
                  c.revolutions_after, c.change(), error(c.change_error).c_str(), unit, minutes.c_str());
    out += summary_line(label, text);
    if (const DerivedError& e = c.change_error; !e.estimated() && !e.why_not.empty())
      out += summary_line("", "its errors not estimated: " + e.why_not);
  }
  return out;
}

std::string spin_states_json(const RunSummary& s) {
  std::string out = "[";
  for (const SpinState& spin : s.spin_states)
    out += std::string(out.size() > 1 ? ", " : "") + "{\"body\": " + json_string(spin.body) +
           ", \"other\": " + (spin.other.empty() ? "null" : json_string(spin.other)) +
           ", \"libration_amplitude\": " + json_number(spin.libration_amplitude) +
           ", \"libration_amplitude_error\": " + json_number(spin.libration_error.error) + ", \"turning_points\": " + std::to_string(spin.turning_points) +
           ", \"libration_period\": " + json_number(spin.libration_period) +
           ", \"libration_period_error\": " + json_number(spin.libration_period_error.error) +
           ", \"libration_period_frames_error\": " + json_number(spin.libration_period_frames_error) +
           ", \"spin_turns\": " + json_number(spin.spin_turns) + ", \"spin_period\": " + json_number(spin.spin_period) +
           ", \"spin_period_error\": " + json_number(spin.spin_period_error.error) +
           ", \"spin_undersampled\": " + flag(spin.spin_undersampled) +
           ", \"spin_tumbling\": " + flag(spin.spin_tumbling) + ", \"turns\": " +
           json_number(spin.turns) + ", \"max_pitch\": " + json_number(spin.max_pitch) +
           ", \"max_roll\": " + json_number(spin.max_roll) + ", \"undersampled\": " + flag(spin.undersampled) +
           ", \"nutation\": " + json_number(spin.nutation) + ", \"max_nutation\": " + json_number(spin.max_nutation) + "}";
  return out + "]";
}

std::string spin_states_lines(const SummaryRow& row, const RunSummary& s) {  // docs/user-guide.md, "Spin state"
  std::string out;
  char part[320];
  const std::string& T = s.time_unit;
  auto error = [](const DerivedError& e) { return e.estimated() ? " ± " + printed("%.3g", e.error) : std::string(); };
  for (const SpinState& spin : s.spin_states) {
    std::string what, periods;
    if (!spin.other.empty()) {
      if (spin.undersampled) {
        what = "libration not measured: the frames are too far apart to follow the yaw (lower run.output_every)";
      } else if (spin.libration_amplitude > 90.0) {
        std::snprintf(part, sizeof part, "circulates, %+.4g turns relative to the line of centres (max pitch %.3g, roll %.3g deg)",
                      spin.turns, spin.max_pitch, spin.max_roll);
        what = part;
      } else if (std::isfinite(spin.libration_amplitude) && spin.turning_points < 2) {
        std::snprintf(part, sizeof part,
                      "swept %.4g deg relative to the line of centres without turning back each way: too short a run "
                      "to tell libration from circulation (max pitch %.3g, roll %.3g deg)",
                      2.0 * spin.libration_amplitude, spin.max_pitch, spin.max_roll);
        what = part;
      } else if (std::isfinite(spin.libration_amplitude)) {
        std::snprintf(part, sizeof part, "librates +-%.4g%s deg about the line of centres (max pitch %.3g, roll %.3g deg)",
                      spin.libration_amplitude, error(spin.libration_error).c_str(), spin.max_pitch, spin.max_roll);
        what = part;
        if (std::isfinite(spin.libration_period)) {
          std::snprintf(part, sizeof part, "libration period %.8g%s %s%s (%d turning points)", spin.libration_period,
                        error(spin.libration_period_error).c_str(), T.c_str(), summary_hours(spin.libration_period, T).c_str(),
                        spin.turning_points);
          periods = part;
        }
      }
    }
    if (std::isfinite(spin.max_nutation))
      std::snprintf(part, sizeof part, "nutation %.3g deg (max %.3g)", spin.nutation, spin.max_nutation);
    else
      std::snprintf(part, sizeof part, "not rotating");
    what += (what.empty() ? "" : "; ") + std::string(part);
    std::snprintf(part, sizeof part, "%s %-18s", std::string(row.label).c_str(), spin.body.c_str());
    out += summary_line(part, what);
    // The rotation period (eq. 17.14), and the libration's, on a line of their own.
    std::string rotation;
    if (std::isfinite(spin.spin_period)) {
      std::snprintf(part, sizeof part, "rotation period %.10g%s %s%s (%.4g turns)", spin.spin_period,
                    error(spin.spin_period_error).c_str(), T.c_str(), summary_hours(spin.spin_period, T).c_str(), spin.spin_turns);
      rotation = part;
    } else if (spin.spin_tumbling) {
      rotation = "rotation period not measured: it tumbles (the axis followed came within 30 deg of its spin's first "
                 "direction)";
    } else if (spin.spin_undersampled) {
      rotation = "rotation period not measured: the frames are too far apart (lower run.output_every)";
    } else if (std::isfinite(spin.spin_turns)) {
      rotation = printed("rotation period not measured: %.3g of a turn in the run", std::abs(spin.spin_turns));
    }
    if (!periods.empty() || !rotation.empty())
      out += summary_line("", periods + (periods.empty() || rotation.empty() ? "" : "; ") + rotation);
  }
  return out;
}

std::string chaos_json(const RunSummary& s) {
  const ChaosValues& c = s.chaos_values;
  return "{\"megno\": " + json_number(c.megno) + ", \"megno_y\": " + json_number(c.megno_y) + ", \"fli\": " +
         json_number(c.fli) + ", \"lyapunov\": " + json_number(c.lyapunov) + ", \"t\": " + json_number(c.t) +
         ", \"overflowed\": " + flag(c.overflowed) + "}";
}

std::string chaos_lines(const SummaryRow& row, const RunSummary& s) {  // docs/derivatives.md, "Chaos indicators"
  if (!s.chaos) return "";
  const ChaosValues& c = s.chaos_values;
  char text[512];
  std::snprintf(text, sizeof text, "MEGNO <Y> = %.6g, FLI = %.4g, lambda ~ ln|delta|/t = %.4g%s%s", c.megno, c.fli,
                c.lyapunov, summary_unit(s.energy_unit.empty() ? "" : "1/" + s.time_unit).c_str(),
                c.overflowed ? " (the deviation overflowed: they stop there)" : "");
  std::string out = summary_line(row.label, text);
  std::snprintf(text, sizeof text, "at t = %.6g (<Y> -> 2 on a regular orbit, ~ lambda t/2 on a chaotic one)", c.t);
  return out + summary_line("", text);
}

std::string orbits_json(const RunSummary& s) {
  std::string out = "[";
  for (const auto& o : s.orbits)
    out += std::string(out.size() > 1 ? ", " : "") + "{\"body\": " + json_string(o.body) + ", \"about\": " +
           json_string(o.about) + ", \"energy_scale\": " + json_number(o.energy_scale) +
           ", \"relative_energy_error\": " + json_number(o.relative_energy_error) +
           ", \"relative_roundoff\": " + json_number(o.relative_roundoff) + "}";
  return out + "]";
}

// The smallest orbit's scale: what the energy error means for the most fragile motion.
std::string orbits_lines(const SummaryRow& row, const RunSummary& s) {
  if (s.orbits.empty()) return "";
  const OrbitScale& o = s.orbits.front();
  char text[512];
  std::snprintf(text, sizeof text, "%s about %s: two-body energy %.4g, |E - E0| %.2e of it (round-off floor %.2e)",
                o.body.c_str(), o.about.c_str(), o.energy_scale, o.relative_energy_error, o.relative_roundoff);
  return summary_line(row.label, text);
}

std::string resolution_json(const RunSummary& s) {
  const ResolutionCheck& c = s.resolution;
  return "{\"body\": " + json_string(c.body) + ", \"about\": " + json_string(c.about) + ", \"window\": " +
         json_number(c.window) + ", \"per_window\": " + json_number(c.per_window) + ", \"over_run\": " +
         json_number(c.over_run) + ", \"whole_run\": " + flag(c.whole_run) + ", \"how\": " + json_string(c.how) +
         ", \"ends_differently\": " + (c.ends_differently.empty() ? std::string("null") : json_string(c.ends_differently)) +
         "}";
}

std::string resolution_lines(const SummaryRow& row, const RunSummary& s) {
  const ResolutionCheck& c = s.resolution;
  if (s.orbits.empty() || !c.done) return "";
  char text[512];
  if (!c.ends_differently.empty())
    std::snprintf(text, sizeof text, "%s about %s: the whole run %s ends otherwise: %s", c.body.c_str(),
                  c.about.c_str(), c.how.c_str(), c.ends_differently.c_str());
  else if (c.whole_run)
    std::snprintf(text, sizeof text, "%s about %s moves by %.2e of its radius over the whole run (repeated %s)",
                  c.body.c_str(), c.about.c_str(), c.over_run, c.how.c_str());
  else
    std::snprintf(text, sizeof text, "%s about %s moves by %.2e of its radius in %.6g, %.2e over the run",
                  c.body.c_str(), c.about.c_str(), c.per_window, c.window, c.over_run);
  return summary_line(row.label, text);
}

std::string pair_models_json(const RunSummary& s) {
  std::string out = "[";
  for (const auto& m : s.pair_models)
    out += std::string(out.size() > 1 ? ", " : "") + "{\"body_a\": " + json_string(m.body_a) + ", \"body_b\": " +
           json_string(m.body_b) + ", \"model\": " + json_string(m.model) + ", \"order\": " + std::to_string(m.order) +
           ", \"estimated_error\": " + json_number(m.estimated_error) + ", \"exceeded\": " + flag(m.exceeded) + "}";
  return out + "]";
}

std::string warnings_json(const RunSummary& s) {
  std::string out = "[";
  for (const std::string& w : s.warnings) out += std::string(out.size() > 1 ? ", " : "") + json_string(w);
  return out + "]";
}

std::string warnings_lines(const SummaryRow& row, const RunSummary& s) {
  std::string out;
  for (const std::string& w : s.warnings) out += summary_line(row.label, w);
  return out;
}

std::string verdict_json(const RunSummary& s) {
  std::string reasons = "[";
  for (const auto& r : s.verdict.reasons) reasons += std::string(reasons.size() > 1 ? ", " : "") + json_string(r);
  return "{\"trustworthy\": " + flag(s.verdict.trustworthy) + ", \"reasons\": " + reasons + "]}";
}

std::string verdict_lines(const SummaryRow& row, const RunSummary& s) {
  if (s.verdict.trustworthy) return summary_line(row.label, "trustworthy");
  std::string out;
  for (const auto& r : s.verdict.reasons) out += summary_line(row.label, "UNTRUSTWORTHY: " + r);
  return out;
}

}  // namespace noether::detail
