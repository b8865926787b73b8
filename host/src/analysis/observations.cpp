// Observation files: reading with errors by file, line and column; writing (docs/fitting.md).
#include <noether/conjunction.hpp>
#include <noether/error.hpp>
#include <noether/lightcurve.hpp>
#include <noether/observations.hpp>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

namespace noether {

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

const std::vector<std::string>& required_columns() {
  static const std::vector<std::string> columns{"t", "observable", "target", "center", "value", "sigma"};
  return columns;
}

}  // namespace

std::vector<Observation> read_observations(const std::filesystem::path& file, const std::vector<std::string>& names,
                                           ObservationsNeed need) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot read the observation file");
  std::map<std::string, std::size_t> column;
  std::vector<Observation> rows;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string bare = trim(line);
    if (bare.empty() || bare[0] == '#') continue;
    const std::vector<std::string> cells = split(bare);
    const std::string where = file.string() + ":" + std::to_string(number);
    if (column.empty()) {  // the header
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (column.count(cells[c])) throw SceneError(where + ": column '" + cells[c] + "' appears twice in the header");
        column[cells[c]] = c;
      }
      for (const auto& name : required_columns())
        if (!column.count(name))
          throw SceneError(where + ": the header has no column '" + name +
                           "' (an observation file's header names t, observable, target, center, value, sigma; "
                           "docs/fitting.md)");
      continue;
    }
    auto cell = [&](const std::string& name) -> std::string {
      const auto it = column.find(name);
      if (it == column.end()) return {};
      if (it->second >= cells.size())
        throw SceneError(where + ": the row has " + std::to_string(cells.size()) + " cells; column '" + name +
                         "' is cell " + std::to_string(it->second + 1));
      return cells[it->second];
    };
    auto number_in = [&](const std::string& name, bool required) -> std::optional<double> {
      const std::string text = cell(name);
      if (text.empty()) {
        if (required) throw SceneError(where + ": column '" + name + "': empty");
        return std::nullopt;
      }
      std::size_t used = 0;
      double value = 0;
      try {
        value = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != text.size() || !std::isfinite(value))
        throw SceneError(where + ": column '" + name + "': '" + text + "' is not a finite number");
      return value;
    };
    auto body = [&](const std::string& name) -> std::size_t {
      const std::string text = cell(name);
      for (std::size_t j = 0; j < names.size(); ++j)
        if (names[j] == text) return j;
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw SceneError(where + ": column '" + name + "': no body '" + text + "' in the run (its bodies: " + known + ")");
    };
    const bool strict = need == ObservationsNeed::values_and_sigmas;
    Observation o;
    o.line = number;
    o.t = *number_in("t", true);
    try {
      o.observable.kind = observable_kind(cell("observable"));
    } catch (const SceneError& e) {
      throw SceneError(where + ": column 'observable': " + e.what());
    }
    o.observable.target = body("target");
    o.observable.center = body("center");
    if (o.observable.target == o.observable.center && !o.observable.is_lightcurve())
      throw SceneError(where + ": target and center are the same body ('" + cell("target") + "')");
    o.value = number_in("value", strict).value_or(std::nan(""));
    const std::optional<double> sigma = number_in("sigma", strict);
    if (sigma && !(*sigma > 0))
      throw SceneError(where + ": column 'sigma': must be positive (got " + cell("sigma") + ")");
    o.sigma = sigma.value_or(0.0);
    if (o.observable.needs_line_of_sight()) {
      for (const char* c : {"los_x", "los_y", "los_z"})
        if (!column.count(c))
          throw SceneError(where + ": " + cell("observable") +
                           " needs the line of sight: columns los_x, los_y, los_z (from the observer towards the bodies)");
      const Eigen::Vector3d los(*number_in("los_x", true), *number_in("los_y", true), *number_in("los_z", true));
      try {
        o.observable.line_of_sight = sky_plane(los).line_of_sight;
      } catch (const SceneError& e) {
        throw SceneError(where + ": columns los_x, los_y, los_z: " + e.what());
      }
    }
    if (o.observable.needs_sunlight()) {
      for (const char* c : {"sun_x", "sun_y", "sun_z"})
        if (!column.count(c))
          throw SceneError(where + ": " + cell("observable") +
                           " needs the sunlight's direction: columns sun_x, sun_y, sun_z (from the Sun towards the bodies)");
      const Eigen::Vector3d sun(*number_in("sun_x", true), *number_in("sun_y", true), *number_in("sun_z", true));
      if (!(sun.norm() > 0)) throw SceneError(where + ": columns sun_x, sun_y, sun_z: the sunlight's direction is zero");
      o.observable.sunlight = sun.normalized();
    }
    rows.push_back(o);
  }
  if (column.empty()) throw SceneError(file.string() + ": no header (the file is empty or all comments)");
  if (rows.empty()) throw SceneError(file.string() + ": the file holds no observation");
  return rows;
}

void write_observations(std::ostream& out, const std::vector<Observation>& rows, const std::vector<std::string>& names) {
  bool sky = false, sun = false;
  for (const auto& o : rows) sky = sky || o.observable.needs_line_of_sight(), sun = sun || o.observable.needs_sunlight();
  out << "t,observable,target,center,value,sigma" << (sky ? ",los_x,los_y,los_z" : "") << (sun ? ",sun_x,sun_y,sun_z" : "")
      << "\n";
  out << std::setprecision(17);
  for (const auto& o : rows) {
    out << o.t << "," << observable_name(o.observable.kind) << "," << names.at(o.observable.target) << ","
        << names.at(o.observable.center) << "," << o.value << ",";
    if (o.sigma > 0) out << o.sigma;
    if (sky) {
      out << ",";
      if (o.observable.needs_line_of_sight())
        out << o.observable.line_of_sight.x() << "," << o.observable.line_of_sight.y() << ","
            << o.observable.line_of_sight.z();
      else
        out << ",,";
    }
    if (sun) {
      out << ",";
      if (o.observable.needs_sunlight())
        out << o.observable.sunlight.x() << "," << o.observable.sunlight.y() << "," << o.observable.sunlight.z();
      else
        out << ",,";
    }
    out << "\n";
  }
}

Observable observable_from_spec(const std::string& spec, const std::vector<std::string>& names,
                                const std::vector<double>& line_of_sight, const std::vector<double>& sunlight) {
  std::vector<std::string> parts;
  std::stringstream in(spec);
  for (std::string p; std::getline(in, p, ':');) parts.push_back(p);
  if (parts.size() != 3)
    throw SceneError("observable '" + spec + "': give NAME:TARGET:CENTER (e.g. position.x:dimorphos:didymos)");
  Observable o;
  try {
    o.kind = observable_kind(parts[0]);
    o.target = body_index(names, parts[1]);
    o.center = body_index(names, parts[2]);
  } catch (const SceneError& e) {
    throw SceneError("observable '" + spec + "': " + e.what());
  }
  if (o.target == o.center && !o.is_lightcurve())
    throw SceneError("observable '" + spec + "': target and center are the same body");
  if (o.needs_line_of_sight()) {
    if (line_of_sight.size() != 3)
      throw SceneError("observable '" + spec + "' needs a line of sight X,Y,Z (from the observer to the bodies)");
    o.line_of_sight = sky_plane(Eigen::Vector3d(line_of_sight[0], line_of_sight[1], line_of_sight[2])).line_of_sight;
  }
  if (o.needs_sunlight()) {
    if (sunlight.size() != 3)
      throw SceneError("observable '" + spec + "' needs the sunlight's direction X,Y,Z (from the Sun to the bodies)");
    const Eigen::Vector3d sun(sunlight[0], sunlight[1], sunlight[2]);
    if (!(sun.norm() > 0) || !sun.allFinite())
      throw SceneError("observable '" + spec + "': the sunlight's direction must be a finite, non-zero vector");
    o.sunlight = sun.normalized();
  }
  return o;
}

ObservableValue observe(const Trajectory& trajectory, const Observation& o, const std::string& where) {
  if (o.observable.is_event_time()) {  // (30.1)
    ObservableValue out;
    try {
      out.value = nearest_conjunction(trajectory, o.observable.target, o.observable.center, o.observable.line_of_sight,
                                      o.t).t;
    } catch (const SceneError& e) {
      throw SceneError((where.empty() ? std::string() : where + ": ") + e.what());
    }
    return out;
  }
  Eigen::Matrix3Xd x, v;
  try {
    trajectory.sample(o.t, x, v);
  } catch (const SceneError& e) {
    throw SceneError((where.empty() ? std::string() : where + ": ") + e.what());
  }
  const auto a = static_cast<Eigen::Index>(o.observable.target), b = static_cast<Eigen::Index>(o.observable.center);
  if (!o.observable.is_lightcurve()) return evaluate(o.observable, x.col(a) - x.col(b), v.col(a) - v.col(b));
  // (29.2): the bodies' surfaces placed at the sampled positions and attitudes.
  if (!trajectory.has_attitudes() || trajectory.surfaces.size() != trajectory.names.size())
    throw Error("a lightcurve needs a trajectory read with its shapes (read_trajectory)");
  const std::vector<Mat3> R = trajectory.attitudes(o.t);
  std::vector<Mesh> placed;
  for (const std::size_t j : {o.observable.target, o.observable.center}) {
    if (!placed.empty() && j == o.observable.target) break;  // one body
    Mesh m = trajectory.surfaces[j];
    if (m.faces.empty())
      throw SceneError((where.empty() ? std::string() : where + ": ") + "body '" + trajectory.names[j] +
                       "' has no surface for a lightcurve (give it an ellipsoid or polyhedron shape, or a point mass a "
                       "radius; a body given by its gravity field has none)");
    for (Eigen::Index k = 0; k < m.vertices.cols(); ++k)
      m.vertices.col(k) = x.col(static_cast<Eigen::Index>(j)) + R[j] * m.vertices.col(k);
    placed.push_back(std::move(m));
  }
  ObservableValue out;
  out.value = disk_integrated_flux(placed, o.observable.sunlight, o.observable.line_of_sight,
                                   o.observable.kind == Observable::Kind::lightcurve_lambert ? Scattering::lambert
                                                                                             : Scattering::lommel_seeliger);
  return out;
}

}  // namespace noether
