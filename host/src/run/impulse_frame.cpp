#include "run/impulse_frame.hpp"

#include <noether/error.hpp>

namespace noether::detail {

Mat3 rtn_frame(const Vec3& r, const Vec3& v) {
  const Vec3 h = r.cross(v);
  if (!(h.norm() > 1e-12 * r.norm() * v.norm()) || !(r.norm() > 0))
    throw Error("an impulse in the RTN frame needs an orbit: the body's position and velocity relative to the "
                "body it orbits are parallel (or zero), so the along-track and normal directions are undefined");
  Mat3 Q;
  Q.col(0) = r.normalized();
  Q.col(2) = h.normalized();
  Q.col(1) = Q.col(2).cross(Q.col(0));
  return Q;
}

Mat3 rtn_frame_derivative(const Vec3& r, const Vec3& v, const Vec3& dr, const Vec3& dv) {
  const Vec3 rhat = r.normalized(), h = r.cross(v), nhat = h.normalized();
  const Vec3 dh = dr.cross(v) + r.cross(dv);
  Mat3 dQ;
  dQ.col(0) = (dr - rhat * rhat.dot(dr)) / r.norm();    // δr̂ = (I − r̂r̂ᵀ) δr / |r|
  dQ.col(2) = (dh - nhat * nhat.dot(dh)) / h.norm();    // δn̂ = (I − n̂n̂ᵀ) δh / |h|
  dQ.col(1) = dQ.col(2).cross(rhat) + nhat.cross(dQ.col(0));  // δt̂ = δn̂ × r̂ + n̂ × δr̂
  return dQ;
}

RelativeOrbit relative_orbit(const Impulse& impulse, const System& system, const State& state) {
  const auto b = static_cast<Eigen::Index>(impulse.body), c = static_cast<Eigen::Index>(impulse.around);
  return {state.x.col(b) - state.x.col(c),
          state.p.col(b) / system.body(impulse.body).mass - state.p.col(c) / system.body(impulse.around).mass};
}

}  // namespace noether::detail
