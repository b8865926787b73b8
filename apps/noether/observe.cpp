// noether observe: observables computed from a run's output file, as an observation file
// (docs/fitting.md, "Observables"): at every frame, or at the rows of a given file; with
// Gaussian noise of each row's sigma for synthetic data.
#include "commands.hpp"

#include <noether/conjunction.hpp>
#include <noether/error.hpp>
#include <noether/observations.hpp>
#include <noether/trajectory.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace noether::app {

struct ObserveOptions {
  std::string run, at, output;
  std::vector<std::string> observables;
  std::vector<double> line_of_sight, sunlight;
  int tessellation = 4;
  std::size_t every = 1;
  double sigma = 0.0;
  bool noise = false, force = false;
  std::uint64_t seed = 1;
};

int observe(const ObserveOptions& o) {
  if (!o.output.empty() && !o.force && std::filesystem::exists(o.output))
    throw OutputError(o.output + " exists; noether does not overwrite output unless asked: pass --force");
  if (o.sigma < 0) throw SceneError("--sigma must be positive");
  if (o.every < 1) throw SceneError("--every must be at least 1");
  if (o.tessellation < 0 || o.tessellation > 8) throw SceneError("--tessellation must be in [0, 8]");
  // The names first (a cheap read), then the whole trajectory — with shapes when a row is a lightcurve.
  const std::vector<std::string> names = read_trajectory_names(o.run);
  std::vector<Observation> rows;
  std::vector<Observable> wanted;
  if (!o.at.empty()) {
    rows = read_observations(o.at, names, ObservationsNeed::times_only);
  } else {
    for (const auto& spec : o.observables)
      wanted.push_back(observable_from_spec(spec, names, o.line_of_sight, o.sunlight));
  }
  bool lightcurve = false;
  for (const auto& row : rows) lightcurve = lightcurve || row.observable.is_lightcurve();
  for (const auto& w : wanted) lightcurve = lightcurve || w.is_lightcurve();
  const Trajectory run = read_trajectory(o.run, TrajectoryShapes{lightcurve, o.tessellation});
  if (o.at.empty()) {
    const auto& t = run.times();
    for (std::size_t k = 0; k < t.size(); k += o.every) {
      if (k > 0 && t[k] == t[k - 1]) continue;  // an impulse's two frames: the value after it
      for (const auto& w : wanted) {
        if (w.is_event_time()) continue;
        Observation row;
        row.t = t[k];
        row.observable = w;
        rows.push_back(row);
      }
    }
    for (const auto& w : wanted) {  // event times: every event in the run, once
      if (!w.is_event_time()) continue;
      for (const auto& c : conjunctions(run, w.target, w.center, w.line_of_sight)) {
        Observation row;
        row.t = c.t;
        row.observable = w;
        rows.push_back(row);
      }
    }
    std::stable_sort(rows.begin(), rows.end(), [](const Observation& a, const Observation& b) { return a.t < b.t; });
  }
  std::mt19937_64 random(o.seed);
  std::normal_distribution<double> gauss;
  for (auto& row : rows) {
    if (o.sigma > 0 && !(row.sigma > 0)) row.sigma = o.sigma;
    const std::string where = row.line ? o.at + ":" + std::to_string(row.line) : std::string();
    row.value = observe(run, row, where).value;
    if (o.noise) {
      if (!(row.sigma > 0))
        throw SceneError((where.empty() ? std::string("--noise") : where) +
                         ": noise needs a sigma (the row's, or --sigma)");
      row.value += row.sigma * gauss(random);
      if (row.observable.is_event_time() && o.at.empty()) row.t = row.value;  // observed when it is seen
    }
  }
  std::ostringstream text;
  text << "# noether observe " << o.run << (o.noise ? " with Gaussian noise of each row's sigma, seed " +
                                                          std::to_string(o.seed) : std::string()) << "\n";
  write_observations(text, rows, run.names);
  if (o.output.empty()) {
    std::cout << text.str();
  } else {
    std::ofstream out(o.output);
    out << text.str();
    out.close();
    if (!out) throw OutputError(o.output + ": cannot write");
    std::cerr << rows.size() << " observations written to " << o.output << "\n";
  }
  return 0;
}

void add_observe_command(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<ObserveOptions>();
  auto* cmd = app.add_subcommand("observe",
                                 "observables computed from a run's output: at every frame (--observable), or at the "
                                 "rows of an observation file (--at); as an observation file (docs/fitting.md)");
  cmd->add_option("run", o->run, "a run's output file (HDF5)")->required();
  auto* given = cmd->add_option("--observable", o->observables,
                                "NAME:TARGET:CENTER at every frame; NAME one of position.x, position.y, position.z, "
                                "sky.east, sky.north, range, range_rate, lightcurve.lommel_seeliger, "
                                "lightcurve.lambert (at every frame); conjunction.time (every conjunction in the run)")
                    ->take_all();
  auto* at = cmd->add_option("--at", o->at, "an observation file: its rows' values computed (value and sigma may be empty)");
  given->excludes(at);
  cmd->add_option("--line-of-sight", o->line_of_sight,
                  "X,Y,Z: from the observer to the bodies (sky.east, sky.north, lightcurves, conjunction.time)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--sunlight", o->sunlight, "X,Y,Z: the direction sunlight travels, from the Sun to the bodies (lightcurves)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--tessellation", o->tessellation,
                  "lightcurves: an ellipsoid's or sphere's facets, 20·4^LEVEL (docs/fitting.md, \"Lightcurves\")")
      ->capture_default_str();
  cmd->add_option("--every", o->every, "with --observable: every K-th frame")->capture_default_str();
  cmd->add_option("--sigma", o->sigma, "1σ written for rows that give none (the observable's unit)");
  cmd->add_flag("--noise", o->noise, "add Gaussian noise of each row's sigma (synthetic data)");
  cmd->add_option("--seed", o->seed, "the noise's random seed")->capture_default_str();
  cmd->add_option("-o,--output", o->output, "the observation file to write (default: standard output)");
  cmd->add_flag("--force", o->force, "replace an existing output file");
  cmd->callback([o, given, at, &chosen] {
    if (given->count() == 0 && at->count() == 0) throw CLI::ValidationError("observe", "give --observable or --at");
    chosen = [o] { return observe(*o); };
  });
}

}  // namespace noether::app
