// noether orbit equilibrium, and noether orbit stability on scenes with rigid bodies: relative
// equilibria and relative periodic orbits of the full body problem (docs/relative-equilibria.md,
// docs/equations.md §18–19).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/lyapunov_orbit.hpp>
#include <noether/relative_equilibrium.hpp>
#include <noether/relative_periodic_orbit.hpp>
#include <noether/scene.hpp>
#include <noether/scene_with_state.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

namespace noether::app {

namespace {

// Which Jacobian the shooting used (docs/equations.md eq. 19.5).
void print_newton_jacobian(const noether::RelativePeriodicOrbit& orbit) {
  std::printf("Newton's Jacobian: %s\n", orbit.jacobian == "tangent map"
                                              ? "the integrator's tangent map (docs/equations.md eq. 19.6)"
                                              : "differences of the map (this integrator has no tangent map)");
}

std::size_t body_index(const noether::System& system, const std::string& name_or_index) {
  const int i = system.index_of(name_or_index);
  if (i >= 0) return static_cast<std::size_t>(i);
  try {
    std::size_t used = 0;
    const long k = std::stol(name_or_index, &used);
    if (used == name_or_index.size() && k >= 0 && static_cast<std::size_t>(k) < system.size())
      return static_cast<std::size_t>(k);
  } catch (const std::exception&) {
  }
  throw noether::SceneError("orbit equilibrium --pair: no body '" + name_or_index + "' in the scene (give names or indices)");
}

noether::EquilibriumFamily family(const std::string& fix) {
  if (fix == "angular-momentum") return noether::EquilibriumFamily::angular_momentum;
  if (fix == "rate") return noether::EquilibriumFamily::rate;
  return noether::EquilibriumFamily::separation;
}

// The angle between a rigid body's long axis (least moment) and the line to the other body of
// the pair, in degrees, folded into [0, 90].
double long_axis_angle(const noether::System& system, const noether::State& s, std::size_t body, std::size_t other) {
  const int r = system.rigid_index(body);
  if (r < 0) return NAN;
  Eigen::SelfAdjointEigenSolver<noether::Mat3> es(system.body(body).inertia);
  const noether::Vec3 axis = s.R[static_cast<std::size_t>(r)] * es.eigenvectors().col(0);
  const noether::Vec3 line = (s.x.col(static_cast<Eigen::Index>(other)) - s.x.col(static_cast<Eigen::Index>(body))).normalized();
  return std::acos(std::min(1.0, std::abs(axis.dot(line)))) * 180 / std::numbers::pi;
}

// An equilibrium inside the bodies' bounding spheres is found all the same, and flagged.
void warn_if_overlapping(const noether::RelativeEquilibrium& eq) {
  if (eq.contact > 0 && eq.separation <= eq.contact)
    std::printf("warning: the bodies' bounding spheres overlap here (separation %.6g <= %.6g, the sum of their radii): "
                "the bodies may touch, and a series model may not converge; this equilibrium may not be physical\n",
                eq.separation, eq.contact);
}

// The oscillating mode dominated by BODY's libration (--libration, --lyapunov).
const noether::NormalMode& libration_mode(const noether::System& system, const noether::EquilibriumStability& st,
                                          std::size_t body, const std::string& option) {
  if (const auto* mode = noether::libration_mode(st, system.body(body).name)) return *mode;
  throw noether::SceneError("orbit equilibrium " + option + ": no oscillating mode of this equilibrium is dominated by the "
                            "libration of '" + system.body(body).name + "' (see the modes above)");
}

// A libration amplitude in degrees from NAME,DEG, checked.
double libration_degrees(const std::string& text, const std::string& option) {
  double degrees = 0;
  try {
    degrees = std::stod(text);
  } catch (const std::exception&) {
    throw noether::SceneError("orbit equilibrium " + option + " NAME,DEG: '" + text + "' is not an angle in degrees");
  }
  if (!(std::abs(degrees) > 0 && std::abs(degrees) < 45))
    throw noether::SceneError("orbit equilibrium " + option + ": give an angle between 0 and 45 degrees (not " + text +
                              "): small amplitudes are what the linearisation predicts");
  return degrees;
}

// --libration NAME,DEG: the equilibrium with that rigid body turned by DEG about k̂, keeping its
// inertial angular velocity ω k̂, so that it librates; and the period of the in-plane mode its
// libration dominates (the one to compare a run with).
struct Librating {
  noether::State state;
  double period = 0;
};
Librating librating(const noether::System& system, const noether::RelativeEquilibrium& eq,
                    const noether::EquilibriumStability& st, const std::vector<std::string>& spec) {
  const std::size_t body = body_index(system, spec[0]);
  const int r = system.rigid_index(body);
  if (r < 0)
    throw noether::SceneError("orbit equilibrium --libration: body '" + system.body(body).name +
                              "' is a point mass; it has no attitude to librate");
  const double degrees = libration_degrees(spec[1], "--libration");
  const double frequency = libration_mode(system, st, body, "--libration").frequency;
  const auto k = static_cast<std::size_t>(r);
  const noether::Mat3& J = system.body(body).inertia;
  Librating out{eq.state, 2 * std::numbers::pi / frequency};
  const noether::Vec3 spin = eq.state.R[k] * J.inverse() * eq.state.Pi.col(r);  // inertial angular velocity
  out.state.R[k] = Eigen::AngleAxisd(degrees * std::numbers::pi / 180, eq.axis).toRotationMatrix() * eq.state.R[k];
  out.state.Pi.col(r) = J * out.state.R[k].transpose() * spin;
  return out;
}

// --lyapunov NAME,DEG: the Lyapunov orbit of NAME's libration (19.3) on the scene's integrator,
// its multipliers, and with -o the orbit as a scene of one period.
int lyapunov(const OrbitOptions& o, const noether::Scene& scene, const noether::FullBodyModel& model,
             const noether::RelativeEquilibrium& eq, const noether::EquilibriumStability& st) {
  const auto& sys = scene.system;
  const std::size_t body = body_index(sys, o.lyapunov[0]);
  if (sys.rigid_index(body) < 0)
    throw noether::SceneError("orbit equilibrium --lyapunov: body '" + sys.body(body).name +
                              "' is a point mass; it has no attitude to librate");
  const double degrees = std::abs(libration_degrees(o.lyapunov[1], "--lyapunov"));
  const auto& mode = libration_mode(sys, st, body, "--lyapunov");
  const auto ly = noether::lyapunov_orbit(model, scene.integrator, eq, mode, degrees * std::numbers::pi / 180);
  std::printf("Lyapunov orbit of the libration of %s, amplitude %s deg, on the map of %s: closure %.2e -> %.2e in %d "
              "Newton steps\n", sys.body(body).name.c_str(), o.lyapunov[1].c_str(), scene.integrator.plugin.c_str(),
              ly.orbit.initial_closure, ly.orbit.closure, ly.orbit.iterations);
  print_newton_jacobian(ly.orbit);
  std::printf("period                           %.12g (linear %.12g; relative %+.3e)\n", ly.orbit.period,
              ly.linear_period, ly.orbit.period / ly.linear_period - 1);
  std::printf("turned by                        %.12g rad about k\n", ly.orbit.angle);
  if (ly.steps > 0)
    std::printf("steps                            %ld of %.12g (the step follows the period)\n", ly.steps, ly.step);
  noether::Scene written = scene;  // with the orbit's step
  written.integrator = noether::lyapunov_integrator(scene.integrator, ly);
  if (!ly.orbit.closed()) {
    std::fflush(stdout);
    std::fprintf(stderr, "noether: the Lyapunov orbit did not close to %.0e (closure %.1e); nothing written: try a "
                 "smaller amplitude, or with an adaptive integrator a smaller rtol (its error bounds the closure: "
                 "rtol 1e-13 closes to ~1e-11)\n", noether::RelativePeriodicOrbit::closed_tolerance, ly.orbit.closure);
    return 1;
  }
  const auto mu = noether::lyapunov_multipliers(model, scene.integrator, ly, o.tolerance);
  std::printf("monodromy                        %s\n", mu.monodromy == "tangent map"
                                                             ? "the integrator's tangent map (docs/equations.md eq. 19.4)"
                                                             : "differences of the map (this integrator has no tangent map)");
  std::printf("multipliers (the map %s the energy):", mu.energy_conserved ? "conserves" : "does not conserve");
  for (auto m : mu.multipliers) std::printf(" %.6g%+.6gi", m.real(), m.imag());
  if (!mu.family.empty()) {
    std::printf("; the family's pair at 1, not judged:");
    for (auto m : mu.family) std::printf(" %.6g%+.6gi", m.real(), m.imag());
  }
  std::printf("\nverdict                          %s (max |mu| = %.10f)\n", mu.verdict.c_str(), mu.max_modulus);
  if (!o.plot.empty())
    plot_spectrum(o.plot, mu.multipliers, {}, "multipliers", 1.0, o.tolerance,
                  "Lyapunov orbit of the libration of " + sys.body(body).name + ": " + mu.verdict);
  if (!o.output.empty()) {
    char desc[300];
    std::snprintf(desc, sizeof desc, "Lyapunov orbit of the libration of %s, amplitude %s deg (noether orbit equilibrium "
                  "--lyapunov from %s): period %.12g", sys.body(body).name.c_str(), o.lyapunov[1].c_str(),
                  o.scene.c_str(), ly.orbit.period);
    std::ofstream file(o.output);
    file << noether::scene_with_state(written, ly.orbit.state, ly.orbit.period,
                                      noether::frames_keeping_step(written, ly.orbit.period), desc);
    file.close();
    if (!file) throw noether::OutputError("cannot write the orbit's scene to " + o.output + "; choose a folder you can write");
    std::printf("written: %s (one period of the orbit)\n", o.output.c_str());
  }
  return 0;
}

}  // namespace

int orbit_equilibrium(const OrbitOptions& o) {
  const noether::Scene scene = noether::load_scene(o.scene, o.overrides);
  noether::PluginRegistry registry;
  const auto model = noether::FullBodyModel::from_scene(scene, registry);
  noether::EquilibriumOptions options;
  options.fix = family(o.fix);
  options.value = o.value;
  options.align = o.align;
  if (!o.pair.empty()) {
    options.body_a = body_index(scene.system, o.pair[0]);
    options.body_b = body_index(scene.system, o.pair[1]);
  }
  const auto& sys = scene.system;
  if (!o.sweep_key.empty() && o.sweep.empty())
    throw noether::SceneError("orbit equilibrium --sweep-key KEY goes with --sweep FROM,TO,COUNT (the values of KEY)");
  if (!o.lyapunov.empty() && (!o.sweep.empty() || !o.libration.empty()))
    throw noether::SceneError("orbit equilibrium --lyapunov goes with neither --sweep nor --libration");
  if (!o.libration.empty() && (o.output.empty() || !o.sweep.empty()))
    throw noether::SceneError("orbit equilibrium --libration goes with -o OUT.yaml (the scene it writes), not with --sweep");
  const std::string a = sys.size() > options.body_a ? sys.body(options.body_a).name : "",
                    b = sys.size() > options.body_b ? sys.body(options.body_b).name : "";

  if (!o.sweep.empty()) {  // a table along the family
    const int count = static_cast<int>(o.sweep[2]);
    const bool over_key = !o.sweep_key.empty();  // the scene key varies, the family member is held
    if (count < 2 || (!over_key && (!(o.sweep[0] > 0) || !(o.sweep[1] > 0))))
      throw noether::SceneError("orbit equilibrium --sweep from,to,count: a count of at least 2, and positive values of " +
                                o.fix + " (or --sweep-key KEY to vary a scene key)");
    const std::string column = over_key ? o.sweep_key : o.fix;
    std::printf("%-14s %-14s %-14s %-16s %-16s %-10s %s\n", column.c_str(), "rate", "period", "L.k", "linear", "energetic",
                "frequencies (turning frame)");
    noether::State guess = scene.initial;
    int failures = 0;
    std::ofstream csv;  // --plot: one row per mode of each member
    if (!o.plot.empty()) {
      csv.open(csv_beside(o.plot));
      csv.precision(12);
      csv << "value,rate,linear,energetic,frequency,growth\n";
    }
    for (int i = 0; i < count; ++i) {
      const double value = o.sweep[0] + (o.sweep[1] - o.sweep[0]) * i / (count - 1);
      // --sweep-key: the scene made again with KEY = value; the previous member is the guess
      // (the first member's, the scene's own state), and the fixed quantity keeps its value.
      std::optional<noether::FullBodyModel> varied;
      if (over_key) {
        auto overrides = o.overrides;
        char text[40];
        std::snprintf(text, sizeof text, "%.17g", value);
        overrides.push_back(o.sweep_key + "=" + text);
        const noether::Scene member = noether::load_scene(o.scene, overrides);
        varied.emplace(noether::FullBodyModel::from_scene(member, registry));
        if (i == 0) guess = member.initial;
      } else {
        options.value = value;
      }
      const noether::FullBodyModel& m_model = varied ? *varied : model;
      const auto eq = noether::find_relative_equilibrium(m_model, guess, options);
      if (over_key && i == 0 && std::isnan(options.value))  // hold the first member's value
        options.value = options.fix == noether::EquilibriumFamily::separation ? eq.separation
                        : options.fix == noether::EquilibriumFamily::rate     ? eq.rate
                                                                              : eq.angular_momentum;
      warn_if_overlapping(eq);
      if (!eq.converged) {
        std::printf("%-14.8g not converged (residual %.1e)\n", value, eq.residual);
        ++failures;
        continue;
      }
      guess = eq.state;
      const auto st = noether::linear_stability(m_model, eq, o.tolerance);
      std::printf("%-14.8g %-14.8g %-14.8g %-16.10g %-16s %-10s", value, eq.rate, 2 * std::numbers::pi / eq.rate,
                  eq.angular_momentum, st.verdict.c_str(), st.energetic_verdict == "energetically stable" ? "stable" :
                  st.energetic_verdict == "undecided" ? "undecided" : ("index " + std::to_string(st.energetic_index)).c_str());
      for (const auto& m : st.modes) {
        if (m.frequency > 0) std::printf(" %.6g", m.frequency);
        else std::printf(" [%+.3g]", m.eigenvalue.real());
        if (csv.is_open())
          csv << value << ',' << eq.rate << ',' << st.verdict << ',' << st.energetic_verdict << ','
              << m.frequency << ',' << m.eigenvalue.real() << "\n";
      }
      std::printf("\n");
    }
    if (csv.is_open()) {
      csv.close();
      if (!csv) throw noether::OutputError("cannot write " + csv_beside(o.plot) + " (the data of --plot); choose a folder you can write");
      draw_plot("plot_equilibrium_sweep.py", {csv_beside(o.plot), o.plot, "--xlabel", column, "--title",
                                               "relative equilibria of " + std::filesystem::path(o.scene).filename().string()},
                o.plot, csv_beside(o.plot));
    }
    return failures == 0 ? 0 : 1;
  }

  const auto eq = noether::find_relative_equilibrium(model, scene.initial, options);
  std::printf("relative equilibrium from %s, %s fixed", o.scene.c_str(), o.fix.c_str());
  if (options.fix == noether::EquilibriumFamily::separation) std::printf(" (%s-%s)", a.c_str(), b.c_str());
  std::printf("\nNewton: %d iterations, largest scaled residual %.2e (%s)", eq.iterations, eq.residual,
              eq.converged ? "converged" : "NOT converged");
  if (eq.alignment > 0) std::printf("; guess's attitudes turned by up to %.3f deg onto the angular momentum", eq.alignment * 180 / std::numbers::pi);
  std::printf("\n");
  std::printf("axis k (total angular momentum)  [%.9f, %.9f, %.9f]\n", eq.axis.x(), eq.axis.y(), eq.axis.z());
  std::printf("rate omega                       %.12g (period %.12g)\n", eq.rate, 2 * std::numbers::pi / eq.rate);
  std::printf("separation %s-%s%*s%.12g\n", a.c_str(), b.c_str(), static_cast<int>(std::max<std::size_t>(1, 21 - a.size() - b.size())), "", eq.separation);
  std::printf("angular momentum L.k             %.12g\n", eq.angular_momentum);
  std::printf("energy                           %.12g\n", eq.energy);
  if (sys.size() == 2)
    for (std::size_t i = 0; i < 2; ++i)
      if (sys.body(i).rigid && !std::isnan(long_axis_angle(sys, eq.state, i, 1 - i)))
        std::printf("long axis of %-20s%.4f deg from the line of centres\n", sys.body(i).name.c_str(),
                    long_axis_angle(sys, eq.state, i, 1 - i));
  warn_if_overlapping(eq);
  if (!eq.converged) {
    std::fprintf(stderr, "noether: Newton did not converge (residual %.1e > %.1e): the scene's state may be too far from an "
                 "equilibrium of this family; try another --fix or --value, or a guess closer to a locked state\n",
                 eq.residual, options.tolerance);
    return 1;
  }
  const auto st = noether::linear_stability(model, eq, o.tolerance);
  std::printf("normal modes of the linearisation in the turning frame (symmetries projected out; invariance defect %.1e):\n",
              st.invariance_defect);
  std::printf("  %-16s %-16s %-12s %s\n", "frequency", "period", "Re lambda", "dominant motion");
  for (const auto& m : st.modes)
    std::printf("  %-16.10g %-16.10g %+-12.2e %s (%.0f %%)%s\n", m.frequency, m.frequency > 0 ? 2 * std::numbers::pi / m.frequency : INFINITY,
                m.eigenvalue.real(), m.kind.c_str(), 100 * m.weight, st.planar ? (m.in_plane ? ", in-plane" : ", out of plane") : "");
  std::printf("linear stability: %s", st.verdict.c_str());
  if (st.planar) std::printf(" (in-plane: %s; out of plane: %s)", st.in_plane_verdict.c_str(), st.out_of_plane_verdict.c_str());
  std::printf(", max |Re lambda| = %.2e x %.3g\n", st.max_real / st.scale, st.scale);
  std::printf("energy-momentum test: %s (%d negative directions; lowest Hessian eigenvalue %.3e of the largest)\n",
              st.energetic_verdict.c_str(), st.energetic_index, st.hessian_eigenvalues.empty() ? 0.0 : st.hessian_eigenvalues.front());
  if (st.verdict == "linearly stable" && st.energetic_index > 0)
    std::printf("note: stable only gyroscopically: any dissipation (tides) makes it unstable\n");
  if (!o.plot.empty() && o.lyapunov.empty()) {  // (with --lyapunov: the orbit's multipliers)
    std::vector<std::string> labels;  // each eigenvalue with Im λ ≥ 0 named by its mode
    for (const auto& l : st.eigenvalues) {
      const noether::NormalMode* nearest = nullptr;
      for (const auto& m : st.modes)
        if (!nearest || std::abs(std::abs(m.eigenvalue.imag()) - std::abs(l.imag())) <
                            std::abs(std::abs(nearest->eigenvalue.imag()) - std::abs(l.imag())))
          nearest = &m;
      labels.push_back((l.imag() > 0 || (l.imag() == 0 && l.real() > 0)) && nearest ? nearest->kind : "");
    }
    plot_spectrum(o.plot, st.eigenvalues, labels, "eigenvalues", eq.rate, o.tolerance,
                  "relative equilibrium of " + std::filesystem::path(o.scene).filename().string() + ": " + st.verdict);
  }
  if (!o.lyapunov.empty()) return lyapunov(o, scene, model, eq, st);
  if (!o.output.empty()) {
    const double period = 2 * std::numbers::pi / eq.rate;
    char desc[300];
    std::snprintf(desc, sizeof desc, "relative equilibrium of %s (noether orbit equilibrium): rate %.12g, period %.12g",
                  o.scene.c_str(), eq.rate, period);
    noether::State state = eq.state;
    double t_end = period;
    int frames = 200;
    std::string what = "one period";
    if (!o.libration.empty()) {  // the body turned about k̂, librating; the run: four libration periods
      const auto turned = librating(sys, eq, st, o.libration);
      state = turned.state;
      t_end = 4 * turned.period;
      frames = 400;
      std::snprintf(desc, sizeof desc, "relative equilibrium of %s (noether orbit equilibrium) with %s turned by %s deg: "
                    "libration period %.12g", o.scene.c_str(), o.libration[0].c_str(), o.libration[1].c_str(), turned.period);
      what = "four libration periods of " + o.libration[0];
    }
    std::ofstream file(o.output);
    file << noether::scene_with_state(scene, state, t_end, frames, desc);
    file.close();
    if (!file) throw noether::OutputError("cannot write the equilibrium scene to " + o.output + "; choose a folder you can write");
    std::printf("written: %s (%s)\n", o.output.c_str(), what.c_str());
  }
  return 0;
}

namespace {

// What orbit verify, refine and stability work on for a scene with rigid bodies: the scene, its
// model, and the period T (--period, or the scene's run.t_end).
struct RigidOrbitProblem {
  noether::Scene scene;
  noether::PluginRegistry registry;
  noether::FullBodyModel model;
  double period;
  RigidOrbitProblem(const OrbitOptions& o, noether::Scene loaded)
      : scene(std::move(loaded)),
        model(noether::FullBodyModel::from_scene(scene, registry)),
        period(o.period > 0 ? o.period : scene.run.t_end) {}
};

}  // namespace

int orbit_rigid_verify(const OrbitOptions& o, noether::Scene scene_loaded) {
  const RigidOrbitProblem problem(o, std::move(scene_loaded));
  const auto& [scene, registry, model, T] = problem;
  const auto c = noether::relative_closure(model, scene.integrator, scene.initial, T);
  const double E0 = model.energy(scene.initial), E1 = model.energy(c.end);
  std::printf("relative periodic orbit of %s on the map of %s over T = %.12g: turned by alpha = %.12g rad about k\n",
              o.scene.c_str(), scene.integrator.plugin.c_str(), T, c.angle);
  std::printf("closure (scaled, as orbit refine measures it)  %.3e\n", c.closure);
  std::printf("energy                                         %.15g -> %.15g (relative change %.2e)\n", E0, E1,
              std::abs(E1 - E0) / std::max(std::abs(E0), 1e-300));
  if (c.closure <= o.tolerance) return 0;
  std::fflush(stdout);  // the numbers, then why they fail
  std::fprintf(stderr, "noether: the orbit does not close up to a turn: closure %.3e > tolerance %.1e (wrong period, or "
               "not a relative periodic orbit; try noether orbit refine)\n", c.closure, o.tolerance);
  return 1;
}

int orbit_rigid_refine(const OrbitOptions& o, noether::Scene scene_loaded) {
  const RigidOrbitProblem problem(o, std::move(scene_loaded));
  const auto& [scene, registry, model, T] = problem;
  const double alpha = noether::relative_closure(model, scene.integrator, scene.initial, T).angle;
  const auto orbit = noether::shoot_relative_periodic_orbit(model, scene.integrator, scene.initial, T, alpha);
  std::printf("closure %.3e -> %.3e in %d Newton steps on the map of %s (T = %.12g held, L.k held, turned by alpha = "
              "%.12g rad)\n", orbit.initial_closure, orbit.closure, orbit.iterations, scene.integrator.plugin.c_str(), T,
              orbit.angle);
  print_newton_jacobian(orbit);
  if (!orbit.closed()) {
    std::fprintf(stderr, "noether: the shooting did not close the orbit (closure %.1e); nothing written: the scene's "
                 "state is not near a relative periodic orbit of period %.6g (try another --period)\n", orbit.closure, T);
    return 1;
  }
  const std::string out = o.output.empty() ? o.scene : o.output;
  std::ofstream file(out);
  file << noether::scene_with_state(scene, orbit.state, T, noether::frames_keeping_step(scene, T),
                                    "relative periodic orbit refined by noether orbit refine from " + o.scene);
  file.close();
  if (!file) throw noether::OutputError("cannot write the refined scene to " + out + "; choose a folder you can write");
  std::printf("written: %s\n", out.c_str());
  return 0;
}

int orbit_rigid_stability(const OrbitOptions& o, noether::Scene scene_loaded) {
  const RigidOrbitProblem problem(o, std::move(scene_loaded));
  const auto& [scene, registry, model, T] = problem;
  // α0: the turn of the first two bodies' line of centres about k̂ over one period.
  double alpha = noether::relative_closure(model, scene.integrator, scene.initial, T).angle;
  if (o.angle_turns != 0) alpha += 2 * std::numbers::pi * o.angle_turns;
  const auto orbit = noether::shoot_relative_periodic_orbit(model, scene.integrator, scene.initial, T, alpha);
  std::printf("relative periodic orbit of %s on the map of %s over T = %.12g: closure %.2e -> %.2e in %d Newton steps, "
              "turned by alpha = %.12g rad about k\n",
              o.scene.c_str(), scene.integrator.plugin.c_str(), T, orbit.initial_closure, orbit.closure, orbit.iterations,
              orbit.angle);
  print_newton_jacobian(orbit);
  if (!orbit.closed()) {
    std::fprintf(stderr, "noether: the shooting did not close the orbit (closure %.1e): the scene's state is not near a "
                 "relative periodic orbit of period %.6g; try another --period\n", orbit.closure, T);
    return 1;
  }
  const auto mu = noether::relative_orbit_multipliers(model, scene.integrator, orbit, o.tolerance);
  std::printf("monodromy: %s\n", mu.monodromy == "tangent map"
                                      ? "the integrator's tangent map (docs/equations.md eq. 19.4)"
                                      : "differences of the map (this integrator has no tangent map)");
  std::printf("the map %s the energy (defect %.1e): reduced by the barycentre, L, the rotation about k%s "
              "(docs/equations.md §19; invariance defect %.1e)\n",
              mu.energy_conserved ? "conserves" : "does not conserve", mu.energy_defect,
              mu.energy_conserved ? ", the energy and the flow" : "", mu.invariance_defect);
  // A multiplier e^{iθ} on the unit circle is an oscillation of frequency (θ + 2πk)/T in the
  // frame turning with the orbit; k = 0 is printed (the monodromy cannot tell k).
  std::printf("multipliers, by modulus (arg/T: the frequency modulo 2 pi/T = %.6g):\n", 2 * std::numbers::pi / T);
  for (auto m : mu.multipliers)
    std::printf("  %+.10f %+.10fi   |mu| = %.12f   arg/T = %.6g\n", m.real(), m.imag(), std::abs(m),
                std::abs(std::arg(m)) / T);
  std::printf("verdict: %s (tolerance %.1e)\n", mu.verdict.c_str(), o.tolerance);
  if (!o.plot.empty())
    plot_spectrum(o.plot, mu.multipliers, {}, "multipliers", 1.0, o.tolerance,
                  "relative periodic orbit of " + std::filesystem::path(o.scene).filename().string() + " (" +
                      scene.integrator.plugin + "): " +
                      mu.verdict);
  return 0;
}

}  // namespace noether::app
