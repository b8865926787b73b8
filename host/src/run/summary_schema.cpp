// The run summary's schema (run/summary_schema.hpp): the rows, and what is written from them
// alone — the checkpoint's values, the reference table of docs/user-guide.md. The structures'
// JSON and text (forces, particles, spin states, chaos, orbits, pair models, the verdict) are in
// run/summary_sections.cpp.
#include "run/summary_schema.hpp"

#include "io/h5.hpp"
#include "io/json_text.hpp"
#include "run/summary_sections.hpp"

#include <noether/error.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace noether::detail {

namespace {

using S = const RunSummary&;

std::string printed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

bool conserves_p(S s) { return s.conserves_linear_momentum; }
bool conserves_L(S s) { return s.conserves_angular_momentum; }
bool rigid(S s) { return !s.final_state.R.empty(); }
bool approached(S s) { return std::isfinite(s.min_distance); }
bool gap_seen(S s) { return std::isfinite(s.min_gap); }

// The diagnostics as named numbers ("initial.energy", …) and back.
void save_diagnostics(const std::string& name, const Diagnostics& d, SavedSummary& out) {
  auto put = [&](const char* key, std::vector<double> values) { out.numbers.emplace_back(name + "." + key, std::move(values)); };
  put("kinetic_translational", {d.kinetic_translational});
  put("kinetic_rotational", {d.kinetic_rotational});
  put("potential", {d.potential});
  put("energy", {d.energy});
  put("linear_momentum", {d.linear_momentum.x(), d.linear_momentum.y(), d.linear_momentum.z()});
  put("angular_momentum", {d.angular_momentum.x(), d.angular_momentum.y(), d.angular_momentum.z()});
  put("orthogonality_error", {d.orthogonality_error});
}
Diagnostics restore_diagnostics(const std::string& name, const SavedSummary& in) {
  Diagnostics d;
  d.kinetic_translational = in.require(name + ".kinetic_translational", 1)[0];
  d.kinetic_rotational = in.require(name + ".kinetic_rotational", 1)[0];
  d.potential = in.require(name + ".potential", 1)[0];
  d.energy = in.require(name + ".energy", 1)[0];
  const std::vector<double>& P = in.require(name + ".linear_momentum", 3);
  const std::vector<double>& L = in.require(name + ".angular_momentum", 3);
  d.linear_momentum = Vec3(P[0], P[1], P[2]);
  d.angular_momentum = Vec3(L[0], L[1], L[2]);
  d.orthogonality_error = in.require(name + ".orthogonality_error", 1)[0];
  return d;
}

// The orbits the verdict judges: "body\tabout" lines, and their scales.
void save_orbits(S s, SavedSummary& out) {
  std::string names;
  std::vector<double> scales;
  for (const auto& o : s.orbits) names += o.body + "\t" + o.about + "\n", scales.push_back(o.energy_scale);
  if (scales.empty()) scales.push_back(0.0);  // an attribute of no numbers is refused by HDF5
  out.texts.emplace_back("orbits", names);
  out.numbers.emplace_back("orbits.energy_scale", scales);
}
void restore_orbits(RunSummary& s, const SavedSummary& in) {
  const std::string* names = in.text("orbits");
  if (!names) throw Error("the checkpoint's summary has no orbits");
  s.orbits.clear();
  for (const std::string& line : io::lines_of(*names)) {
    const std::size_t tab = line.find('\t');
    s.orbits.push_back({line.substr(0, tab), tab == std::string::npos ? "" : line.substr(tab + 1), 0.0, 0.0});
  }
  if (s.orbits.empty()) return;
  const std::vector<double>& scales = in.require("orbits.energy_scale", s.orbits.size());
  for (std::size_t k = 0; k < s.orbits.size(); ++k) s.orbits[k].energy_scale = scales[k];
}

// docs/user-guide.md, "Summary reference": each row's use in words.
std::string uses_of(const SummaryRow& row) {
  std::string out;
  auto add = [&out](const char* what) { out += (out.empty() ? "" : ", ") + std::string(what); };
  if (!(row.uses & kNotJson)) add("JSON");
  if (row.uses & kCheckpoint) add("checkpoint");
  if (row.uses & kEnsemble) add("ensemble");
  if (row.uses & kCompare) add("compare");
  return out;
}

// The rows. Lambdas read RunSummary's members; kinds and uses say how each is written.
const SummaryRow kRows[] = {
    {.key = "potential", .kind = Kind::text, .label = "potential", .doc = "the potential's plugins, \"+\"-joined",
     .text = [](S s) { return s.potential; }},
    {.key = "integrator", .kind = Kind::text, .label = "integrator", .doc = "the integrator and its settings",
     .text = [](S s) { return s.integrator; }},
    {.key = "units", .kind = Kind::text, .label = "units", .doc = "the scene's units, when it declares them",
     .text = [](S s) { return s.units; }, .has = [](S s) { return !s.units.empty(); },
     .line = [](const SummaryRow& r, S s) { return s.units.empty() ? "" : summary_line(r.label, s.units); }},
    {.key = "E0", .dimension = Dimension::kEnergy, .label = "E0",
     .doc = "total energy at t0: Σ‖γ‖²/2m + Σ ½ Πᵀ J⁻¹ Π + U",
     .number = [](S s) { return s.initial.energy; },
     .line = [](const SummaryRow& r, S s) { return summary_line(r.label, printed("%.10g", s.initial.energy) + summary_unit(s.energy_unit)); }},
    {.key = "max_abs_energy_error", .dimension = Dimension::kEnergy, .uses = kCheckpoint | kEnsemble | kCompare,
     .label = "max |E - E0|", .heading = "max|dE|",
     .doc = "largest \\|E − E0\\| over the output frames (\\|E − W − E0\\| with forces: their work W counts), with "
            "it relative to the energy scale and the frames interpolated between the method's steps",
     .number = [](S s) { return s.max_abs_energy_error; },
     .line = [](const SummaryRow& r, S s) {
       const std::string interpolated = s.interpolated_frames > 0 ? ", " + std::to_string(s.interpolated_frames) + " of " +
                                                                        std::to_string(s.frames) + " interpolated between the method's steps"
                                                                  : "";
       return summary_line(s.forces.empty() ? r.label : "max |E - W - E0|",
                           printed("%.4e", s.max_abs_energy_error) + summary_unit(s.energy_unit) + " (relative to " +
                               s.energy_scale + ": " + printed("%.2e", s.max_rel_energy_error) + "; at the output frames" +
                               interpolated + ")");
     },
     .restore_number = [](RunSummary& s, double v) { s.max_abs_energy_error = v; }},
    {.key = "max_rel_energy_error", .uses = kEnsemble,
     .doc = "max_abs_energy_error / the energy scale (on the line above)", .number = [](S s) { return s.max_rel_energy_error; }},
    {.key = "energy_roundoff", .dimension = Dimension::kEnergy,
     .doc = "what round-off allows \\|E − E0\\| to reach: ε (T0 + \\|U0\\|) (1 + √steps); an error at this floor is not the "
            "integrator's (docs/user-guide.md \"Verdict\"; on the smallest orbit's line, as a part of its energy)",
     .number = [](S s) { return s.energy_roundoff; }},
    {.key = "energy_scale", .kind = Kind::text,
     .doc = "\\|E0\\|, or the initial kinetic energy T0 when \\|E0\\| < 10⁻³ T0 (on the line above)",
     .text = [](S s) { return s.energy_scale; }},
    {.key = "max_rel_linear_momentum_error", .uses = kCheckpoint, .label = "max rel. linear momentum err",
     .doc = "max ‖P − P0‖ / Σ‖γ_i(0)‖, P = Σ γ_i; only when the scene conserves P",
     .number = [](S s) { return s.max_rel_linear_momentum_error; }, .has = conserves_p,
     .line = [](const SummaryRow& r, S s) {
       return s.conserves_linear_momentum ? summary_line(r.label, printed("%.3e", s.max_rel_linear_momentum_error)) : "";
     },
     .restore_number = [](RunSummary& s, double v) { s.max_rel_linear_momentum_error = v; }},
    {.key = "max_rel_angular_momentum_error", .uses = kCheckpoint | kEnsemble | kCompare,
     .label = "max rel. angular momentum err", .heading = "max dL/L",
     .doc = "max ‖L − L0‖ / (Σ‖x_i × γ_i‖ + Σ‖Π_k‖ at t0), L = Σ(x_i × γ_i + R_k Π_k) about the origin; only when "
            "the scene conserves L",
     .number = [](S s) { return s.max_rel_angular_momentum_error; }, .has = conserves_L,
     .line = [](const SummaryRow& r, S s) {
       return s.conserves_angular_momentum ? summary_line(r.label, printed("%.3e", s.max_rel_angular_momentum_error)) : "";
     },
     .restore_number = [](RunSummary& s, double v) { s.max_rel_angular_momentum_error = v; }},
    {.key = "max_orthogonality_error", .uses = kCheckpoint | kCompare, .label = "max ||I - R^T R||_F",
     .heading = "max orth",
     .doc = "largest Frobenius-norm distance of an attitude from SO(3); scenes with rigid bodies",
     .number = [](S s) { return s.max_orthogonality_error; }, .has = rigid,
     .line = [](const SummaryRow& r, S s) { return rigid(s) ? summary_line(r.label, printed("%.4e", s.max_orthogonality_error)) : ""; },
     .restore_number = [](RunSummary& s, double v) { s.max_orthogonality_error = v; }},
    {.key = "conserves_linear_momentum", .kind = Kind::flag, .uses = kCheckpoint,
     .doc = "whether the scene conserves P (no net external force at t0): the P error is reported",
     .number = [](S s) { return s.conserves_linear_momentum ? 1.0 : 0.0; },
     .restore_number = [](RunSummary& s, double v) { s.conserves_linear_momentum = v != 0; }},
    {.key = "conserves_angular_momentum", .kind = Kind::flag, .uses = kCheckpoint,
     .doc = "whether the scene conserves L (no net external torque about the origin at t0)",
     .number = [](S s) { return s.conserves_angular_momentum ? 1.0 : 0.0; },
     .restore_number = [](RunSummary& s, double v) { s.conserves_angular_momentum = v != 0; }},
    {.key = "closest_approach", .dimension = Dimension::kLength, .uses = kCheckpoint | kEnsemble,
     .label = "closest approach",
     .doc = "smallest distance between two body centres: the least of `closest_approaches` (scenes of 2 to 12 "
            "bodies; its line is theirs), else seen at the output frames (13 to 64 bodies); the pair and the time",
     .number = [](S s) { return s.min_distance; }, .has = approached,
     .line = [](const SummaryRow& r, S s) {
       if (!s.closest_approaches.empty()) return closest_approaches_lines(r, s);
       return approached(s) ? summary_line(r.label, printed("%.6g", s.min_distance) + summary_unit(s.length_unit) + " (" +
                                                         s.min_distance_pair + ") at t = " +
                                                         printed("%.6g", s.t_of_min_distance) + summary_time_unit(s))
                            : "";
     },
     .restore_number = [](RunSummary& s, double v) { s.min_distance = v; }},
    {.key = "t_of_closest_approach", .dimension = Dimension::kTime, .uses = kCheckpoint,
     .doc = "when the closest approach was seen (on its line)", .number = [](S s) { return s.t_of_min_distance; },
     .has = approached,
     .restore_number = [](RunSummary& s, double v) { s.t_of_min_distance = v; }},
    {.key = "closest_approach_pair", .kind = Kind::text, .uses = kCheckpoint,
     .doc = "the bodies of the closest approach, \"a–b\" (on its line)", .text = [](S s) { return s.min_distance_pair; },
     .has = approached,
     .restore_text = [](RunSummary& s, const std::string& v) { s.min_distance_pair = v; }},
    {.key = "closest_approaches", .kind = Kind::structure,
     .doc = "per pair of bodies (scenes of 2 to 12), the closest first: the least distance of their centres located "
            "between frames on the Hermite of their relative motion (`where`: `encounter`, or the segment's `start` "
            "when they recede from there, or the run's `end` when still closing), its time, their errors by the run "
            "repeated at half the step (`distance_error`, which includes `frames_error`, the interpolation's bound; "
            "`time_error`; `error_method`: how, or why not); the 10 closest on the closest approach lines "
            "(docs/user-guide.md \"Closest approaches\")",
     .json = closest_approaches_json},
    {.key = "smallest_gap", .dimension = Dimension::kLength, .uses = kCheckpoint,
     .doc = "the smallest gap seen between two bodies with radii: between their surfaces when one has a solid shape "
            "(docs/equations.md eq. 16.5), else ‖x_a − x_b‖ − (r_a + r_b)",
     .number = [](S s) { return s.min_gap; }, .has = gap_seen,
     .restore_number = [](RunSummary& s, double v) { s.min_gap = v; }},
    {.key = "smallest_gap_reach", .dimension = Dimension::kLength, .uses = kCheckpoint,
     .doc = "r_a + r_b of the smallest gap's pair", .number = [](S s) { return s.min_gap_reach; }, .has = gap_seen,
     .restore_number = [](RunSummary& s, double v) { s.min_gap_reach = v; }},
    {.key = "smallest_gap_pair", .kind = Kind::text, .uses = kCheckpoint, .doc = "the smallest gap's bodies, \"a–b\"",
     .text = [](S s) { return s.min_gap_pair; }, .has = gap_seen,
     .restore_text = [](RunSummary& s, const std::string& v) { s.min_gap_pair = v; }},
    {.key = "impulses", .kind = Kind::integer, .uses = kCheckpoint, .label = "impulses",
     .doc = "the scene's impulses applied (in this segment), and the energy they changed (docs/user-guide.md \"Impulses\")",
     .number = [](S s) { return double(s.impulses); },
     .line = [](const SummaryRow& r, S s) {
       return s.impulses > 0 ? summary_line(r.label, std::to_string(s.impulses) + " applied, energy changed by " +
                                                         printed("%+.6g", s.impulse_energy) + summary_unit(s.energy_unit) +
                                                         " (errors measured from the references each one moved)")
                             : "";
     },
     .restore_number = [](RunSummary& s, double v) { s.impulses = static_cast<int>(v); }},
    {.key = "impulse_energy", .dimension = Dimension::kEnergy, .uses = kCheckpoint,
     .doc = "the energy the impulses changed (on their line)", .number = [](S s) { return s.impulse_energy; },
     .restore_number = [](RunSummary& s, double v) { s.impulse_energy = v; }},
    {.key = "forces", .kind = Kind::structure, .label = "force",
     .doc = "per force beyond the potential: name, work, linear and angular momentum put in (docs/forces.md)",
     .json = forces_json, .line = forces_lines},
    {.key = "particles", .kind = Kind::structure, .label = "particles",
     .doc = "the massless particles: count, in flight, escaped, landed per body, the step-halving check (null: none)",
     .has = [](S s) { return s.particles.count > 0; }, .json = particles_json, .line = particles_lines},
    {.key = "mutual_period", .dimension = Dimension::kTime, .uses = kEnsemble, .label = "mutual orbit period",
     .doc = "a two-body-like scene's mutual orbit period from the trajectory: the last whole revolution's time / "
            "the revolutions",
     .number = [](S s) { return s.mutual_period; }, .has = [](S s) { return s.mutual_revolutions > 0; },
     .line = [](const SummaryRow& r, S s) -> std::string {
       if (s.mutual_pair.empty()) return "";
       if (s.mutual_undersampled)
         return summary_line(r.label, "not measured: the frames are too far apart to follow the orbit of " +
                                          s.mutual_pair + " (more than a third of a turn; lower run.output_every)");
       if (s.mutual_revolutions == 0)
         return summary_line(r.label, "not measured: " + s.mutual_pair + " made less than one revolution");
       const DerivedError& e = s.mutual_period_error;
       const std::string error = e.estimated() ? " ± " + printed("%.3g", e.error) + " " + s.time_unit + " (" + e.method() + ")"
                                 : e.why_not.empty() ? ""
                                                     : "; its error not estimated: " + e.why_not;
       return summary_line(r.label, printed("%.10g", s.mutual_period) + " " + s.time_unit + summary_hours(s.mutual_period, s.time_unit) +
                                        " (" + s.mutual_pair + ", " + std::to_string(s.mutual_revolutions) + " revolution" +
                                        (s.mutual_revolutions == 1 ? "" : "s") + " of the trajectory)" + error);
     }},
    {.key = "mutual_period_error", .dimension = Dimension::kTime, .uses = kEnsemble,
     .doc = "the mutual period's estimated error, by the run repeated at half the step, or at a tenfold tighter "
            "tolerance (docs/user-guide.md \"Verdict\"; on its line)",
     .number = [](S s) { return s.mutual_period_error.error; },
     .has = [](S s) { return s.mutual_period_error.estimated(); }},
    {.key = "mutual_period_at_half_step", .dimension = Dimension::kTime,
     .doc = "the mutual period of the run repeated at half the step, or at the other tolerance (on its line)",
     .number = [](S s) { return s.mutual_period_error.at_half_step; },
     .has = [](S s) { return s.mutual_period_error.estimated(); }},
    {.key = "mutual_period_error_method", .kind = Kind::text,
     .doc = "how the mutual period's error was estimated, or why it was not (on its line)",
     .text = [](S s) {
       return s.mutual_period_error.estimated() ? s.mutual_period_error.method() : s.mutual_period_error.why_not;
     },
     .has = [](S s) { return s.mutual_period_error.estimated() || !s.mutual_period_error.why_not.empty(); }},
    {.key = "mutual_pair", .kind = Kind::text, .doc = "the mutual orbit's bodies, \"a–b\" (on its line)",
     .text = [](S s) { return s.mutual_pair; }, .has = [](S s) { return !s.mutual_pair.empty(); }},
    {.key = "mutual_revolutions", .kind = Kind::integer, .doc = "the whole revolutions timed (on its line)",
     .number = [](S s) { return double(s.mutual_revolutions); }},
    {.key = "mutual_undersampled", .kind = Kind::flag,
     .doc = "the frames were more than a third of a turn of the mutual orbit apart: its period is not measured "
            "(on its line)",
     .number = [](S s) { return s.mutual_undersampled ? 1.0 : 0.0; }},
    {.key = "orbit_periods", .kind = Kind::structure, .label = "orbit period",
     .doc = "each body's orbit about the body, at least as heavy, to which it is bound with the smallest "
            "semi-major axis at the start, but the binary's (scenes of 3 to 64 bodies): `period` measured from the "
            "trajectory as the mutual period is, over `revolutions` since the start or the last impulse (NaN before "
            "one; `undersampled`: frames too far apart; `radial`: a fall), "
            "`period_error` by the run repeated finer (`error_method`); docs/user-guide.md \"Orbit periods\"",
     .json = orbit_periods_json, .line = orbit_periods_lines},
    {.key = "period_changes", .kind = Kind::structure, .label = "period change",
     .doc = "per impulse (jumps at one instant are one) of a two-body-like scene: the mutual period timed before "
            "and after it (`before`, `after`, from the jump before or the start, to the next or the end; "
            "`revolutions_before`, `revolutions_after`), `change` = after − before (ΔP), each one's error by the run "
            "repeated at half the step (`before_error`, `after_error`, `change_error`: ΔP's own change; "
            "`error_method`: how, or why not); docs/user-guide.md \"Impulses\"",
     .json = period_changes_json, .line = period_changes_lines},
    {.key = "spin_states", .kind = Kind::structure, .label = "spin state",
     .doc = "per rigid body: libration about its binary's line of centres (amplitude and period, with their "
            "errors), or its turns; its rotation period with its error; and nutation (docs/user-guide.md \"Spin "
            "state\")",
     .json = spin_states_json, .line = spin_states_lines},
    {.key = "chaos", .kind = Kind::structure, .label = "chaos indicators",
     .doc = "MEGNO, its ⟨Y⟩, FLI, ln‖δ‖/t and the time, with run.chaos (docs/derivatives.md)",
     .has = [](S s) { return s.chaos; }, .json = chaos_json, .line = chaos_lines},
    {.key = "orbits", .kind = Kind::structure, .uses = kCheckpoint, .label = "smallest orbit",
     .doc = "the orbits the verdict judges on their own energy scale, the smallest first (docs/user-guide.md \"Verdict\")",
     .json = orbits_json, .line = orbits_lines, .save = save_orbits, .restore = restore_orbits},
    {.key = "resolution_check", .kind = Kind::structure, .label = "resolution check",
     .doc = "the smallest orbit repeated at half the step (an adaptive method: at a tenfold tighter tolerance), when the energy cannot certify it",
     .has = [](S s) { return s.resolution.done; }, .json = resolution_json, .line = resolution_lines},
    {.key = "initial", .kind = Kind::structure, .uses = kNotJson | kCheckpoint,
     .doc = "the diagnostics at t0 (energies, momenta), from which the errors are measured",
     .save = [](S s, SavedSummary& out) { save_diagnostics("initial", s.initial, out); },
     .restore = [](RunSummary& s, const SavedSummary& in) { s.initial = restore_diagnostics("initial", in); }},
    {.key = "final", .kind = Kind::structure, .uses = kNotJson | kCheckpoint, .doc = "the diagnostics at the last frame",
     .save = [](S s, SavedSummary& out) { save_diagnostics("final", s.final, out); },
     .restore = [](RunSummary& s, const SavedSummary& in) { s.final = restore_diagnostics("final", in); }},
    {.key = "output_frames", .kind = Kind::integer, .uses = kCheckpoint, .label = "output frames",
     .doc = "frames written (and judged)", .number = [](S s) { return double(s.frames); },
     .restore_number = [](RunSummary& s, double v) { s.frames = static_cast<std::size_t>(v); }},
    {.key = "interpolated_frames", .kind = Kind::integer,
     .doc = "frames interpolated between the method's steps (on the energy's line)",
     .number = [](S s) { return double(s.interpolated_frames); }},
    {.key = "final_time", .dimension = Dimension::kTime, .uses = kEnsemble, .doc = "the time the run ended at",
     .number = [](S s) { return s.final_state.t; }},
    {.key = "steps", .kind = Kind::integer, .uses = kEnsemble | kCompare, .label = "steps",
     .doc = "the integrator's steps", .number = [](S s) { return double(s.work.steps); }},
    {.key = "potential_evaluations", .kind = Kind::integer, .uses = kEnsemble | kCompare,
     .label = "potential evaluations", .heading = "U evals", .doc = "evaluations of the potential (forces and torques)",
     .number = [](S s) { return double(s.work.potential_evaluations); }},
    {.key = "newton_iterations", .kind = Kind::integer, .label = "Newton iterations per step",
     .doc = "summed over the rigid bodies (the LGVI solves (128) once per rigid body per step); the text gives them per step",
     .number = [](S s) { return double(s.work.newton_iterations); },
     .line = [](const SummaryRow& r, S s) {
       const double steps = static_cast<double>(std::max<std::int64_t>(1, s.work.steps));
       return summary_line(r.label, printed("%.3f", static_cast<double>(s.work.newton_iterations) / steps));
     }},
    {.key = "rejected_steps", .kind = Kind::integer, .uses = kCompare, .label = "rejected steps",
     .doc = "steps an adaptive method rejected (null: the method does not report them)",
     .number = [](S s) { return double(s.work.rejected_steps); }, .has = [](S s) { return s.work.rejected_steps >= 0; },
     .line = [](const SummaryRow& r, S s) {
       return summary_line(r.label, s.work.rejected_steps < 0 ? "not reported" : std::to_string(s.work.rejected_steps));
     }},
    {.key = "threads", .kind = Kind::integer, .label = "threads", .doc = "threads in each evaluation of the potential",
     .number = [](S s) { return double(s.threads); },
     .line = [](const SummaryRow& r, S s) {
       return s.threads > 1 ? summary_line(r.label, std::to_string(s.threads) + " in each evaluation") : "";
     }},
    {.key = "wall_seconds", .dimension = Dimension::kWallSeconds, .label = "wall time", .doc = "the run's wall time in seconds",
     .number = [](S s) { return s.wall_seconds; },
     .line = [](const SummaryRow& r, S s) { return summary_line(r.label, printed("%.3f", s.wall_seconds) + " s"); }},
    {.key = "stop_reason", .kind = Kind::text, .uses = kCheckpoint, .label = "stopped early",
     .doc = "why the run ended before t_end (an event, an interrupt, the wall-time budget); null: it reached t_end",
     .text = [](S s) { return s.stop_reason; }, .has = [](S s) { return !s.stop_reason.empty(); },
     .line = [](const SummaryRow& r, S s) {
       if (s.stop_reason.empty()) return std::string();
       const DerivedError& e = s.stop_time_error;
       return summary_line(r.label, s.stop_reason + (e.estimated() ? " ± " + printed("%.3g", e.error) : std::string()));
     },
     .restore_text = [](RunSummary& s, const std::string& v) { s.stop_reason = v; }},
    {.key = "stop_time_error", .dimension = Dimension::kTime,
     .doc = "the time of the event that stopped the run (a collision, an escape): its estimated error, by the run "
            "repeated at half the step stopping at the same event (on its line)",
     .number = [](S s) { return s.stop_time_error.error; }, .has = [](S s) { return s.stop_time_error.estimated(); }},
    {.key = "pair_models", .kind = Kind::structure, .label = "pair",
     .doc = "what a tolerance-driven potential chose per pair, its estimated error, and whether it was exceeded",
     .json = pair_models_json, .line = [](const SummaryRow&, S s) { return format_pair_models(s.pair_models); }},
    {.key = "warnings", .kind = Kind::structure, .label = "warning",
     .doc = "what in the scene's input looks mistaken, with the numbers (a spin past breakup, a step longer than "
            "the shortest period, a density no body has: docs/user-guide.md \"Units\"; an impulse that unbinds a "
            "bound pair: \"Impulses\"); the run is not judged by them",
     .json = warnings_json, .line = warnings_lines},
    {.key = "verdict", .kind = Kind::structure, .label = "verdict",
     .doc = "`trustworthy`, or one `UNTRUSTWORTHY: …` line per failed check (docs/user-guide.md \"Verdict\")",
     .json = verdict_json, .line = verdict_lines},
};

}  // namespace

const std::vector<double>* SavedSummary::number(std::string_view key) const {
  for (const auto& [name, values] : numbers)
    if (name == key) return &values;
  return nullptr;
}
const std::vector<double>& SavedSummary::require(std::string_view key, std::size_t size) const {
  const std::vector<double>* v = number(key);
  if (!v) throw Error("the checkpoint's summary has no " + std::string(key));
  if (v->size() != size)
    throw Error("the checkpoint's summary " + std::string(key) + " has " + std::to_string(v->size()) +
                " numbers, not " + std::to_string(size));
  return *v;
}
const std::string* SavedSummary::text(std::string_view key) const {
  for (const auto& [name, value] : texts)
    if (name == key) return &value;
  return nullptr;
}

std::span<const SummaryRow> summary_rows() { return kRows; }

const SummaryRow& summary_row(std::string_view key) {
  for (const SummaryRow& row : kRows)
    if (row.key == key) return row;
  throw std::out_of_range("the run summary has no row " + std::string(key));
}

std::vector<const SummaryRow*> summary_rows_for(SummaryUse use) {
  std::vector<const SummaryRow*> out;
  for (const SummaryRow& row : kRows)
    if (row.uses & use) out.push_back(&row);
  return out;
}

std::string summary_line(std::string_view label, const std::string& text) {
  std::string out(label);
  out.resize(std::max<std::size_t>(out.size() + 1, 30), ' ');
  return out + text + "\n";
}

std::string summary_unit(const std::string& unit) { return unit.empty() ? "" : " " + unit; }
std::string summary_time_unit(const RunSummary& s) { return summary_unit(s.energy_unit.empty() ? "" : s.time_unit); }
std::string summary_hours(double t, const std::string& unit) {
  return unit == "s" ? printed(" = %.6g h", t / 3600.0) : "";
}

std::string summary_value_text(const SummaryRow& row, const RunSummary& s) {
  switch (row.kind) {
    case Kind::number: return printed("%.6g", row.number(s));
    case Kind::integer: return std::to_string(static_cast<long long>(row.number(s)));
    case Kind::flag: return row.number(s) != 0 ? "yes" : "no";
    case Kind::text: return row.text(s);
    case Kind::structure: break;
  }
  return row.json(s);
}

std::string summary_value_json(const SummaryRow& row, const RunSummary& s) {
  if (row.has && !row.has(s)) return "null";
  switch (row.kind) {
    case Kind::number: return json_number(row.number(s));
    case Kind::integer: return std::to_string(static_cast<long long>(row.number(s)));
    case Kind::flag: return row.number(s) != 0 ? "true" : "false";
    case Kind::text: return json_string(row.text(s));
    case Kind::structure: break;
  }
  return row.json(s);
}

SavedSummary save_summary(const RunSummary& s) {
  SavedSummary out;
  for (const SummaryRow* row : summary_rows_for(kCheckpoint)) {
    if (row->save)
      row->save(s, out);
    else if (row->kind == Kind::text)
      out.texts.emplace_back(row->key, row->text(s));
    else
      out.numbers.emplace_back(row->key, std::vector<double>{row->number(s)});
  }
  return out;
}

void restore_summary(RunSummary& s, const SavedSummary& in) {
  for (const SummaryRow* row : summary_rows_for(kCheckpoint)) {
    const std::string key(row->key);
    if (row->restore) {
      row->restore(s, in);
    } else if (row->kind == Kind::text) {
      const std::string* text = in.text(key);
      if (!text) throw Error("the checkpoint's summary has no " + key);
      row->restore_text(s, *text);
    } else {
      row->restore_number(s, in.require(key, 1)[0]);
    }
  }
}

SavedSummary upgrade_saved_summary(SavedSummary in) {
  // Checkpoints from before the impulses' rows were kept: saving a run with impulses was refused.
  if (!in.number("impulses")) in.numbers.insert(in.numbers.end(), {{"impulses", {0.0}}, {"impulse_energy", {0.0}}});
  if (!in.number("statistics")) return in;
  // The layout of Simulation::save before the schema: numbers by position.
  const char* const statistics[] = {"max_abs_energy_error", "max_rel_linear_momentum_error",
                                    "max_rel_angular_momentum_error", "max_orthogonality_error",
                                    "conserves_linear_momentum", "conserves_angular_momentum", "smallest_gap",
                                    "smallest_gap_reach", "closest_approach", "t_of_closest_approach",
                                    "linear_momentum_scale", "angular_momentum_scale"};
  const char* const diagnostics[] = {"kinetic_translational", "kinetic_rotational", "potential", "energy",
                                     "linear_momentum", "angular_momentum", "orthogonality_error"};
  const std::size_t diagnostic_sizes[] = {1, 1, 1, 1, 3, 3, 1};
  SavedSummary out;
  for (auto& [name, values] : in.numbers) {
    if (name == "statistics" && values.size() == std::size(statistics)) {
      for (std::size_t k = 0; k < values.size(); ++k) out.numbers.push_back({statistics[k], {values[k]}});
    } else if ((name == "initial" || name == "final") && values.size() == 11) {
      std::size_t at = 0;
      for (std::size_t k = 0; k < std::size(diagnostics); at += diagnostic_sizes[k++])
        out.numbers.push_back({name + "." + diagnostics[k],
                               std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(at),
                                                   values.begin() + static_cast<std::ptrdiff_t>(at + diagnostic_sizes[k]))});
    } else if (name == "frames") {
      out.numbers.push_back({"output_frames", values});
    } else if (name == "orbit_scales") {
      out.numbers.push_back({"orbits.energy_scale", values});
    } else if (name == "exchanged_momenta" && values.size() == 2) {
      out.numbers.push_back({"exchanged_linear_momentum", {values[0]}});
      out.numbers.push_back({"exchanged_angular_momentum", {values[1]}});
    } else {
      out.numbers.emplace_back(std::move(name), std::move(values));
    }
  }
  for (auto& [name, text] : in.texts)
    out.texts.emplace_back(name == "min_gap_pair"        ? "smallest_gap_pair"
                           : name == "min_distance_pair" ? "closest_approach_pair"
                                                         : name,
                           std::move(text));
  return out;
}

std::string summary_reference_markdown() {
  std::string out =
      "| key | text line | unit | written to | meaning |\n"
      "|-----|-----------|------|------------|---------|\n";
  for (const SummaryRow& row : kRows) {
    // In symbols (L, M, T: a scene's units when it declares none); none for a number.
    const std::string unit = row.dimension == Dimension::kOne ? "" : io::unit_of(row.dimension, Units{});
    std::string label;  // a table cell: its pipes escaped, in code too
    for (const char c : row.label) label += c == '|' ? std::string("\\|") : std::string(1, c);
    out += "| `" + std::string(row.key) + "` | " + (label.empty() ? "" : "`" + label + "`") + " | " +
           unit + " | " + uses_of(row) + " | " + std::string(row.doc) + " |\n";
  }
  return out;
}

}  // namespace noether::detail
