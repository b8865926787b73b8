// Bodies apart where a run starts (start_apart.hpp).
#include "scene/start_apart.hpp"

#include "run/event_watch.hpp"

#include <algorithm>
#include <array>
#include <sstream>
#include <vector>

namespace noether::detail {

namespace {

std::optional<StartConflict> coincident(const System& sys, const State& s) {
  std::vector<std::size_t> order(sys.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto key = [&](std::size_t i) {
    const auto c = s.x.col(static_cast<Eigen::Index>(i));
    return std::array<double, 3>{c.x(), c.y(), c.z()};
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::size_t i = std::min(order[k - 1], order[k]), j = std::max(order[k - 1], order[k]);
    if (key(i) == key(j))
      return StartConflict{j, "bodies '" + sys.body(i).name + "' and '" + sys.body(j).name +
                                  "' start at the same position"};
  }
  return std::nullopt;
}

// The unit a body's mesh file is read in, or "" for a shape that is not a mesh file.
std::string mesh_unit(const Body& body) {
  if (!body.shape.is_map() || !body.shape.has("polyhedron")) return "";
  const Params& p = body.shape.at("polyhedron");
  return p.is_map() && p.has("units") ? p.at("units").as_string() : "";
}

// "the mesh of 'a' is read in km", "the meshes of 'a' and 'b' are read in m", or "".
std::string mesh_units(const Body& a, const Body& b) {
  const std::string ua = mesh_unit(a), ub = mesh_unit(b);
  if (!ua.empty() && ua == ub) return "the meshes of '" + a.name + "' and '" + b.name + "' are read in " + ua;
  std::string out = ua.empty() ? "" : "the mesh of '" + a.name + "' is read in " + ua;
  if (!ub.empty()) out += (out.empty() ? "" : ", ") + std::string("the mesh of '") + b.name + "' is read in " + ub;
  return out;
}

}  // namespace

std::optional<StartConflict> start_conflict(const System& sys, const State& s, bool collisions) {
  if (auto c = coincident(sys, s)) return c;
  if (!collisions || sys.size() > 64) return std::nullopt;
  for (const Watch& w : watches(sys, Events{0.0, true, {}})) {
    const double gap = w.gap(sys, s);  // surfaces, or the spheres of `radius` (16.5)
    if (!(gap < -1e-9 * w.threshold)) continue;
    const Body &a = sys.body(w.a), &b = sys.body(w.b);
    const double separation =
        (s.x.col(static_cast<Eigen::Index>(w.a)) - s.x.col(static_cast<Eigen::Index>(w.b))).norm();
    std::ostringstream msg;
    msg.precision(4);
    msg << "bodies '" << a.name << "' and '" << b.name << "' overlap at the start: " << -gap
        << " inside each other's surface (centres " << separation << " apart; bounding radii " << a.radius << " and "
        << b.radius << ")";
    if (const std::string units = mesh_units(a, b); !units.empty())
      msg << "; " << units << " (shape.polyhedron.units: a mesh in the wrong units is 1000 times too large or small)";
    msg << "; move them apart";
    return StartConflict{w.b, msg.str()};
  }
  return std::nullopt;
}

}  // namespace noether::detail
