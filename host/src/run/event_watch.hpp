#pragma once
// What the stepping loop watches for events (docs/equations.md §16): one function g of the state
// per watched pair, positive until the event and ≤ 0 at it, located inside a step by regula
// falsi on interpolated states (16.3).
#include <noether/stepping.hpp>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace noether {

struct Watch {
  enum class Kind { kCloseApproach, kCollision, kEscape, kUnbound };
  Kind kind = Kind::kCloseApproach;
  std::size_t a = 0, b = 0;
  double threshold = 0.0;  // close approach: the distance; collision: the bounding spheres' radii; escape: the distance
  bool armed = false;      // a pair that starts at g ≤ 0 is armed only once g > 0 again
  // A collision of shapes: each body's surface points in its body frame (surface_samples;
  // empty for a body without a solid, a sphere of its radius).
  std::shared_ptr<const std::array<Eigen::Matrix3Xd, 2>> samples;

  // g at a state (positions; attitudes for shapes; momenta for kUnbound). Eqs. 16.1, 16.5, 16.8.
  double gap(const System& system, const State& state) const;
  // Whether g > 0 is certain from the centres' squared distance alone (no square root, no
  // surface): the check the stepping loop makes at every step before computing g.
  // (In line: it is most of what an event costs a step.)
  bool clear(const State& state) const {
    const double r2 = (state.x.col(static_cast<Eigen::Index>(a)) - state.x.col(static_cast<Eigen::Index>(b))).squaredNorm();
    const double d2 = threshold * threshold;
    switch (kind) {
      case Kind::kCloseApproach: return r2 > d2;  // r > d
      case Kind::kCollision: return r2 > d2;      // the bounding spheres apart (16.5)
      case Kind::kEscape: return r2 < d2;
      case Kind::kUnbound: return false;
    }
    return false;
  }
  const char* name() const;  // "close approach", "collision", "escape", "unbound"
  // The stop reason: "collision: the shapes of bodies 'a' and 'b' touched at t = …".
  std::string describe(const System& system, double t) const;
};

// The watches of a run's events.
std::vector<Watch> watches(const System& system, const Events& events);

// The events as a cut of the stepping loop's steps: each watched pair's g, its crossing inside
// a step located by the Illinois variant of regula falsi on the interpolated states (16.3); the
// earliest crossing of any armed pair is the cut.
class EventWatch final : public StepCut {
 public:
  EventWatch(const System& system, const Events& events) : watch_(watches(system, events)) {}
  bool empty() const { return watch_.empty(); }
  void arm(const System& system, const State& start) override;
  std::optional<double> cut(const System& system, const Step& step) override;
  void describe(const System& system, double t, StopInfo& stop) const override;

 private:
  std::vector<Watch> watch_;
  const Watch* hit_ = nullptr;  // the pair of the last cut
};

// Whether a stop reason (StopInfo::reason) is an event's — "collision: …", "escape: …" — rather
// than an interruption.
bool is_event(const std::string& reason);

}  // namespace noether
