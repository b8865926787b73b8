// The verdict on a run (docs/user-guide.md, "Verdict"): each check against run.trust.
#include <noether/simulation.hpp>

#include "run/event_watch.hpp"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <limits>
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
  char why[768];
  // The round-off floor of |E − E0| (RunSummary::energy_roundoff): a sum of terms of very
  // different size (a spacecraft's 0.03 J beside a primary's 9e10 J of spin) cannot be known
  // better than ε times their sum, and each step's rounding of the state adds to it.
  const double terms = T0 + std::abs(s.initial.potential);
  s.energy_roundoff = std::numeric_limits<double>::epsilon() * terms *
                      (1.0 + std::sqrt(static_cast<double>(std::max<std::int64_t>(s.work.steps, 0))));
  const bool at_roundoff = s.max_abs_energy_error <= s.energy_roundoff;
  if (s.max_rel_energy_error > limit.energy) {
    std::snprintf(why, sizeof why, "relative energy error %.2e (of %s) > %.0e%s", s.max_rel_energy_error,
                  s.energy_scale.c_str(), limit.energy,
                  at_roundoff ? ", but at the round-off floor of the energy's terms: run.trust.energy asks for more "
                                "than double precision gives (no step or tolerance lowers it)"
                              : "");
    v.reasons.push_back(why);
  }
  // Each orbit on its own scale (a small body's motion is lost in E0): the run's energy error,
  // which includes that orbit's, as a fraction of the orbit's two-body energy. When that cannot
  // certify the smallest orbit, the step-halving check decides, if it ran (fixed-step methods).
  // An orbit whose energy is below the floor's 1/limit cannot be certified by the energy even when
  // its error happens to be small: the resolution check decides.
  for (auto& orbit : s.orbits) {
    orbit.relative_energy_error = orbit.energy_scale > 0 ? s.max_abs_energy_error / orbit.energy_scale : 0.0;
    orbit.relative_roundoff = orbit.energy_scale > 0 ? s.energy_roundoff / orbit.energy_scale : 0.0;
    orbit.uncertified = false;
  }
  if (!s.orbits.empty()) {  // the smallest scale: the largest fraction
    OrbitScale& smallest = s.orbits.front();
    smallest.uncertified = s.max_rel_energy_error <= limit.energy && smallest.energy_scale < scale &&
                           std::max(smallest.relative_energy_error, smallest.relative_roundoff) > limit.energy;
  }
  const ResolutionCheck& check = s.resolution;
  if (check.done) {
    if (!check.ends_differently.empty()) {
      std::snprintf(why, sizeof why, "%s's orbit about %s is not resolved: %s changes how the run ends (%s)",
                    check.body.c_str(), check.about.c_str(), check.change.c_str(), check.ends_differently.c_str());
      v.reasons.push_back(why);
    } else if (check.whole_run && check.over_run > limit.position) {
      std::snprintf(why, sizeof why,
                    "%s's orbit about %s is not resolved: the run repeated %s ends %.2e of its radius away > %.0e "
                    "(%s?)",
                    check.body.c_str(), check.about.c_str(), check.how.c_str(), check.over_run, limit.position,
                    check.remedy.c_str());
      v.reasons.push_back(why);
    } else if (check.over_run > limit.position) {
      std::snprintf(why, sizeof why,
                    "%s's orbit about %s is not resolved: halving the step moves it by %.2e of its radius in one "
                    "orbit (%.6g), %.2e over the run > %.0e (a smaller step?)",
                    check.body.c_str(), check.about.c_str(), check.per_window, check.window, check.over_run,
                    limit.position);
      v.reasons.push_back(why);
    }
  } else if (!s.orbits.empty() && s.orbits.front().uncertified && s.orbits.front().relative_roundoff > limit.energy) {
    const OrbitScale& orbit = s.orbits.front();
    std::snprintf(why, sizeof why,
                  "%s's orbit about %s is not certified: the round-off floor of the energy's terms (%.2e: their sum "
                  "%.3e times the double's epsilon and 1 + sqrt(steps)) is %.2e of the orbit's two-body energy "
                  "(%.3e) > %.0e, so the energy cannot see its errors; no step or tolerance changes that. A run of "
                  "at most %.3g s (run.rerun_seconds) is checked by repeating it when it finishes (at half the step; "
                  "an adaptive method at a tenfold tighter tolerance), or carry %s as a massless particle "
                  "(particles:), whose orbit is integrated and judged on its own",
                  orbit.body.c_str(), orbit.about.c_str(), s.energy_roundoff, terms, orbit.relative_roundoff,
                  orbit.energy_scale, limit.energy, scene.run.rerun_seconds, orbit.body.c_str());
    v.reasons.push_back(why);
  } else if (!s.orbits.empty() && s.orbits.front().uncertified) {
    const OrbitScale& orbit = s.orbits.front();
    std::snprintf(why, sizeof why,
                  "the energy error %.2e is %.2e of the two-body energy of %s's orbit about %s (%.3e) > %.0e: "
                  "its motion is not certified (a fixed-step run checks it by halving the step when it finishes)",
                  s.max_abs_energy_error, orbit.relative_energy_error, orbit.body.c_str(), orbit.about.c_str(),
                  orbit.energy_scale, limit.energy);
    v.reasons.push_back(why);
  }
  for (const auto& m : s.pair_models)
    if (m.exceeded) {
      std::snprintf(why, sizeof why,
                    "the model of pair %s–%s exceeded its tolerance at t = %.6g (separation %.6g, estimated error "
                    "%.1e > %.0e)",
                    m.body_a.c_str(), m.body_b.c_str(), m.exceeded_time, m.exceeded_separation, m.exceeded_error,
                    m.tolerance);
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
  // The particles at half their step (particles.check): their fates, and where those in flight
  // stand and those landed hit, against the run's.
  const ParticleCheck& particles = s.particles.check;
  if (particles.checked > 0) {
    if (static_cast<double>(particles.fates_differ) > limit.particle_fates * static_cast<double>(particles.checked)) {
      std::snprintf(why, sizeof why,
                    "the particles are not resolved: halving their step changes the fate of %zu of the %zu checked "
                    "(> %.3g%%; a smaller particles.step?)",
                    particles.fates_differ, particles.checked, 100 * limit.particle_fates);
      v.reasons.push_back(why);
    }
    // How far halving the step moves them, `what` and of what, against run.trust.position.
    auto moved = [&](double fraction, const char* what, const char* of) {
      if (!(fraction > limit.position)) return;
      std::snprintf(why, sizeof why,
                    "the particles are not resolved: halving their step moves the checked ones%s by up to %.2e of %s "
                    "(> %.0e; a smaller particles.step?)",
                    what, fraction, of, limit.position);
      v.reasons.push_back(why);
    };
    moved(particles.position, " in flight", "their distance from the centre");
    moved(particles.landing_point, "' landing points", "the body's radius");
  }
  // The numbers the run derives, against their errors estimated by the run repeated finer
  // (derived_check.cpp): the step that would meet the tolerance, h (tolerance / error)^(1/p) —
  // with p = 1 when the method does not declare its order, a step small enough for any p ≥ 1 —,
  // or for a method that chooses its steps the rtol, rtol (tolerance / error)^(1/q), q = p/(p+1)
  // (0.5 when not declared).
  // `frames`: the part of the error that is the frames' interpolation (the same in both runs);
  // where it is most of the error, the remedy is frames closer together, not a smaller step.
  auto unresolved = [&](const std::string& what, const DerivedError& e, double value, double tolerance,
                        const char* key, const std::string& unit, double frames = 0.0) {
    if (!e.estimated() || !(e.error > tolerance * std::abs(value))) return;
    const double fraction = e.error / std::abs(value);
    const std::string u = unit.empty() ? "" : " " + unit;
    if (frames >= 0.5 * e.error) {
      std::snprintf(why, sizeof why,
                    "%s is not resolved: its estimated error %.3g%s is %.2e of it > %.0e (run.trust.%s), %.3g%s of it "
                    "the frames' interpolation: frames closer together (a smaller run.output_every) locate it",
                    what.c_str(), e.error, u.c_str(), fraction, tolerance, key, frames, u.c_str());
      v.reasons.push_back(why);
      return;
    }
    const double shrink = std::pow(tolerance / fraction, 1.0 / e.exponent());
    char remedy[256];
    if (e.tolerance_factor == 0.0)
      std::snprintf(remedy, sizeof remedy, "a step of about %.3g %s or less meets it if the error is the step's",
                    e.step * shrink, s.time_unit.c_str());
    else if (e.tolerance * shrink >= 1e-14)
      std::snprintf(remedy, sizeof remedy, "an rtol of about %.2g or less meets it if the error is the tolerance's",
                    e.tolerance * shrink);
    else
      std::snprintf(remedy, sizeof remedy,
                    "it would take an rtol of about %.2g, below what double precision meets: a method of higher "
                    "order, or a fixed-step one whose error is estimated by halving its step",
                    e.tolerance * shrink);
    std::snprintf(why, sizeof why,
                  "%s is not resolved: its estimated error %.3g%s is %.2e of it > %.0e (run.trust.%s; %s); %s (on a "
                  "chaotic orbit none does: run.chaos tells)",
                  what.c_str(), e.error, u.c_str(), fraction, tolerance, key, e.method().c_str(), remedy);
    v.reasons.push_back(why);
  };
  const std::string& T = s.time_unit;
  unresolved("the mutual period of " + s.mutual_pair, s.mutual_period_error, s.mutual_period, limit.period, "period", T);
  for (const OrbitPeriod& o : s.orbit_periods)
    unresolved("the orbit period of " + o.body + " about " + o.about, o.error, o.period, limit.period, "period", T);
  // Each impulse: the period timed before it (those after are the next one's before, or the one
  // above), and ΔP on its own scale.
  for (const PeriodChange& c : s.period_changes) {
    char at[64];
    std::snprintf(at, sizeof at, "%.6g %s", c.t, s.time_unit.c_str());
    unresolved("the mutual period of " + s.mutual_pair + " before the impulse at t = " + at, c.before_error, c.before,
               limit.period, "period", T);
    unresolved("the period change ΔP of " + s.mutual_pair + " at t = " + at, c.change_error, c.change(),
               limit.period_change, "period_change", T);
  }
  // Each body's libration (amplitude and period: run.trust.libration) and rotation period
  // (run.trust.period, as the mutual period's).
  for (const SpinState& spin : s.spin_states) {
    unresolved("the libration amplitude of " + spin.body, spin.libration_error, spin.libration_amplitude,
               limit.libration, "libration", "deg");
    unresolved("the libration period of " + spin.body, spin.libration_period_error, spin.libration_period,
               limit.libration, "libration", T, spin.libration_period_frames_error);
    unresolved("the rotation period of " + spin.body, spin.spin_period_error, spin.spin_period, limit.period, "period",
               T);
  }
  // The event that stopped the run: its time against the time run until it.
  if (is_event(s.stop_reason))
    unresolved("the time of the event that stopped the run (" + s.stop_reason.substr(0, s.stop_reason.find(':')) + ")",
               s.stop_time_error, s.final_state.t - scene.initial.t, limit.event_time, "event_time", T);
  // Each encounter's distance.
  for (const ClosestApproach& c : s.closest_approaches) {
    char at[64];
    std::snprintf(at, sizeof at, "%.6g %s", c.t, s.time_unit.c_str());
    unresolved("the closest approach of " + c.pair + " at t = " + at, c.distance_error, c.distance,
               limit.closest_approach, "closest_approach", s.length_unit, c.frames_error);
  }
  // Bodies inside each other (their surfaces when shaped, else their spheres) by more than the
  // event's root tolerance (a run stopped by a collision ends at contact, to ~1e-10).
  if (s.min_gap < -1e-6 * s.min_gap_reach) {
    std::snprintf(why, sizeof why, "bodies %s overlapped (%.3g inside each other)", s.min_gap_pair.c_str(),
                  -s.min_gap);
    v.reasons.push_back(why);
  }
  v.trustworthy = v.reasons.empty();
}
}  // namespace noether
