// Values that look like slips of units (input_warnings.hpp).
#include "scene/input_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace noether::detail {

namespace {

constexpr double kBreakupFactor = 10.0;      // spins beyond this many times √(GM/R³) are warned
constexpr double kNaturalMassKg = 1e6;       // lighter bodies (spacecraft) are held by their structure
constexpr double kLowestDensity = 50.0;      // kg/m³: below the fluffiest comet nucleus (67P: 533)
constexpr double kHighestDensity = 25000.0;  // kg/m³: above osmium (22 590)
constexpr double kSecondsPerDay = 86400.0;

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// The node a warning points at: `key` of body entry `b` when given, else the entry itself.
const Params& key_or_entry(const Params& b, const char* key) { return b.has(key) ? b.at(key) : b; }

// A spin beyond breakup, and which units the number would be plausible in.
void spin_beyond_breakup(const Scene& scene, std::vector<std::string>& out) {
  const System& sys = scene.system;
  const Units& u = scene.units;
  const auto& entries = scene.root.at("bodies").items();
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const std::size_t i = sys.body_of_rigid(k);
    const Body& body = sys.body(i);
    if (!(body.radius > 0.0) || (u.declared && body.mass * u.mass_si < kNaturalMassKg)) continue;
    const double omega = (body.inertia_inverse * scene.initial.Pi.col(static_cast<Eigen::Index>(k))).norm();
    const double breakup = std::sqrt(sys.G() * body.mass / std::pow(body.radius, 3));  // ω_c = √(GM/R³)
    if (!(omega > kBreakupFactor * breakup)) continue;
    const Params& where = key_or_entry(entries[i], entries[i].has("angular_velocity") ? "angular_velocity"
                                                                                      : "angular_momentum");
    const std::string rate = "rad/" + u.time;
    std::string msg = where.here() + "body '" + body.name + "' spins at |Ω| = " + number(omega) + " " + rate + ", " +
                      number(omega / breakup) + " times its breakup rate √(GM/R³) = " + number(breakup) + " " +
                      rate + " (R = " + number(body.radius) + " " + u.length +
                      ", its bounding radius; a monolith can exceed it, a rubble pile cannot): angular velocities "
                      "are in " + rate;
    // The units the number may have been written in: those that put it below breakup.
    struct Reading {
      std::string unit;
      double factor;  // rad/<time> per one of `unit`
    };
    std::vector<Reading> readings{{"deg/" + u.time, std::numbers::pi / 180.0}};
    if (u.declared) {
      for (const auto& [name, seconds] : {std::pair<const char*, double>{"s", 1.0}, {"h", 3600.0}, {"day", kSecondsPerDay}})
        if (name != u.time) readings.push_back({std::string("deg/") + name, std::numbers::pi / 180.0 * u.time_si / seconds});
      if (u.time != "min") readings.push_back({"rpm", 2.0 * std::numbers::pi * u.time_si / 60.0});
    }
    std::string meant;
    for (const Reading& r : readings) {
      const double as = omega * r.factor;
      if (as <= 2.0 * breakup && meant.empty())
        meant = "; read as " + r.unit + " it would be " + number(as) + " " + rate + " (" + number(as / breakup) +
                " times breakup)";
    }
    out.push_back(msg + (meant.empty() ? "" : meant));
  }
}

// A fixed step longer than half the shortest period: bound pairs' Kepler periods, spin periods.
void step_beyond_periods(const Scene& scene, std::vector<std::string>& out) {
  const Params& integrator = scene.integrator.params;
  if (!given(integrator, "step")) return;
  const Params& step_node = integrator.at("step");
  const double step = step_node.as_double();
  if (!(step > 0.0)) return;
  const System& sys = scene.system;
  const State& s = scene.initial;
  double shortest = std::numeric_limits<double>::infinity();
  std::string what;
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    const Body& body = sys.body(sys.body_of_rigid(k));
    const double omega = (body.inertia_inverse * s.Pi.col(static_cast<Eigen::Index>(k))).norm();
    if (omega > 0.0 && 2.0 * std::numbers::pi / omega < shortest) {
      shortest = 2.0 * std::numbers::pi / omega;
      what = "the spin of '" + body.name + "'";
    }
  }
  if (sys.size() <= 64)
    for (std::size_t a = 0; a < sys.size(); ++a)
      for (std::size_t b = a + 1; b < sys.size(); ++b) {
        const auto ia = static_cast<Eigen::Index>(a), ib = static_cast<Eigen::Index>(b);
        const double ma = sys.body(a).mass, mb = sys.body(b).mass, mu = ma * mb / (ma + mb);
        const double r = (s.x.col(ib) - s.x.col(ia)).norm();
        const Vec3 v = s.p.col(ib) / mb - s.p.col(ia) / ma;
        const double energy = 0.5 * mu * v.squaredNorm() - sys.G() * ma * mb / r;  // two-body energy
        if (!(energy < 0.0)) continue;
        const double axis = -sys.G() * ma * mb / (2.0 * energy);
        const double period = 2.0 * std::numbers::pi * std::sqrt(std::pow(axis, 3) / (sys.G() * (ma + mb)));
        if (period < shortest) {
          shortest = period;
          what = "the orbit of '" + sys.body(b).name + "' and '" + sys.body(a).name + "'";
        }
      }
  if (!(step > 0.5 * shortest)) return;
  const Units& u = scene.units;
  std::string msg = step_node.here() + "integrator.step = " + number(step) + " " + u.time +
                    " is longer than half the shortest period the scene starts with (" + what + ", " +
                    number(shortest) + " " + u.time + "): fewer than two steps a period cannot follow it";
  if (u.declared && u.time != "s")
    msg += "; the scene's time unit is " + u.time + " (" + number(step) + " s would be " + number(step / u.time_si) +
           " " + u.time + ")";
  out.push_back(msg);
}

// A density no body has, from a given mass and the shape's volume.
void density_out_of_range(const Scene& scene, std::vector<std::string>& out) {
  const Units& u = scene.units;
  if (!u.declared) return;
  const auto& entries = scene.root.at("bodies").items();
  for (std::size_t i = 0; i < scene.system.size(); ++i) {
    const Body& body = scene.system.body(i);
    if (!body.solid || !(entries[i].has("mass") || entries[i].has("density"))) continue;
    const double density = body.solid->density * u.mass_si / std::pow(u.length_si, 3);  // kg/m³
    if (density >= kLowestDensity && density <= kHighestDensity) continue;
    const bool mesh = body.solid->kind == Solid::Kind::Polyhedron;
    std::string size = mesh ? "its mesh" : "its semi-axes (in the scene's " + u.length + ")";
    std::string meant;
    if (mesh && body.shape.is_map() && body.shape.has("polyhedron") && body.shape.at("polyhedron").has("units")) {
      const std::string unit = body.shape.at("polyhedron").at("units").as_string();
      size = "its mesh (read in " + unit + ")";
      const char* other = unit == "m" ? "km" : unit == "km" ? "m" : nullptr;
      if (other && density * (unit == "m" ? 1e-9 : 1e9) >= kLowestDensity &&
          density * (unit == "m" ? 1e-9 : 1e9) <= kHighestDensity) {
        const double f = unit == "m" ? 1e-9 : 1e9;  // the density if the mesh were in `other`
        meant = "; read in " + std::string(other) + " the mesh would give " + number(density * f) + " kg/m³";
      }
    }
    const std::string range = " outside the 50–25000 kg/m³ of comets to metals";
    if (entries[i].has("density")) {  // the density typed: in g/cm³, or in another mass or length unit?
      const double grams = density * 1000.0;
      const bool si = u.mass == "kg" && u.length == "m";
      out.push_back(entries[i].at("density").here() + "body '" + body.name + "': its density " +
                    number(body.solid->density) + " " + u.mass + "/" + u.length + "³" +
                    (si ? "" : " = " + number(density) + " kg/m³") + " is" + range +
                    (grams >= kLowestDensity && grams <= kHighestDensity
                         ? "; densities are in " + u.mass + "/" + u.length + "³ — was it in g/cm³ (" +
                               number(grams) + " kg/m³)?"
                         : ""));
      continue;
    }
    out.push_back(entries[i].at("mass").here() + "body '" + body.name + "': its mass " + number(body.mass) + " " +
                  u.mass + " in the volume of " + size + ", " + number(body.solid->volume) + " " + u.length +
                  "³, is a density of " + number(density) + " kg/m³," + range + meant);
  }
}

}  // namespace

std::vector<std::string> input_warnings(const Scene& scene) {
  std::vector<std::string> out;
  density_out_of_range(scene, out);  // first: a wrong density makes the spin look fast
  spin_beyond_breakup(scene, out);
  step_beyond_periods(scene, out);
  return out;
}

}  // namespace noether::detail
