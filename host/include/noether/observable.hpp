#pragma once
// An observable: one number a run predicts at a time, as an observation file states it
// (docs/fitting.md, "Observables"; docs/equations.md §27). Each depends on a target body seen
// from a center body only through their relative position r = x_target − x_center and velocity
// u = v_target − v_center, so its value and its gradients ∂/∂r, ∂/∂u say everything a fit needs
// (the target's rows +, the center's −).
#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace noether {

struct Observable {
  enum class Kind {
    position_x,  // r · x̂ of the scene's axes (27.1)
    position_y,
    position_z,
    sky_east,    // r · ê and r · n̂ on the sky plane of a line of sight ℓ (27.2)
    sky_north,
    range,       // |r| (27.3)
    range_rate,  // r · u / |r| (27.4)
    // The disk-integrated brightness of target and center together (one body when they are the
    // same), from their shapes and attitudes (§29): not a function of r and u alone.
    lightcurve_lommel_seeliger,
    lightcurve_lambert,
    // The time of the conjunction on the sky of target and center nearest to the row's time
    // (§30): when their projected separation is least.
    conjunction_time,
  };
  Kind kind = Kind::position_x;
  std::size_t target = 0, center = 0;
  Eigen::Vector3d line_of_sight = Eigen::Vector3d::Zero();  // sky_*, lightcurve_*: unit, from the observer to the bodies
  Eigen::Vector3d sunlight = Eigen::Vector3d::Zero();       // lightcurve_*: unit, from the Sun to the bodies

  bool is_lightcurve() const { return kind == Kind::lightcurve_lommel_seeliger || kind == Kind::lightcurve_lambert; }
  // Whether it needs a line of sight, sunlight; whether it reads the velocities.
  bool is_event_time() const { return kind == Kind::conjunction_time; }
  bool needs_line_of_sight() const {
    return kind == Kind::sky_east || kind == Kind::sky_north || is_lightcurve() || is_event_time();
  }
  bool needs_sunlight() const { return is_lightcurve(); }
  bool needs_velocity() const { return kind == Kind::range_rate; }
};

// The names the observation files use ("position.x", …, "sky.east", "sky.north", "range",
// "range_rate", "lightcurve.lommel_seeliger", "lightcurve.lambert", "conjunction.time"), in the
// order of Observable::Kind.
const std::vector<std::string>& observable_names();
const std::string& observable_name(Observable::Kind kind);
// The kind of a name; SceneError listing the names when it is none of them.
Observable::Kind observable_kind(const std::string& name);

// The sky plane of a line of sight ℓ (27.2): north n̂ is the scene's +z projected on the plane
// (+y when ℓ is along z), east ê = n̂ × ℓ — on the sky, east is to the left of north, as an
// observer looking along ℓ sees it. SceneError when ℓ is zero or not finite.
struct SkyPlane {
  Eigen::Vector3d line_of_sight, east, north;
};
SkyPlane sky_plane(const Eigen::Vector3d& line_of_sight);

struct ObservableValue {
  double value = 0.0;
  Eigen::Vector3d d_r = Eigen::Vector3d::Zero();  // ∂value/∂r
  Eigen::Vector3d d_u = Eigen::Vector3d::Zero();  // ∂value/∂u (0 unless needs_velocity())
};

// The value at relative position r and velocity u, with its gradients (27.1)–(27.4).
// A range_rate at r = 0 is NaN (the direction is undefined). Error for a lightcurve or an event
// time (observe() computes those from a trajectory).
ObservableValue evaluate(const Observable& o, const Eigen::Vector3d& r, const Eigen::Vector3d& u);

}  // namespace noether
