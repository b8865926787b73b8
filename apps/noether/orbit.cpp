// noether orbit find | verify | stability | refine: periodic orbits (docs/periodic-orbits.md).
#include "commands.hpp"

#include <noether/error.hpp>
#include <noether/least_action.hpp>
#include <noether/periodic_orbit.hpp>
#include <noether/scene.hpp>

#include <CLI/CLI.hpp>

#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>
#include <utility>

namespace noether::app {

// noether orbit …: periodic orbits of planar point masses (docs/periodic-orbits.md).

namespace {

// The scene's bodies and potential; ξ from its initial state; T from --period or run.t_end.
noether::OrbitModel orbit_model(const OrbitOptions& o, const noether::Scene& scene, Eigen::VectorXd& xi, double& T) {
  noether::PluginRegistry registry;
  auto model = noether::OrbitModel::from_scene(scene, registry);
  xi = model.phase_point(scene.initial);
  T = o.period > 0 ? o.period : scene.run.t_end;
  return model;
}

noether::FlowOptions flow_options(const OrbitOptions& o) {
  noether::FlowOptions f;
  f.rtol = o.rtol;
  f.atol = o.rtol * 1e-2;
  return f;
}

void print_multipliers(const std::vector<std::complex<double>>& list) {
  for (auto l : list)
    if (std::abs(l) > 1e-9) std::printf("  %+.10f %+.10fi   |lambda| = %.12f\n", l.real(), l.imag(), std::abs(l));
}

}  // namespace

int orbit_verify(const OrbitOptions& o) {
  noether::Scene scene = noether::load_scene(o.scene, o.overrides);  // read once: a polyhedron's set-up is costly
  if (scene.system.rigid_count() > 0) return orbit_rigid_verify(o, std::move(scene));
  Eigen::VectorXd xi;
  double T;
  const auto model = orbit_model(o, scene, xi, T);
  const auto f = noether::integrate_flow(model, xi, T, false, flow_options(o));
  const double closure = (f.end - xi).norm();
  std::printf("period %.15g, integrator rk rkf78 rtol %.1e on the scene's potential, %zu steps\n"
              "closure ||xi(T) - xi(0)|| = %.3e (relative %.3e)\n",
              T, o.rtol, f.steps, closure, closure / xi.norm());
  std::printf("energy %.15g\n", model.energy(xi));
  if (closure <= o.tolerance * std::max(1.0, xi.norm())) return 0;
  std::fprintf(stderr, "noether: the orbit does not close: relative closure %.3e > tolerance %.1e (wrong period, "
               "or not a periodic orbit; try noether orbit refine)\n", closure / std::max(1.0, xi.norm()), o.tolerance);
  return 1;
}

int orbit_stability(const OrbitOptions& o) {
  noether::Scene scene = noether::load_scene(o.scene, o.overrides);  // read once: a polyhedron's set-up is costly
  if (scene.system.rigid_count() > 0) return orbit_rigid_stability(o, std::move(scene));
  Eigen::VectorXd xi;
  double T;
  const auto model = orbit_model(o, scene, xi, T);
  const auto f = noether::integrate_flow(model, xi, T, true, flow_options(o));
  const auto s = noether::stability(model, xi, f.monodromy, o.tolerance);
  std::printf("period %.15g, closure %.3e, variational equations by rkf78 rtol %.1e (%zu steps)\n", T,
              (f.end - xi).norm(), o.rtol, f.steps);
  std::printf("in-plane multipliers of P Phi(T) P (first integrals projected out), by modulus:\n");
  print_multipliers(s.multipliers);
  std::printf("max |lambda(Phi)| = %.10f, max |lambda(P Phi P)| = %.10f\n", s.max_unprojected, s.max_projected);
  std::printf("out-of-plane multipliers (z, v_z block of Phi; not judged):\n");
  print_multipliers(s.out_of_plane);
  if (o.first_order > 0) {
    const auto M = noether::first_order_monodromy(model, xi, T, static_cast<std::size_t>(o.first_order), flow_options(o));
    const auto s1 = noether::stability(model, xi, M, o.tolerance);
    std::printf("Vanderbei's first-order product with %d steps: max |lambda| = %.4f, projected %.4f\n", o.first_order,
                s1.max_unprojected, s1.max_projected);
  }
  std::printf("verdict: %s (tolerance %.1e)\n", s.verdict.c_str(), o.tolerance);
  if (!o.plot.empty()) {  // the in-plane multipliers (the projected-out ones, 0, left out)
    std::vector<std::complex<double>> shown;
    for (auto l : s.multipliers)
      if (std::abs(l) > 1e-9) shown.push_back(l);
    plot_spectrum(o.plot, shown, {}, "multipliers", 1.0, o.tolerance,
                  "in-plane multipliers of " + std::filesystem::path(o.scene).filename().string() + ": " + s.verdict);
  }
  return 0;
}

int orbit_refine(const OrbitOptions& o) {
  noether::Scene scene = noether::load_scene(o.scene, o.overrides);  // read once: a polyhedron's set-up is costly
  if (scene.system.rigid_count() > 0) return orbit_rigid_refine(o, std::move(scene));
  Eigen::VectorXd xi;
  double T;
  const auto model = orbit_model(o, scene, xi, T);
  const double before = (noether::integrate_flow(model, xi, T, false, flow_options(o)).end - xi).norm();
  const auto r = noether::refine_periodic_orbit(model, xi, T, 1e-12, 12, flow_options(o));
  // Measured as `orbit verify` measures it: the flow alone (the refinement's own closure comes
  // from a flow integrated with the variational equations, whose extra components change the
  // adaptive steps and so the last digits).
  const double after = (noether::integrate_flow(model, r.xi0, r.period, false, flow_options(o)).end - r.xi0).norm();
  std::printf("closure %.3e -> %.3e in %d Newton steps (as orbit verify measures it); period %.15g -> %.15g\n",
              before, after, r.iterations, T, r.period);
  const std::string out = o.output.empty() ? o.scene : o.output;
  std::ofstream file(out);
  file << noether::orbit_scene(model, r.xi0, r.period, "refined by noether orbit refine from " + o.scene);
  file.close();
  if (!file) throw noether::OutputError("cannot write the refined scene to " + out + "; choose a folder you can write");
  std::printf("written: %s\n", out.c_str());
  return after <= 1e-10 ? 0 : 1;
}

int orbit_find(OrbitOptions o) {
  noether::LeastActionProblem p;
  noether::PluginRegistry registry;
  if (!o.scene.empty()) {  // the scene's bodies, G and potential
    if (!o.masses.empty() || o.bodies_given)
      throw noether::SceneError("orbit find: --bodies and --masses do not go with --scene (the scene gives the bodies)");
    p.model = noether::OrbitModel::from_scene(noether::load_scene(o.scene, o.overrides), registry);
  } else {
    if (o.masses.empty() && o.bodies < 2)
      throw noether::SceneError("orbit find: --bodies must be at least 2, not " + std::to_string(o.bodies) +
                                " (for one body in an external field, give a --scene)");
    for (std::size_t j = 0; j < o.masses.size(); ++j)
      if (!(o.masses[j] > 0))
        throw noether::SceneError("orbit find: --masses must be positive; body " + std::to_string(j + 1) + " has " +
                                  (std::ostringstream() << o.masses[j]).str());
    p.model = noether::OrbitModel::point_masses(
        o.masses.empty() ? std::vector<double>(static_cast<std::size_t>(std::max(o.bodies, 0)), 1.0) : o.masses, 1.0,
        registry);
  }
  if (o.period > 0) p.period = o.period;
  p.modes = o.modes;
  p.choreography = o.choreography;
  p.points = o.points > 0 ? o.points : [&] {  // Vanderbei's 100, adjusted: > 2F, multiple of n
    int m = std::max(100, 2 * o.modes + 2);
    while (p.choreography && p.n() > 0 && m % static_cast<int>(p.n()) != 0) ++m;
    return m;
  }();
  p.validate();
  std::error_code made;
  std::filesystem::create_directories(o.out_dir, made);
  if (made)
    throw noether::OutputError("cannot create the --out-dir folder " + o.out_dir + ": " + made.message() +
                               "; choose a folder you can write");
  const auto& model = p.model;
  std::vector<double> found_actions;
  int k = 0, failures = 0;
  for (int s = 0; s < o.starts; ++s) {
    const auto orbit = noether::minimize_action(p, noether::random_start(p, o.seed + static_cast<unsigned>(s)));
    std::printf("start %3d: action %.10f, EOM residual %.2e", s, orbit.action, orbit.residual);
    if (p.n() > 1) std::printf(", min distance %.3f", orbit.min_distance);
    bool seen = false;
    for (double a : found_actions) seen |= std::abs(a - orbit.action) < 1e-6 * std::abs(a);
    if (orbit.residual > o.max_residual || orbit.min_distance < 1e-3) {
      std::printf("  (rejected: EOM residual above %.0e, not a solution at this truncation)\n", o.max_residual);
      ++failures;
      continue;
    }
    if (seen) {
      std::printf("  (found before)\n");
      continue;
    }
    Eigen::VectorXd xi = noether::lift_planar(orbit.initial_state(p));
    double T = p.period;
    double closure = (noether::integrate_flow(model, xi, T, false).end - xi).norm();
    if (o.refine) {
      const auto r = noether::refine_periodic_orbit(model, xi, T);
      if (r.closure < closure) xi = r.xi0, T = r.period, closure = r.closure;
    }
    if (closure > 1e-8 * std::max(1.0, xi.norm())) {  // verified by integration, or not an orbit
      std::printf("  (rejected: closure %.1e after one period)\n", closure);
      ++failures;
      continue;
    }
    std::printf("\n");
    found_actions.push_back(orbit.action);
    ++k;
    const std::string stem = (std::filesystem::path(o.out_dir) / ("orbit-" + std::to_string(k))).string();
    char desc[256];
    std::snprintf(desc, sizeof desc, "least-action orbit %d: action %.10f, EOM residual %.2e, closure %.2e", k,
                  orbit.action, orbit.residual, closure);
    std::ofstream(stem + ".yaml") << noether::orbit_scene(model, xi, T, desc);
    std::ofstream curve(stem + ".csv");
    curve << "t";
    for (std::size_t j = 0; j < p.n(); ++j) curve << ",x" << j + 1 << ",y" << j + 1;
    curve << "\n";
    for (int i = 0; i <= 400; ++i) {
      const double tau = 2 * std::numbers::pi * i / 400;
      curve << p.period * i / 400;
      for (std::size_t j = 0; j < p.n(); ++j) {
        const auto z = noether::fourier_position(p, orbit.coefficients, j, tau);
        curve << ',' << z.x() << ',' << z.y();
      }
      curve << "\n";
    }
    curve.close();  // complete on disk before the plotting script reads it
    std::printf("  -> %s.yaml (period %.12f, closure %.2e after refinement)\n", stem.c_str(), T, closure);
    std::string command;
    if (!run_plot_script("plot_orbit.py", {stem + ".csv", stem + ".png", "--title", desc}, command))
      std::fprintf(stderr, "noether: could not draw %s.png (needs python3-matplotlib; "
                   "command: %s)\n", stem.c_str(), command.c_str());
  }
  std::printf("%d distinct orbits from %d starts (%d starts rejected)\n", k, o.starts, failures);
  return k > 0 ? 0 : 1;
}

void add_orbit_command(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<OrbitOptions>();
  const CLI::Validator positive(
      [](std::string& v) -> std::string {
        try {
          if (std::stod(v) > 0) return {};
        } catch (const std::exception&) {
        }
        return "must be a positive number, not " + v;
      },
      "> 0");
  auto* orbit_cmd = app.add_subcommand("orbit", "periodic orbits: find (least action), verify, stability, refine; relative equilibria of rigid bodies");
  orbit_cmd->require_subcommand(1);
  auto* find_cmd = orbit_cmd->add_subcommand("find", "minimize a Fourier-discretized action from random starts");
  auto* bodies_opt = find_cmd->add_option("--bodies", o->bodies, "number of bodies (equal masses, G = 1, point-mass)")
                         ->capture_default_str();
  find_cmd->add_option("--masses", o->masses, "masses (overrides --bodies)")->delimiter(',');
  find_cmd->add_option("--scene", o->scene,
                       "take the bodies, G and potential from this scene instead (point masses, planar)");
  find_cmd->add_option("--set", o->overrides, "override a key of --scene")->take_all();
  find_cmd->add_option("--period", o->period, "period T of the orbits sought (default 2 pi)")->check(positive);
  find_cmd->add_option("--modes", o->modes, "Fourier modes per coordinate")->capture_default_str();
  find_cmd->add_option("--points", o->points, "quadrature points (default: 100, or more than 2 × modes)");
  find_cmd->add_flag("--choreography", o->choreography, "all bodies on one curve, z_j(t) = z(t + 2 pi j/n)");
  find_cmd->add_option("--seed", o->seed, "random seed")->capture_default_str();
  find_cmd->add_option("--starts", o->starts, "random starts")->capture_default_str();
  find_cmd->add_option("--out-dir", o->out_dir, "folder for orbit-K.yaml, .csv and .png")->capture_default_str();
  find_cmd->add_flag_callback("--no-refine", [o] { o->refine = false; }, "skip the Newton (shooting) refinement");
  find_cmd->add_option("--max-residual", o->max_residual,
                       "largest equation-of-motion residual along the Fourier curve to try to refine")
      ->capture_default_str();
  std::vector<CLI::App*> orbit_scene_cmds;
  for (auto [name, help] : {std::pair{"verify", "integrate one period and report the closure error"},
                            std::pair{"stability", "monodromy multipliers with the first integrals projected out"},
                            std::pair{"refine", "Newton (shooting) on the initial state and period"}}) {
    auto* c = orbit_cmd->add_subcommand(name, help);
    c->add_option("scene", o->scene, "scene of the orbit (YAML)")->required();
    c->add_option("--period", o->period, "period (default: the scene's run.t_end)")->check(positive);
    c->add_option("--set", o->overrides, "override a scene key")->take_all();
    c->add_option("--rtol", o->rtol, "relative tolerance of the rkf78 integration")->capture_default_str();
    orbit_scene_cmds.push_back(c);
  }
  orbit_scene_cmds[0]->add_option("--tolerance", o->tolerance, "closure accepted (relative)")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--tolerance", o->tolerance, "|lambda| <= 1 + tolerance is stable")->capture_default_str();
  orbit_scene_cmds[1]->add_option("--first-order", o->first_order, "also Vanderbei's first-order product with N steps");
  orbit_scene_cmds[1]->add_option("--plot", o->plot, "PNG: the multipliers and the unit circle; data in the .csv beside it");
  orbit_scene_cmds[1]->add_option("--turns", o->angle_turns,
                                  "rigid bodies: whole turns to add to the measured angle alpha")->capture_default_str();
  orbit_scene_cmds[2]->add_option("-o,--output", o->output, "refined scene (default: overwrite the input)");

  auto* equilibrium_cmd = orbit_cmd->add_subcommand(
      "equilibrium", "relative equilibrium of rigid bodies (locked, turning about the angular momentum) and its stability");
  equilibrium_cmd->add_option("scene", o->scene, "scene whose state is the first guess (YAML)")->required();
  equilibrium_cmd->add_option("--set", o->overrides, "override a scene key")->take_all();
  equilibrium_cmd->add_option("--fix", o->fix, "the member of the family: separation, angular-momentum or rate")
      ->check(CLI::IsMember({"separation", "angular-momentum", "rate"}))->capture_default_str();
  equilibrium_cmd->add_option("--value", o->value, "its value (default: the scene's)");
  equilibrium_cmd->add_option("--pair", o->pair, "a,b: the bodies whose separation is fixed (default: the first two)")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--sweep", o->sweep, "from,to,count: a table along the family, each solution the next guess")
      ->delimiter(',')->expected(3);
  equilibrium_cmd->add_option("--sweep-key", o->sweep_key,
                              "KEY: --sweep varies this scene key (a mass, a semi-axis) with the --fix quantity held");
  equilibrium_cmd->add_option("--tolerance", o->tolerance, "|Re lambda| <= tolerance x max(omega, |lambda|) is stable")
      ->capture_default_str();
  equilibrium_cmd->add_flag_callback("--no-align", [o] { o->align = false; },
                                     "keep the guess's attitudes (default: principal axes turned onto the angular momentum)");
  equilibrium_cmd->add_option("-o,--output", o->output, "write the equilibrium as a scene (one period)");
  equilibrium_cmd->add_option("--libration", o->libration,
                              "NAME,DEG: with -o, that body turned by DEG about the axis, librating (four libration periods)")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--lyapunov", o->lyapunov,
                              "NAME,DEG: the periodic orbit of that body's libration at that amplitude, on the scene's "
                              "integrator; with -o, written as a scene of one period")
      ->delimiter(',')->expected(2);
  equilibrium_cmd->add_option("--plot", o->plot,
                              "PNG: the eigenvalues (or, with --sweep, the modes along the family); data in the .csv beside it");

  // The subcommand chosen runs with the options as parsed.
  const auto choose = [o, &chosen](int (*command)(const OrbitOptions&)) {
    return [o, &chosen, command] { chosen = [o, command] { return command(*o); }; };
  };
  find_cmd->callback([o, &chosen, bodies_opt] {
    o->bodies_given = bodies_opt->count() > 0;
    chosen = [o] { return orbit_find(*o); };
  });
  orbit_scene_cmds[0]->callback(choose(orbit_verify));
  orbit_scene_cmds[1]->callback(choose(orbit_stability));
  orbit_scene_cmds[2]->callback(choose(orbit_refine));
  equilibrium_cmd->callback(choose(orbit_equilibrium));
}

}  // namespace noether::app
