// Each pair of bodies' closest approach as a run feature (closest_approach_feature.hpp).
#include "run/closest_approach_feature.hpp"

#include <noether/error.hpp>

#include "run/summary_schema.hpp"

#include <algorithm>
#include <cmath>

namespace noether::detail {

ClosestApproachFeature::ClosestApproachFeature(const System& system) : system_(system) {
  for (std::size_t a = 0; a < system.size(); ++a)
    for (std::size_t b = a + 1; b < system.size(); ++b) pairs_.push_back(Track{.a = a, .b = b});
}

Vec3 ClosestApproachFeature::relative(const State& s, const Track& p) const {
  return s.x.col(static_cast<Eigen::Index>(p.b)) - s.x.col(static_cast<Eigen::Index>(p.a));
}

Vec3 ClosestApproachFeature::relative_velocity(const State& s, const Track& p) const {
  return s.p.col(static_cast<Eigen::Index>(p.b)) / system_.body(p.b).mass -
         s.p.col(static_cast<Eigen::Index>(p.a)) / system_.body(p.a).mass;
}

void ClosestApproachFeature::offer(Track& p, double distance, double t, ClosestApproach::Where where,
                                   double frames_error, double frames_time_error) const {
  if (!(distance < p.distance)) return;
  p.distance = distance, p.t = t, p.where = where, p.frames_error = frames_error;
  p.frames_time_error = frames_time_error;
}

namespace {

// The cubic Hermite of r over [t0, t0 + dt] through (r0, v0) and (r1, v1), at u ∈ [0, 1]: r and ṙ.
struct Hermite {
  Vec3 r0, v0, r1, v1;
  double dt;
  Vec3 at(double u) const {
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * r0 + (u3 - 2 * u2 + u) * dt * v0 + (-2 * u3 + 3 * u2) * r1 + (u3 - u2) * dt * v1;
  }
  Vec3 rate(double u) const {
    const double u2 = u * u;
    return ((6 * u2 - 6 * u) * r0 + (-6 * u2 + 6 * u) * r1) / dt + (3 * u2 - 4 * u + 1) * v0 + (3 * u2 - 2 * u) * v1;
  }
  double g(double u) const { return at(u).dot(rate(u)); }  // ½ d|r|²/dt
};

}  // namespace

void ClosestApproachFeature::observe_frame(const State& state, bool first_of_segment, RunSummary&) {
  for (Track& p : pairs_) {
    const Vec3 r = relative(state, p), v = relative_velocity(state, p);
    if (first_of_segment) {  // the segment's start: receding from there, or closing (for now)
      p.distance = r.norm(), p.t = state.t, p.frames_error = p.frames_time_error = 0.0;
      p.where = r.dot(v) >= 0.0 ? ClosestApproach::Where::kStart : ClosestApproach::Where::kEnd;
    } else if (state.t > p.t_prev) {
      // The minima between the frames: each turn of g = r·ṙ from negative to positive on the
      // Hermite (sampled at 16 points, then bisected), with the interpolation's error bound.
      const Hermite h{p.r_prev, p.v_prev, r, v, state.t - p.t_prev};
      constexpr int kSamples = 16;
      double u_prev = 0.0, g_prev = h.g(0.0);
      for (int k = 1; k <= kSamples; ++k) {
        const double u = static_cast<double>(k) / kSamples, g = h.g(u);
        if (g_prev < 0.0 && g >= 0.0) {
          double lo = u_prev, hi = u;
          for (int i = 0; i < 60 && hi - lo > 1e-15; ++i) (h.g(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
          const double u_min = 0.5 * (lo + hi);
          const Vec3 r_min = h.at(u_min), v_min = h.rate(u_min);
          const double d = r_min.norm();
          const double mu = system_.G() * (system_.body(p.a).mass + system_.body(p.b).mass);
          // Ω²: the relative motion's angular rate², its own gravity's G M / r³, and its mean
          // acceleration over the frames' interval per unit distance (a third body's pull: a
          // spacecraft and a moon both falling towards a primary).
          const double omega2 = std::max({r_min.cross(v_min).squaredNorm() / std::pow(d, 4), mu / (d * d * d),
                                          (v - p.v_prev).norm() / (h.dt * d)});
          // The Hermite's remainder (Δt⁴/384 |r''''|) and its rate's (Δt³/72 |r''''|), |r''''| ≈ Ω⁴ |r|;
          // the time's through r·ṙ, whose rate at the minimum is g' (by differences on the Hermite).
          // (Twice the remainders: Ω is a guess of |r''''|'s scale, within a factor ~1.5 on Didymos'
          // spacecraft at 300 and 1200 s frames against 60 s ones.)
          const double position_bound = 2.0 * std::pow(h.dt, 4) * omega2 * omega2 * d / 384.0;
          const double velocity_bound = 2.0 * std::pow(h.dt, 3) * omega2 * omega2 * d / 72.0;
          const double du = std::min({1e-4, u_min, 1.0 - u_min});
          const double turning = du > 0.0 ? (h.g(u_min + du) - h.g(u_min - du)) / (2.0 * du * h.dt) : 0.0;
          const double g_bound = d * velocity_bound + v_min.norm() * position_bound;
          offer(p, d, p.t_prev + u_min * h.dt, ClosestApproach::Where::kEncounter, position_bound,
                turning > 0.0 ? g_bound / turning : h.dt);
        }
        u_prev = u, g_prev = g;
      }
      offer(p, r.norm(), state.t, r.dot(v) < 0.0 ? ClosestApproach::Where::kEnd : ClosestApproach::Where::kEncounter,
            0.0, 0.0);
    }
    p.t_prev = state.t, p.r_prev = r, p.v_prev = v;  // (a jump's second frame: same t, new velocity)
  }
}

void ClosestApproachFeature::save_running(SavedSummary& out) const {
  std::vector<double> v;
  for (const Track& p : pairs_)
    v.insert(v.end(), {p.distance, p.t, static_cast<double>(p.where), p.frames_error, p.frames_time_error, p.t_prev,
                       p.r_prev.x(), p.r_prev.y(), p.r_prev.z(), p.v_prev.x(), p.v_prev.y(), p.v_prev.z()});
  if (!v.empty()) out.numbers.push_back({"closest_approaches", std::move(v)});
}

void ClosestApproachFeature::restore_running(const SavedSummary& in) {
  const std::vector<double>* v = in.number("closest_approaches");
  if (!v) return;  // a checkpoint from before it was kept: followed from the loaded state
  constexpr std::size_t kNumbers = 12;  // per pair
  if (v->size() != kNumbers * pairs_.size())
    throw Error("its closest approaches' running values are not 12 numbers for each of its " +
                std::to_string(pairs_.size()) + " pairs");
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double* n = v->data() + kNumbers * k;
    Track& p = pairs_[k];
    p.distance = n[0], p.t = n[1], p.where = static_cast<ClosestApproach::Where>(static_cast<int>(n[2]));
    p.frames_error = n[3], p.frames_time_error = n[4], p.t_prev = n[5];
    p.r_prev = Vec3(n[6], n[7], n[8]), p.v_prev = Vec3(n[9], n[10], n[11]);
  }
}

void ClosestApproachFeature::summarize(RunSummary& summary) const {
  summary.closest_approaches.clear();
  for (const Track& p : pairs_) {
    ClosestApproach c;
    c.pair = system_.body(p.a).name + "–" + system_.body(p.b).name;
    c.distance = p.distance, c.t = p.t, c.where = p.where, c.frames_error = p.frames_error;
    c.frames_time_error = p.frames_time_error;
    summary.closest_approaches.push_back(std::move(c));
  }
  std::stable_sort(summary.closest_approaches.begin(), summary.closest_approaches.end(),
                   [](const ClosestApproach& x, const ClosestApproach& y) { return x.distance < y.distance; });
  if (summary.closest_approaches.empty()) return;
  const ClosestApproach& least = summary.closest_approaches.front();
  summary.min_distance = least.distance, summary.t_of_min_distance = least.t, summary.min_distance_pair = least.pair;
}

}  // namespace noether::detail
