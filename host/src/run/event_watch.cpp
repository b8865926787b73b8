// The event functions of the stepping loop (event_watch.hpp; docs/equations.md §16).
#include "run/event_watch.hpp"

#include <noether/surface_distance.hpp>

#include "run/regula_falsi.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

namespace noether {

namespace {

Vec3 position(const State& s, std::size_t i) { return s.x.col(static_cast<Eigen::Index>(i)); }
Mat3 attitude(const System& system, const State& s, std::size_t i) {
  const auto k = system.rigid_index(i);
  return k >= 0 ? s.R[static_cast<std::size_t>(k)] : Mat3::Identity();
}

// min over the points q of the first body (body frame of a) of the gap of x_a + R_a q to the
// second body's surface; points outside its bounding sphere count by their distance to it (a
// lower bound, positive), so only the points near it cost a surface_gap.
double sampled_gap(const System& system, const State& s, std::size_t a, std::size_t b, const Eigen::Matrix3Xd& points) {
  const Body& B = system.body(b);
  const Mat3 Ra = attitude(system, s, a);
  const Mat3 Rb_t = attitude(system, s, b).transpose();
  const Vec3 offset = Rb_t * (position(s, a) - position(s, b));
  const Mat3 A = Rb_t * Ra;
  double g = std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k < points.cols(); ++k) {
    const Vec3 p = offset + A * points.col(k);
    const double r = p.norm();
    g = std::min(g, r > B.radius ? r - B.radius : surface_gap(*B.solid, p));
  }
  return g;
}

// A body's surface against a solid's (16.5): a body without a solid is a sphere of its radius
// about its centre (a point mass: radius 0), exact against the solid; two solids meet when a
// surface point of one enters the other (vertices of a polyhedron, the sampled ellipsoid).
double contact_gap(const System& system, const State& s, std::size_t a, std::size_t b,
                   const std::array<Eigen::Matrix3Xd, 2>& samples) {
  const Body &A = system.body(a), &B = system.body(b);
  const double spheres = (position(s, a) - position(s, b)).norm() - (A.radius + B.radius);
  if (spheres > 0) return spheres;  // the bounding spheres apart: no contact
  if (!A.solid) return surface_gap(*B.solid, attitude(system, s, b).transpose() * (position(s, a) - position(s, b))) - A.radius;
  if (!B.solid) return surface_gap(*A.solid, attitude(system, s, a).transpose() * (position(s, b) - position(s, a))) - B.radius;
  return std::min(sampled_gap(system, s, a, b, samples[0]), sampled_gap(system, s, b, a, samples[1]));
}

}  // namespace

double Watch::gap(const System& system, const State& s) const {
  const double r = (position(s, a) - position(s, b)).norm();
  switch (kind) {
    case Kind::kCloseApproach: return r - threshold;  // (16.1)
    case Kind::kCollision: return samples ? contact_gap(system, s, a, b, *samples) : r - threshold;
    case Kind::kEscape: return threshold - r;
    case Kind::kUnbound: {  // minus the two-body energy per reduced mass (16.8): e ≥ 1 at g ≤ 0
      const double ma = system.body(a).mass, mb = system.body(b).mass;
      const Vec3 v = s.p.col(static_cast<Eigen::Index>(a)) / ma - s.p.col(static_cast<Eigen::Index>(b)) / mb;
      return system.G() * (ma + mb) / r - 0.5 * v.squaredNorm();
    }
  }
  return r;
}

const char* Watch::name() const {
  switch (kind) {
    case Kind::kCloseApproach: return "close approach";
    case Kind::kCollision: return "collision";
    case Kind::kEscape: return "escape";
    case Kind::kUnbound: return "unbound";
  }
  return "";
}

std::string Watch::describe(const System& system, double t) const {
  std::ostringstream why;
  why.precision(10);
  const std::string na = system.body(a).name, nb = system.body(b).name;
  switch (kind) {
    case Kind::kCloseApproach:
      why << "close approach: bodies '" << na << "' and '" << nb << "' came within " << threshold;
      break;
    case Kind::kCollision:
      if (samples)
        why << "collision: the surfaces of bodies '" << na << "' and '" << nb << "' touched";
      else
        why << "collision: bodies '" << na << "' and '" << nb << "' came within " << threshold
            << " (the sum of their radii)";
      break;
    case Kind::kEscape:
      why << "escape: body '" << na << "' went farther than " << threshold << " from '" << nb << "'";
      break;
    case Kind::kUnbound:
      why << "unbound: body '" << na << "' is no longer bound to '" << nb
          << "' (two-body energy ≥ 0, osculating e ≥ 1)";
      break;
  }
  why << " at t = " << t;
  return why.str();
}

bool is_event(const std::string& reason) {
  Watch w;
  for (const auto kind : {Watch::Kind::kCloseApproach, Watch::Kind::kCollision, Watch::Kind::kEscape,
                          Watch::Kind::kUnbound}) {
    w.kind = kind;
    if (reason.rfind(std::string(w.name()) + ":", 0) == 0) return true;
  }
  return false;
}

std::vector<Watch> watches(const System& system, const Events& events) {
  std::vector<Watch> out;
  using K = Watch::Kind;
  auto watch = [](K kind, std::size_t a, std::size_t b, double threshold) {
    Watch w;
    w.kind = kind, w.a = a, w.b = b, w.threshold = threshold;
    return w;
  };
  for (std::size_t a = 0; a < system.size(); ++a)
    for (std::size_t b = a + 1; b < system.size(); ++b) {
      if (events.close_approach > 0) out.push_back(watch(K::kCloseApproach, a, b, events.close_approach));
      const Body &A = system.body(a), &B = system.body(b);
      const double contact = A.radius + B.radius;
      if (!events.collisions || !(contact > 0)) continue;
      Watch w = watch(K::kCollision, a, b, contact);
      if (A.solid || B.solid)
        w.samples = std::make_shared<const std::array<Eigen::Matrix3Xd, 2>>(std::array<Eigen::Matrix3Xd, 2>{
            A.solid ? surface_samples(*A.solid) : Eigen::Matrix3Xd(3, 0),
            B.solid ? surface_samples(*B.solid) : Eigen::Matrix3Xd(3, 0)});
      out.push_back(std::move(w));
    }
  if (const auto& e = events.escape) {
    if (e->distance > 0) out.push_back(watch(K::kEscape, e->body, e->about, e->distance));
    if (e->unbound) out.push_back(watch(K::kUnbound, e->body, e->about, 0.0));
  }
  return out;
}

void EventWatch::arm(const System& system, const State& start) {
  for (auto& w : watch_) w.armed = w.gap(system, start) > 0;
}

std::optional<double> EventWatch::cut(const System& system, const Step& step) {
  const State& reached = step.reached;
  std::optional<double> first;
  hit_ = nullptr;
  for (auto& w : watch_) {
    if (w.clear(reached)) {  // most steps of most pairs
      w.armed = true;
      continue;
    }
    const double g1 = w.gap(system, reached);
    if (!w.armed) {
      w.armed = g1 > 0;
      continue;
    }
    if (g1 > 0) continue;
    const double b = detail::illinois_root([&](double c) { return w.gap(system, step.at(c)); }, step.t_prev, step.t,
                                           w.gap(system, step.previous), g1, 1e-14);
    if (!first || b < *first) first = b, hit_ = &w;
  }
  return first;
}

void EventWatch::describe(const System& system, double t, StopInfo& stop) const {
  stop.reason = hit_->describe(system, t);
  stop.event = hit_->name();
  stop.body_a = hit_->a;
  stop.body_b = hit_->b;
}

}  // namespace noether
