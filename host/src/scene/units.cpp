// Scene units (docs/equations.md §17).
#include <noether/error.hpp>
#include <noether/units.hpp>

#include "scene/scene_schema.hpp"

#include <utility>

namespace noether {

namespace {

using Table = std::initializer_list<std::pair<const char*, double>>;

constexpr double au = 149597870700.0;           // IAU 2012, m
constexpr double GM_sun = 1.32712440041e20;     // IAU 2015 nominal (TDB), m³/s²
constexpr double GM_earth = 3.986004415e14;     // IERS/EGM2008, m³/s²

const Table lengths = {{"m", 1.0}, {"km", 1e3}, {"au", au}};
const Table masses = {{"kg", 1.0}, {"t", 1e3}, {"M_earth", GM_earth / G_SI}, {"M_sun", GM_sun / G_SI}};
const Table times = {{"s", 1.0}, {"min", 60.0}, {"h", 3600.0}, {"day", 86400.0}, {"yr", 365.25 * 86400.0}};

double lookup(const Table& table, const std::string& name) {
  for (const auto& [key, value] : table)
    if (name == key) return value;
  return 0.0;
}

std::string names(const Table& table) {
  std::string s;
  for (const auto& entry : table) s += (s.empty() ? "" : ", ") + std::string(entry.first);
  return s;
}

}  // namespace

double Units::gravitational_constant() const {
  return G_SI * mass_si * time_si * time_si / (length_si * length_si * length_si);  // eq. (17.1)
}

std::string Units::describe() const {
  if (!declared) return "scene units (not declared; G = 1 unless given)";
  return length + ", " + mass + ", " + time;
}

double length_unit_in_metres(const std::string& name) { return lookup(lengths, name); }

Units parse_units(const Params& p) {
  Units u{true, std::string("m"), std::string("kg"), std::string("s"), 1.0, 1.0, 1.0};
  if (p.is_scalar()) {
    if (p.as_string() != "SI")
      throw SceneError(p.here() + "'units' must be SI or a mapping {length, mass, time}, e.g. "
                       "units: {length: km, mass: kg, time: h}");
    return u;
  }
  if (!p.is_map())
    throw SceneError(p.here() + "'units' must be SI or a mapping {length, mass, time}");
  const detail::SceneSection& keys = detail::scene_section("units");
  keys.check(p, "'units'");
  const std::pair<const char*, std::pair<const Table*, std::pair<std::string*, double*>>> fields[] = {
      {"length", {&lengths, {&u.length, &u.length_si}}},
      {"mass", {&masses, {&u.mass, &u.mass_si}}},
      {"time", {&times, {&u.time, &u.time_si}}}};
  for (const auto& [key, target] : fields) {
    const auto& [table, out] = target;
    const std::string name = keys.text(p, key);  // SI's when absent
    const double si = lookup(*table, name);
    if (si == 0.0)
      throw SceneError(p.at(key).here() + "unknown " + key + " unit '" + name + "'; known: " + names(*table));
    *out.first = name;
    *out.second = si;
  }
  return u;
}

}  // namespace noether
