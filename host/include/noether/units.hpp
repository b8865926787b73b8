#pragma once
// The units a scene declares (`units: {length, mass, time}`, docs/user-guide.md "Units"):
// names for every output quantity and the gravitational constant in them (docs/equations.md
// eq. 17.1). A scene without `units:` is in units of its own choosing, written L, M, T.
#include <noether/params.hpp>

#include <string>

namespace noether {

struct Units {
  bool declared = false;
  std::string length = "L", mass = "M", time = "T";  // unit names as written in the scene
  double length_si = 1.0, mass_si = 1.0, time_si = 1.0;  // one unit in m, kg, s (declared only)

  // G in these units (eq. 17.1); only for declared units.
  double gravitational_constant() const;

  // Unit strings for the output's `unit` attributes: "km/h", "kg km^2/h^2", ...
  std::string of_length() const { return length; }
  std::string of_time() const { return time; }
  std::string of_mass() const { return mass; }
  std::string of_velocity() const { return length + "/" + time; }
  std::string of_momentum() const { return mass + " " + length + "/" + time; }
  std::string of_angular_momentum() const { return mass + " " + length + "^2/" + time; }
  std::string of_energy() const { return mass + " " + length + "^2/" + time + "^2"; }
  std::string of_inertia() const { return mass + " " + length + "^2"; }
  std::string of_angular_velocity() const { return "rad/" + time; }
  std::string of_G() const { return length + "^3/(" + mass + " " + time + "^2)"; }
  // "km, kg, h" or "scene units (not declared)".
  std::string describe() const;
};

// CODATA 2018.
inline constexpr double G_SI = 6.67430e-11;

// Reads `units:` ({length, mass, time}, each optional with SI default, or the word SI); the
// known names are listed in the error for an unknown one.
Units parse_units(const Params& p);

// One unit of length named `name` in metres, or 0 when unknown (for shape files' units).
double length_unit_in_metres(const std::string& name);

}  // namespace noether
