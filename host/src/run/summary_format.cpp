// A run's summary as `noether run` prints it: text, or one JSON object (--summary json).
#include "io/json_text.hpp"

#include <noether/simulation.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace noether {

std::string format_pair_models(const std::vector<PairModel>& models) {
  std::string out;
  char line[512];
  for (const auto& m : models) {
    const std::string pair = "pair " + m.body_a + "–" + m.body_b;
    std::snprintf(line, sizeof line, "%-31s %s, estimated error %.1e at separation %.6g (tolerance %.0e)\n",
                  pair.c_str(), m.model.c_str(), m.estimated_error, m.separation, m.tolerance);
    out += line;
    if (m.exceeded) {
      std::snprintf(line, sizeof line,
                    "%-31s EXCEEDED at t = %.6g: separation %.6g, estimated error %.1e > tolerance %.0e\n", "",
                    m.exceeded_time, m.exceeded_separation, m.exceeded_error, m.tolerance);
      out += line;
    }
  }
  return out;
}

namespace {
// " = 11.9326 h" after a time in seconds (none in other units).
std::string hours(double t, const std::string& unit) {
  if (unit != "s") return "";
  char text[48];
  std::snprintf(text, sizeof text, " = %.6g h", t / 3600.0);
  return text;
}
// " kg m^2/s^2" after a number in declared units (nothing when the scene declares none).
std::string with_unit(const std::string& unit) { return unit.empty() ? "" : " " + unit; }
}  // namespace

std::string format_summary(const RunSummary& s) {
  char buf[2048];
  const double steps = static_cast<double>(std::max<std::int64_t>(1, s.work.steps));
  // Only what the scene conserves, and a closest approach only where there are two bodies.
  std::string optional;
  char line[512];
  if (s.conserves_linear_momentum) {
    std::snprintf(line, sizeof line, "max rel. linear momentum err  %.3e\n", s.max_rel_linear_momentum_error);
    optional += line;
  }
  if (s.conserves_angular_momentum) {
    std::snprintf(line, sizeof line, "max rel. angular momentum err %.3e\n", s.max_rel_angular_momentum_error);
    optional += line;
  }
  if (s.final_state.R.size() > 0) {
    std::snprintf(line, sizeof line, "max ||I - R^T R||_F           %.4e\n", s.max_orthogonality_error);
    optional += line;
  }
  if (std::isfinite(s.min_distance)) {
    std::snprintf(line, sizeof line, "closest approach              %.6g%s (%s) at t = %.6g%s\n", s.min_distance,
                  with_unit(s.length_unit).c_str(), s.min_distance_pair.c_str(), s.t_of_min_distance,
                  with_unit(s.energy_unit.empty() ? "" : s.time_unit).c_str());
    optional += line;
  }
  if (s.impulses > 0) {  // docs/user-guide.md, "Impulses"
    std::snprintf(line, sizeof line,
                  "impulses                      %d applied, energy changed by %+.6g%s (errors measured from the "
                  "references each one moved)\n",
                  s.impulses, s.impulse_energy, with_unit(s.energy_unit).c_str());
    optional += line;
  }
  for (const ForceSummary& f : s.forces) {  // docs/forces.md: what each force put in
    std::snprintf(line, sizeof line, "force %-23s work %+.6g%s, angular momentum put in (%.4g, %.4g, %.4g)%s\n",
                  f.name.c_str(), f.work, with_unit(s.energy_unit).c_str(), f.angular_momentum.x(),
                  f.angular_momentum.y(), f.angular_momentum.z(),
                  s.energy_unit.empty() ? "" : (" " + s.angular_momentum_unit).c_str());
    optional += line;
  }
  if (s.particles.count > 0) {  // docs/user-guide.md, "Particles"
    const ParticleSummary& p = s.particles;
    std::string landed;
    for (std::size_t b = 0; b < p.impacts.size(); ++b)
      if (p.impacts[b] > 0) {
        landed += ", ";
        landed += std::to_string(p.impacts[b]);
        landed += " landed on ";
        landed += p.bodies[b];
      }
    std::snprintf(line, sizeof line, "particles                     %zu: %zu in flight, %zu escaped%s; %.3g us a particle-step\n",
                  p.count, p.in_flight, p.escaped, landed.c_str(),
                  p.steps > 0 ? 1e6 * p.seconds / static_cast<double>(p.steps + p.check.steps) : 0.0);
    optional += line;
    if (const ParticleCheck& c = p.check; c.checked > 0) {
      std::snprintf(line, sizeof line,
                    "particles at half the step    %zu checked: %zu fates differ; in flight moved <= %.2g of their "
                    "distance, landing points <= %.2g of the radius, times <= %.2g%s\n",
                    c.checked, c.fates_differ, c.position, c.landing_point, c.landing_time,
                    with_unit(s.energy_unit.empty() ? "" : s.time_unit).c_str());
      optional += line;
    }
  }
  if (!s.mutual_pair.empty()) {
    if (s.mutual_revolutions > 0) {
      std::snprintf(line, sizeof line, "mutual orbit period           %.10g %s%s (%s, %d revolution%s of the trajectory)\n",
                    s.mutual_period, s.time_unit.c_str(), hours(s.mutual_period, s.time_unit).c_str(),
                    s.mutual_pair.c_str(), s.mutual_revolutions, s.mutual_revolutions == 1 ? "" : "s");
    } else {
      std::snprintf(line, sizeof line, "mutual orbit period           not measured: %s made less than one revolution\n",
                    s.mutual_pair.c_str());
    }
    optional += line;
  }
  for (const SpinState& spin : s.spin_states) {  // docs/user-guide.md, "Spin state"
    std::string what;
    char part[256];
    if (!spin.other.empty()) {
      if (spin.undersampled) {
        what = "libration not measured: the frames are too far apart to follow the yaw (lower run.output_every)";
      } else if (spin.libration_amplitude > 90.0) {
        std::snprintf(part, sizeof part, "circulates, %+.4g turns relative to the line of centres (max pitch %.3g, roll %.3g deg)",
                      spin.turns, spin.max_pitch, spin.max_roll);
        what = part;
      } else if (std::isfinite(spin.libration_amplitude)) {
        std::snprintf(part, sizeof part, "librates +-%.4g deg about the line of centres (max pitch %.3g, roll %.3g deg)",
                      spin.libration_amplitude, spin.max_pitch, spin.max_roll);
        what = part;
      }
    }
    if (std::isfinite(spin.max_nutation))
      std::snprintf(part, sizeof part, "nutation %.3g deg (max %.3g)", spin.nutation, spin.max_nutation);
    else
      std::snprintf(part, sizeof part, "not rotating");
    what += (what.empty() ? "" : "; ") + std::string(part);
    std::snprintf(line, sizeof line, "spin state %-18s %s\n", spin.body.c_str(), what.c_str());
    optional += line;
  }
  if (s.chaos) {  // docs/derivatives.md, "Chaos indicators"
    const ChaosValues& c = s.chaos_values;
    std::snprintf(line, sizeof line, "chaos indicators              MEGNO <Y> = %.6g, FLI = %.4g, lambda ~ ln|delta|/t = %.4g%s%s\n",
                  c.megno, c.fli, c.lyapunov, with_unit(s.energy_unit.empty() ? "" : "1/" + s.time_unit).c_str(),
                  c.overflowed ? " (the deviation overflowed: they stop there)" : "");
    optional += line;
    std::snprintf(line, sizeof line,
                  "                              at t = %.6g (<Y> -> 2 on a regular orbit, ~ lambda t/2 on a chaotic one)\n",
                  c.t);
    optional += line;
  }
  if (!s.orbits.empty()) {
    // The smallest orbit's scale: what the energy error means for the most fragile motion.
    const OrbitScale& o = s.orbits.front();
    std::snprintf(line, sizeof line, "smallest orbit                %s about %s: two-body energy %.4g, |E - E0| %.2e of it\n",
                  o.body.c_str(), o.about.c_str(), o.energy_scale, o.relative_energy_error);
    optional += line;
    const ResolutionCheck& c = s.resolution;
    if (c.done && !c.ends_differently.empty())
      std::snprintf(line, sizeof line, "step-halving check            %s about %s: the whole run at h/2 ends otherwise: %s\n",
                    c.body.c_str(), c.about.c_str(), c.ends_differently.c_str());
    else if (c.done && c.whole_run)
      std::snprintf(line, sizeof line,
                    "step-halving check            %s about %s moves by %.2e of its radius over the whole run (repeated at h/2)\n",
                    c.body.c_str(), c.about.c_str(), c.over_run);
    else if (c.done)
      std::snprintf(line, sizeof line,
                    "step-halving check            %s about %s moves by %.2e of its radius in %.6g, %.2e over the run\n",
                    c.body.c_str(), c.about.c_str(), c.per_window, c.window, c.over_run);
    if (c.done) optional += line;
  }
  // Frames between the method's steps are interpolated states, not the method's own: say so.
  const std::string where_energy =
      s.interpolated_frames > 0 ? ", " + std::to_string(s.interpolated_frames) + " of " + std::to_string(s.frames) +
                                      " interpolated between the method's steps"
                                : "";
  std::snprintf(
      buf, sizeof buf,
      "potential                     %s\n"
      "integrator                    %s\n"
      "E0                            %.10g%s\n"
      "%s%.4e%s (relative to %s: %.2e; at the output frames%s)\n"
      "%s"
      "output frames                 %zu\n"
      "steps                         %lld\n"
      "potential evaluations         %lld\n"
      "Newton iterations per step    %.3f\n"
      "rejected steps                %s\n"
      "wall time                     %.3f s\n",
      s.potential.c_str(), s.integrator.c_str(), s.initial.energy, with_unit(s.energy_unit).c_str(),
      s.forces.empty() ? "max |E - E0|                  " : "max |E - W - E0|              ", s.max_abs_energy_error, with_unit(s.energy_unit).c_str(), s.energy_scale.c_str(), s.max_rel_energy_error, where_energy.c_str(), optional.c_str(), s.frames,
      static_cast<long long>(s.work.steps), static_cast<long long>(s.work.potential_evaluations),
      static_cast<double>(s.work.newton_iterations) / steps,
      s.work.rejected_steps < 0 ? "not reported" : std::to_string(s.work.rejected_steps).c_str(),
      s.wall_seconds);
  std::string out = buf;
  if (!s.units.empty()) out.insert(out.find("E0 "), "units                         " + s.units + "\n");
  if (!s.stop_reason.empty()) out += "stopped early                 " + s.stop_reason + "\n";
  if (s.threads > 1)  // after the wall time, which they shared
    out.insert(out.find("wall time "), "threads                       " + std::to_string(s.threads) + " in each evaluation\n");
  out += format_pair_models(s.pair_models);
  if (s.verdict.trustworthy) {
    out += "verdict                       trustworthy\n";
  } else {
    for (const auto& r : s.verdict.reasons) out += "verdict                       UNTRUSTWORTHY: " + r + "\n";
  }
  return out;
}

using detail::json_number;
using detail::json_string;

std::string format_summary_json(const RunSummary& s) {
  std::ostringstream out;
  auto field = [&out, first = true](const char* name, const std::string& value) mutable {
    out << (first ? "{\n  " : ",\n  ") << json_string(name) << ": " << value;
    first = false;
  };
  field("potential", json_string(s.potential));
  field("integrator", json_string(s.integrator));
  field("units", s.units.empty() ? "null" : json_string(s.units));
  field("E0", json_number(s.initial.energy));
  field("max_abs_energy_error", json_number(s.max_abs_energy_error));
  field("max_rel_energy_error", json_number(s.max_rel_energy_error));
  field("energy_scale", json_string(s.energy_scale));
  field("max_rel_linear_momentum_error",
        s.conserves_linear_momentum ? json_number(s.max_rel_linear_momentum_error) : "null");
  field("max_rel_angular_momentum_error",
        s.conserves_angular_momentum ? json_number(s.max_rel_angular_momentum_error) : "null");
  field("max_orthogonality_error", s.final_state.R.empty() ? "null" : json_number(s.max_orthogonality_error));
  field("closest_approach", json_number(s.min_distance));
  field("t_of_closest_approach", std::isfinite(s.min_distance) ? json_number(s.t_of_min_distance) : "null");
  field("mutual_pair", s.mutual_pair.empty() ? "null" : json_string(s.mutual_pair));
  field("mutual_period", s.mutual_revolutions > 0 ? json_number(s.mutual_period) : "null");
  field("mutual_revolutions", std::to_string(s.mutual_revolutions));
  field("impulses", std::to_string(s.impulses));
  field("impulse_energy", json_number(s.impulse_energy));
  std::string forces = "[";
  auto vector = [](const Vec3& v) {
    std::string out = "[";
    out += json_number(v.x());
    out += ", ";
    out += json_number(v.y());
    out += ", ";
    out += json_number(v.z());
    return out + "]";
  };
  for (const ForceSummary& f : s.forces)
    forces += std::string(forces.size() > 1 ? ", " : "") + "{\"name\": " + json_string(f.name) +
              ", \"work\": " + json_number(f.work) + ", \"linear_momentum\": " + vector(f.linear_momentum) +
              ", \"angular_momentum\": " + vector(f.angular_momentum) + "}";
  field("forces", forces + "]");
  if (s.particles.count > 0) {  // docs/user-guide.md, "Particles"
    const ParticleSummary& p = s.particles;
    std::string landed = "{";
    for (std::size_t b = 0; b < p.bodies.size(); ++b) {
      landed += b ? ", " : "";
      landed += json_string(p.bodies[b]);
      landed += ": ";
      landed += std::to_string(p.impacts[b]);
    }
    std::string fields = "[";
    for (const std::string& f : p.fields) {
      fields += fields.size() > 1 ? ", " : "";
      fields += json_string(f);
    }
    field("particles", "{\"count\": " + std::to_string(p.count) + ", \"in_flight\": " + std::to_string(p.in_flight) +
                           ", \"escaped\": " + std::to_string(p.escaped) + ", \"landed\": " + landed +
                           "}, \"verlet_steps\": " + std::to_string(p.steps) + ", \"seconds\": " + json_number(p.seconds) +
                           ", \"fields\": " + fields + "], \"check\": {\"checked\": " + std::to_string(p.check.checked) +
                           ", \"fates_differ\": " + std::to_string(p.check.fates_differ) +
                           ", \"position\": " + json_number(p.check.position) +
                           ", \"landing_point\": " + json_number(p.check.landing_point) +
                           ", \"landing_time\": " + json_number(p.check.landing_time) +
                           ", \"verlet_steps\": " + std::to_string(p.check.steps) + "}}");
  } else {
    field("particles", "null");
  }
  std::string spins = "[";
  for (const SpinState& spin : s.spin_states)
    spins += std::string(spins.size() > 1 ? ", " : "") + "{\"body\": " + json_string(spin.body) +
             ", \"other\": " + (spin.other.empty() ? "null" : json_string(spin.other)) +
             ", \"libration_amplitude\": " + json_number(spin.libration_amplitude) +
             ", \"turns\": " + json_number(spin.turns) + ", \"max_pitch\": " + json_number(spin.max_pitch) +
             ", \"max_roll\": " + json_number(spin.max_roll) +
             ", \"undersampled\": " + (spin.undersampled ? "true" : "false") +
             ", \"nutation\": " + json_number(spin.nutation) + ", \"max_nutation\": " + json_number(spin.max_nutation) + "}";
  field("spin_states", spins + "]");
  if (s.chaos) {
    const ChaosValues& c = s.chaos_values;
    field("chaos", "{\"megno\": " + json_number(c.megno) + ", \"megno_y\": " + json_number(c.megno_y) +
                       ", \"fli\": " + json_number(c.fli) + ", \"lyapunov\": " + json_number(c.lyapunov) +
                       ", \"t\": " + json_number(c.t) + ", \"overflowed\": " + (c.overflowed ? "true" : "false") + "}");
  } else {
    field("chaos", "null");
  }
  field("closest_approach_pair", std::isfinite(s.min_distance) ? json_string(s.min_distance_pair) : "null");
  std::string orbits = "[";
  for (const auto& o : s.orbits)
    orbits += std::string(orbits.size() > 1 ? ", " : "") + "{\"body\": " + json_string(o.body) +
              ", \"about\": " + json_string(o.about) + ", \"energy_scale\": " + json_number(o.energy_scale) +
              ", \"relative_energy_error\": " + json_number(o.relative_energy_error) + "}";
  field("orbits", orbits + "]");
  field("resolution_check",
        s.resolution.done ? "{\"body\": " + json_string(s.resolution.body) + ", \"about\": " +
                                json_string(s.resolution.about) + ", \"window\": " + json_number(s.resolution.window) +
                                ", \"per_window\": " + json_number(s.resolution.per_window) +
                                ", \"over_run\": " + json_number(s.resolution.over_run) +
                                ", \"whole_run\": " + (s.resolution.whole_run ? "true" : "false") +
                                ", \"ends_differently\": " +
                                (s.resolution.ends_differently.empty() ? std::string("null")
                                                                       : json_string(s.resolution.ends_differently)) + "}"
                          : "null");
  field("output_frames", std::to_string(s.frames));
  field("interpolated_frames", std::to_string(s.interpolated_frames));
  field("final_time", json_number(s.final_state.t));
  field("stop_reason", s.stop_reason.empty() ? "null" : json_string(s.stop_reason));
  field("steps", std::to_string(s.work.steps));
  field("potential_evaluations", std::to_string(s.work.potential_evaluations));
  field("newton_iterations", std::to_string(s.work.newton_iterations));
  field("rejected_steps", s.work.rejected_steps < 0 ? "null" : std::to_string(s.work.rejected_steps));
  field("wall_seconds", json_number(s.wall_seconds));
  field("threads", std::to_string(s.threads));
  std::string models = "[";
  for (const auto& m : s.pair_models)
    models += std::string(models.size() > 1 ? ", " : "") + "{\"body_a\": " + json_string(m.body_a) +
              ", \"body_b\": " + json_string(m.body_b) + ", \"model\": " + json_string(m.model) +
              ", \"order\": " + std::to_string(m.order) + ", \"estimated_error\": " + json_number(m.estimated_error) +
              ", \"exceeded\": " + (m.exceeded ? "true" : "false") + "}";
  field("pair_models", models + "]");
  std::string reasons = "[";
  for (const auto& r : s.verdict.reasons) reasons += std::string(reasons.size() > 1 ? ", " : "") + json_string(r);
  field("verdict", std::string("{\"trustworthy\": ") + (s.verdict.trustworthy ? "true" : "false") +
                       ", \"reasons\": " + reasons + "]}");
  out << "\n}\n";
  return out.str();
}

}  // namespace noether