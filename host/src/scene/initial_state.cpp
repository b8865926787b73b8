// The bodies' initial state: positions and velocities (absolute, relative to another body, or
// osculating elements), attitudes and spins (scene_sections.hpp; docs/user-guide.md "Initial
// states").
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"
#include "scene/start_apart.hpp"

#include <noether/error.hpp>
#include <noether/euler_angles.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <unordered_map>

namespace noether::detail {

namespace {

Mat3 attitude(const Params& p, const std::string& body) {
  Mat3 R;
  if (p.is_map()) {
    scene_section("bodies[].attitude").check(p, "attitude of body '" + body + "'");
    if (p.has("matrix")) return attitude(p.at("matrix"), body);
    if (p.has("euler_angles")) {  // 3-2-1 (yaw, pitch, roll) in degrees, eq. 17.9
      const Vec3 angles = vec3(p.at("euler_angles"));
      if (!angles.allFinite())
        throw SceneError(p.at("euler_angles").here() + "euler_angles of body '" + body + "' must be finite");
      return rotation_from_euler_321(angles * (std::numbers::pi / 180.0));
    }
    const auto q = p.at("quaternion").as_doubles();
    if (q.size() != 4)
      throw SceneError(p.here() + "quaternion of body '" + body + "' needs 4 numbers [w, x, y, z]");
    const Vec4 qv(q[0], q[1], q[2], q[3]);
    if (std::abs(qv.norm() - 1.0) > 1e-9) {
      std::ostringstream msg;
      msg << p.here() << "quaternion of body '" << body << "' has norm " << qv.norm()
          << "; a rotation needs a unit quaternion (scalar first)";
      throw SceneError(msg.str());
    }
    R = rotation_from_quaternion(qv);
  } else {
    R = mat3(p);
  }
  const double err = orthogonality_error(R);
  if (err > 1e-10 || R.determinant() <= 0.0) {
    std::ostringstream msg;
    msg << p.here() << "attitude of body '" << body
        << "' is not a rotation matrix: ‖I − RᵀR‖ = " << err << ", det R = " << R.determinant()
        << " (needs ‖I − RᵀR‖ ≤ 1e-10 and det R = +1)";
    throw SceneError(msg.str());
  }
  return R;
}

// Each body's initial position and velocity (docs/user-guide.md, "Initial states"): absolute,
// relative to another body (`relative_to`), or osculating elements about another body
// (`orbit`, eqs. 17.2–17.4, angles in degrees); then, with `barycentric: true`, shifted so
// that the barycentre rests at the origin.
std::pair<std::vector<Vec3>, std::vector<Vec3>> initial_translation(const Params& bodies, const System& sys,
                                                                    bool barycentric) {
  const std::size_t n = sys.size();
  std::vector<Vec3> x(n, Vec3::Zero()), v(n, Vec3::Zero());
  std::vector<int> mark(n, 0);  // 0 open, 1 resolving, 2 done
  std::unordered_map<std::string, std::size_t> index;  // name → body (O(1) per reference)
  for (std::size_t j = 0; j < n; ++j) index.emplace(sys.body(j).name, j);
  auto index_of = [&](const Params& name_node, const std::string& who) {
    const std::string name = name_node.as_string();
    if (const auto found = index.find(name); found != index.end()) return found->second;
    std::string known;
    for (const auto& b : sys.bodies()) known += (known.empty() ? "" : ", ") + b.name;
    throw SceneError(name_node.here() + who + " refers to body '" + name + "', which the scene does not "
                     "have (bodies: " + known + ")");
  };
  // The body whose state body i's is given relative to, if any (keys checked here).
  auto reference_of = [&](std::size_t i) -> std::optional<std::size_t> {
    const Params& b = bodies.items()[i];
    const std::string who = "body '" + sys.body(i).name + "'";
    if (b.has("orbit")) {
      for (const char* key : {"position", "velocity", "relative_to"})
        if (b.has(key))
          throw SceneError(b.at(key).here() + who + ": 'orbit' gives the position and velocity; remove '" +
                           key + "'");
      const Params& o = b.at("orbit");
      scene_section("bodies[].orbit").check(o, "the orbit of " + who);
      const std::size_t c = index_of(o.at("around"), "the orbit of " + who);
      if (c == i) throw SceneError(o.at("around").here() + who + " cannot orbit itself");
      return c;
    }
    if (!b.has("position"))
      throw SceneError(b.here() + who + " needs 'position' (or 'orbit': osculating elements about another body)");
    if (!b.has("relative_to")) return std::nullopt;
    const std::size_t c = index_of(b.at("relative_to"), who + "'s 'relative_to'");
    if (c == i) throw SceneError(b.at("relative_to").here() + who + " cannot be relative to itself");
    return c;
  };
  // Body i's state once its reference body's (if any) is known.
  auto place = [&](std::size_t i, std::optional<std::size_t> c) {
    const Params& b = bodies.items()[i];
    const std::string who = "body '" + sys.body(i).name + "'";
    if (!b.has("orbit")) {
      x[i] = vec3(b.at("position"));
      if (b.has("velocity")) v[i] = vec3(b.at("velocity"));
      if (c) x[i] += x[*c], v[i] += v[*c];
      return;
    }
    const OrbitalElements el = orbit_elements(b.at("orbit"), who);
    const double mu = sys.G() * (sys.body(i).mass + sys.body(*c).mass);
    const RelativeState rel = state_from_elements(el, mu);  // (17.2)–(17.4)
    x[i] = x[*c] + rel.r;
    v[i] = v[*c] + rel.v;
  };
  // Follow each chain of references up to a placed body (iteratively: a chain may be as long as
  // the scene), then place it from the top down.
  std::vector<std::size_t> chain;
  for (std::size_t i = 0; i < n; ++i) {
    chain.clear();
    for (std::size_t j = i; mark[j] != 2;) {
      if (mark[j] == 1)
        throw SceneError(bodies.items()[j].here() + "body '" + sys.body(j).name + "': its initial state refers, "
                         "through relative_to / orbit.around, back to itself");
      mark[j] = 1;
      chain.push_back(j);
      const auto c = reference_of(j);
      if (!c) break;
      j = *c;
    }
    for (auto k = chain.rbegin(); k != chain.rend(); ++k) {
      place(*k, reference_of(*k));
      mark[*k] = 2;
    }
  }
  if (barycentric) {
    Vec3 mx = Vec3::Zero(), mv = Vec3::Zero();
    double m = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      mx += sys.body(i).mass * x[i];
      mv += sys.body(i).mass * v[i];
      m += sys.body(i).mass;
    }
    for (std::size_t i = 0; i < n; ++i) {
      x[i] -= mx / m;
      v[i] -= mv / m;
    }
  }
  return {x, v};
}

}  // namespace

OrbitalElements orbit_elements(const Params& o, const std::string& who) {
  const double deg = M_PI / 180.0;
  const SceneSection& elements = scene_section("particles.orbits[]");  // a body's orbit has the same rows
  OrbitalElements el;
  el.a = o.at("a").as_double();
  el.e = elements.number(o, "e");
  el.i = elements.number(o, "i") * deg;
  el.Omega = elements.number(o, "Omega") * deg;
  el.omega = elements.number(o, "omega") * deg;
  if (!(std::isfinite(el.a) && el.a > 0.0))
    throw SceneError(o.at("a").here() + "the orbit of " + who + ": 'a' must be positive (bound orbits only; "
                     "give position and velocity for others)");
  if (!(el.e >= 0.0 && el.e < 1.0))
    throw SceneError(o.at("e").here() + "the orbit of " + who + ": 'e' must be in [0, 1) (bound orbits "
                     "only; give position and velocity for others)");
  if (o.has("nu") && o.has("M"))
    throw SceneError(o.here() + "the orbit of " + who + ": give the true anomaly 'nu' or the mean anomaly "
                     "'M' (degrees), not both (neither: M = 0, at periapsis)");
  el.nu = o.has("nu") ? o.at("nu").as_double() * deg : true_from_mean_anomaly(elements.number(o, "M") * deg, el.e);
  if (!std::isfinite(el.i + el.Omega + el.omega + el.nu))
    throw SceneError(o.here() + "the orbit of " + who + ": angles must be finite numbers (degrees)");
  return el;
}

State initial_state(const Params& bodies, const System& sys, bool barycentric) {
  State s = State::zeros(sys);
  const auto [positions, velocities] = initial_translation(bodies, sys, barycentric);
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Params& b = bodies.items()[i];
    const Body& body = sys.body(i);
    const auto col = static_cast<Eigen::Index>(i);
    s.x.col(col) = positions[i];
    s.p.col(col) = body.mass * velocities[i];
    if (const int k = sys.rigid_index(i); k >= 0) {
      if (b.has("attitude")) s.R[static_cast<std::size_t>(k)] = attitude(b.at("attitude"), body.name);
      if (b.has("angular_velocity"))
        s.Pi.col(k) = body.inertia * vec3(b.at("angular_velocity"));  // Π = J Ω
      if (b.has("angular_momentum")) s.Pi.col(k) = vec3(b.at("angular_momentum"));
    }
  }
  if (const auto conflict = start_conflict(sys, s, false))
    throw SceneError(bodies.items()[conflict->body].here() + conflict->what);
  return s;
}

}  // namespace noether::detail
