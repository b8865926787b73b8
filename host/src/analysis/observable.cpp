// Observables and their gradients (docs/equations.md §27).
#include <noether/error.hpp>
#include <noether/observable.hpp>
#include <noether/params.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace noether {

using Eigen::Vector3d;

const std::vector<std::string>& observable_names() {
  static const std::vector<std::string> names{"position.x", "position.y", "position.z", "sky.east",
                                              "sky.north",  "range",      "range_rate",
                                              "lightcurve.lommel_seeliger", "lightcurve.lambert", "conjunction.time"};
  return names;
}

const std::string& observable_name(Observable::Kind kind) {
  return observable_names().at(static_cast<std::size_t>(kind));
}

Observable::Kind observable_kind(const std::string& name) {
  const auto& names = observable_names();
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<Observable::Kind>(k);
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  const std::string near = closest_match(name, names);
  throw SceneError("unknown observable '" + name + "'" + (near.empty() ? "" : " (did you mean " + near + "?)") +
                   "; the observables are " + known);
}

SkyPlane sky_plane(const Vector3d& line_of_sight) {
  const double norm = line_of_sight.norm();
  if (!(norm > 0) || !std::isfinite(norm))
    throw SceneError("a line of sight must be a finite, non-zero vector (from the observer towards the bodies)");
  SkyPlane sky;
  sky.line_of_sight = line_of_sight / norm;
  const Vector3d& l = sky.line_of_sight;
  // (27.2): n̂ = ẑ projected on the plane ⟂ ℓ; ŷ when ℓ is (nearly) along ẑ.
  Vector3d up = Vector3d::UnitZ() - l.z() * l;
  if (up.norm() < 1e-8) up = Vector3d::UnitY() - l.y() * l;
  sky.north = up.normalized();
  sky.east = sky.north.cross(l);
  return sky;
}

ObservableValue evaluate(const Observable& o, const Vector3d& r, const Vector3d& u) {
  ObservableValue out;
  switch (o.kind) {
    case Observable::Kind::position_x:
    case Observable::Kind::position_y:
    case Observable::Kind::position_z: {  // (27.1)
      const auto axis = static_cast<Eigen::Index>(o.kind) - static_cast<Eigen::Index>(Observable::Kind::position_x);
      out.value = r[axis];
      out.d_r[axis] = 1.0;
      break;
    }
    case Observable::Kind::sky_east:
    case Observable::Kind::sky_north: {  // (27.2)
      const SkyPlane sky = sky_plane(o.line_of_sight);
      out.d_r = o.kind == Observable::Kind::sky_east ? sky.east : sky.north;
      out.value = out.d_r.dot(r);
      break;
    }
    case Observable::Kind::range: {  // (27.3)
      out.value = r.norm();
      out.d_r = out.value > 0 ? Vector3d(r / out.value) : Vector3d::Zero();
      break;
    }
    case Observable::Kind::range_rate: {  // (27.4): ρ̇ = r̂·u, ∂/∂r = (u − ρ̇ r̂)/ρ, ∂/∂u = r̂
      const double rho = r.norm();
      if (!(rho > 0)) {
        out.value = std::numeric_limits<double>::quiet_NaN();
        break;
      }
      const Vector3d rhat = r / rho;
      out.value = rhat.dot(u);
      out.d_r = (u - out.value * rhat) / rho;
      out.d_u = rhat;
      break;
    }
    case Observable::Kind::lightcurve_lommel_seeliger:
    case Observable::Kind::lightcurve_lambert:
      throw Error("a lightcurve is not a function of the relative position: it is computed from the bodies' shapes "
                  "and attitudes (observe)");
    case Observable::Kind::conjunction_time:
      throw Error("an event time is not a function of the relative position at one time: it is found in a trajectory "
                  "(observe)");
  }
  return out;
}

}  // namespace noether
