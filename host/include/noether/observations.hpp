#pragma once
// Observation files (docs/fitting.md, "Observation files"): CSV with a header naming at least
// the columns t, observable, target, center, value, sigma (any order; more columns are kept
// out of the way), one scalar observation a row; the sky observables and lightcurves also need
// los_x, los_y, los_z, the line of sight, and lightcurves sun_x, sun_y, sun_z, the sunlight's
// direction. Lines starting with # are comments.
#include <noether/observable.hpp>
#include <noether/trajectory.hpp>

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace noether {

struct Observation {
  double t = 0.0;
  Observable observable;
  double value = 0.0;
  double sigma = 0.0;    // 1σ, in the observable's unit (> 0 for a fit)
  std::size_t line = 0;  // in its file, for messages (0: made in code)
};

// How strict the reader is: a fit needs every value and a positive sigma; `noether observe --at`
// computes the values, so it takes rows whose value and sigma are empty (a positive sigma
// where one is given).
enum class ObservationsNeed { values_and_sigmas, times_only };

// Reads a file, naming its bodies by `names` (a run's, in scene order). SceneError
// "FILE:LINE: column 'C': …" for the first bad row: a missing column, a number that does not
// read, an unknown observable or body, a non-positive sigma, a missing line of sight.
std::vector<Observation> read_observations(const std::filesystem::path& file, const std::vector<std::string>& names,
                                           ObservationsNeed need = ObservationsNeed::values_and_sigmas);

// Writes rows in the same format (values to 17 digits; a sigma of 0 is left empty).
void write_observations(std::ostream& out, const std::vector<Observation>& rows, const std::vector<std::string>& names);

// An observable from "NAME:TARGET:CENTER" (bodies by name; the sky observables and lightcurves
// need a line of sight: `line_of_sight` of size 3; lightcurves also `sunlight`, and may name one
// body twice for its lightcurve alone). SceneError naming the spec and what is wrong.
Observable observable_from_spec(const std::string& spec, const std::vector<std::string>& names,
                                const std::vector<double>& line_of_sight = {}, const std::vector<double>& sunlight = {});

// The observation's value in a trajectory: sampled at its time (SceneError "FILE:LINE: t = …
// is outside the run" through `where`). A lightcurve needs the trajectory's shapes and
// attitudes (read_trajectory with shapes) and has no gradients. An event time is the
// conjunction nearest to the row's t (nearest_conjunction).
ObservableValue observe(const Trajectory& trajectory, const Observation& o, const std::string& where = {});

}  // namespace noether
