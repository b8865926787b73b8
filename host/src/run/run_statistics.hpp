#pragma once
// RunStatistics: the run's accounting at every output frame — the summary's running values
// (E0, max |E − E0|, the momentum errors, closest approach, the smallest gap) and the frame
// handed on to the output. Internal to libnoether (Simulation, its continuation).
#include <noether/diagnostics.hpp>
#include <noether/error.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "run/attracting_pairs.hpp"
#include "run/event_watch.hpp"
#include "run/summary_schema.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace noether::detail {

// The run's accounting at every frame: the summary's statistics, and the frame to the output.
class RunStatistics final : public Observer {
 public:
  // `write` hands each observed frame on (to the output); `on_frame` is called at the end of
  // every frame's accounting (the run features' observe_frame), with whether it was a segment's first.
  RunStatistics(const System& system, RunSummary& summary, std::function<void(const State&, const Diagnostics&)> write,
                std::function<void(const State&, bool)> on_frame = nullptr)
      : system_(system), s_(summary), write_(std::move(write)), on_frame_(std::move(on_frame)) {
    if (system.size() <= 64) contacts_ = watches(system, Events{0.0, true, {}});  // O(n²): small scenes only
  }

  void observe(const State& state, const Forces& forces, bool interpolated) override {
    const Diagnostics d = account(state, forces);
    if (interpolated) ++s_.interpolated_frames;
    if (write_) write_(state, d);
  }

  // The statistics of one frame (also of the frames a continued run replays from its file).
  Diagnostics account(const State& state, const Forces& forces) {
    const Diagnostics d = diagnose(system_, state, forces.U);
    // A non-finite energy or state is a failure, never a number in the summary (std::max
    // would drop a NaN silently).
    const bool state_finite = state.x.allFinite() && state.p.allFinite() && state.Pi.allFinite();
    if (s_.frames == 0 && (!state_finite || !std::isfinite(d.energy))) {  // refused before any step
      std::ostringstream msg;
      msg << "the initial state: ";
      if (!state_finite)
        msg << "its " << (!state.x.allFinite() ? "positions" : !state.p.allFinite() ? "momenta m v" : "angular momenta J Ω")
            << " are not finite";
      else
        msg << "its energy is not finite (kinetic " << d.kinetic_translational + d.kinetic_rotational
            << ", potential " << d.potential << ")";
      msg << ": masses × velocities², or G × masses² / distances, overflow a double; give the scene "
             "units that keep its numbers far from 1e±300 (docs/user-guide.md \"Units\")";
      throw SceneError(msg.str());
    }
    if (!std::isfinite(d.energy) || !state_finite) {
      std::ostringstream msg;
      msg << "the " << (std::isfinite(d.energy) ? "state" : "energy") << " became non-finite at t = " << state.t
          << " (the integrator diverged: a smaller step or tolerance?)";
      throw IntegrationError(msg.str(), state.t);
    }
    // Positions beyond kLargestCoordinate: their distances' squares overflow (separations of inf,
    // potentials of 0: a summary over them said "trustworthy").
    if (state.x.size() > 0 && state.x.cwiseAbs().maxCoeff() > kLargestCoordinate) {
      std::ostringstream msg;
      msg << "a position is beyond " << kLargestCoordinate << " at t = " << state.t
          << " (its distances' squares overflow a double: give the scene units that keep its numbers far from 1e±300, "
             "docs/user-guide.md \"Units\")";
      if (s_.frames == 0) throw SceneError("the initial state: " + msg.str());  // refused before any step
      throw IntegrationError(msg.str(), state.t);
    }
    // Finite state, infinite momenta: products that overflow a double (a body 1e300 away). A
    // summary over them would say "error 0"; no such run is trustworthy.
    if (!d.linear_momentum.allFinite() || !d.angular_momentum.allFinite()) {
      std::ostringstream msg;
      msg << "the total " << (d.linear_momentum.allFinite() ? "angular" : "linear") << " momentum is not finite at t = "
          << state.t << " (positions × momenta overflow a double: give the scene units that keep its numbers "
          << "far from 1e±300, docs/user-guide.md \"Units\")";
      if (s_.frames == 0) throw SceneError("the initial state: " + msg.str());  // refused before any step
      throw IntegrationError(msg.str(), state.t);
    }
    if (s_.frames == 0) {
      s_.initial = d;
      // Scales for the relative momentum errors: the sum of the magnitudes of the parts.
      p_scale_ = L_scale_ = exchanged_p_ = exchanged_L_ = 0.0;
      for (Eigen::Index i = 0; i < state.p.cols(); ++i) {
        p_scale_ += state.p.col(i).norm();
        L_scale_ += Vec3(state.x.col(i)).cross(Vec3(state.p.col(i))).norm();
      }
      for (Eigen::Index k = 0; k < state.Pi.cols(); ++k) L_scale_ += state.Pi.col(k).norm();
      s_.min_distance = std::numeric_limits<double>::infinity();
      s_.orbits = orbit_scales(state);
      detect_conservation(state, forces);
    }
    const bool first_of_segment = s_.frames == 0;
    s_.final = d;
    // Forces beyond the potential put in W, ΔP, ΔL since t0: the forced flow conserves E − W,
    // P − ΔP and L − ΔL (docs/equations.md eq. 33.3), so errors are measured from E0 + W, ….
    double W = 0.0;
    Vec3 dP = Vec3::Zero(), dL = Vec3::Zero();
    if (state.force_balance.size() > 0) {
      const Eigen::VectorXd total = state.force_balance.rowwise().sum();
      W = total(0);
      dP = total.segment<3>(1);
      dL = total.segment<3>(4);  // (each force's part: ForceBalanceFeature)
    }
    s_.max_abs_energy_error = std::max(s_.max_abs_energy_error, std::abs(d.energy - W - s_.initial.energy));
    // Momentum the forces put in counts in the scale: what they exchange (a flyby accelerating
    // the whole scene) is carried with its own round-off, which no method can beat.
    exchanged_p_ = std::max(exchanged_p_, dP.norm());
    exchanged_L_ = std::max(exchanged_L_, dL.norm());
    if (p_scale_ + exchanged_p_ > 0)
      s_.max_rel_linear_momentum_error =
          std::max(s_.max_rel_linear_momentum_error,
                   (d.linear_momentum - dP - s_.initial.linear_momentum).norm() / (p_scale_ + exchanged_p_));
    if (L_scale_ + exchanged_L_ > 0)
      s_.max_rel_angular_momentum_error =
          std::max(s_.max_rel_angular_momentum_error,
                   (d.angular_momentum - dL - s_.initial.angular_momentum).norm() / (L_scale_ + exchanged_L_));
    s_.max_orthogonality_error = std::max(s_.max_orthogonality_error, d.orthogonality_error);
    // Closest approach of centres at the frames, O(n²): scenes too large for every pair to be
    // followed between frames (the closest approach feature, up to kClosestApproachMostBodies),
    // and small enough.
    if (state.x.cols() > static_cast<Eigen::Index>(kClosestApproachMostBodies) && state.x.cols() <= 64)
      for (Eigen::Index i = 0; i < state.x.cols(); ++i)
        for (Eigen::Index j = i + 1; j < state.x.cols(); ++j) {
          const double r = (state.x.col(i) - state.x.col(j)).norm();
          const Body &a = system_.body(static_cast<std::size_t>(i)), &b = system_.body(static_cast<std::size_t>(j));
          if (r < s_.min_distance) {
            s_.min_distance = r;
            s_.t_of_min_distance = state.t;
            s_.min_distance_pair = a.name + "–" + b.name;
          }
        }
    for (const Watch& w : contacts_) {  // the collision event's gap: the surfaces, or the spheres
      const double g = w.gap(system_, state);
      if (g < s_.min_gap) {
        s_.min_gap = g;
        s_.min_gap_reach = w.threshold;
        s_.min_gap_pair = system_.body(w.a).name + "–" + system_.body(w.b).name;
      }
    }
    ++s_.frames;
    if (on_frame_) on_frame_(state, first_of_segment);
    return d;
  }

  // An impulse (Simulation, docs/equations.md §24) changed the momenta from `before` to `after` at
  // the same positions (potential energy U): the references of the conserved quantities move by
  // the jump (24.3).
  void impulse(const State& before, const State& after, double U) {
    const Diagnostics a = diagnose(system_, before, U), b = diagnose(system_, after, U);
    s_.initial.energy += b.energy - a.energy;
    s_.initial.kinetic_translational += b.kinetic_translational - a.kinetic_translational;
    s_.initial.linear_momentum += b.linear_momentum - a.linear_momentum;
    s_.initial.angular_momentum += b.angular_momentum - a.angular_momentum;
    ++s_.impulses;
    s_.impulse_energy += b.energy - a.energy;
  }

  // Its running values beyond the summary's rows, named, for a saved simulation: the scales of
  // the relative momentum errors, the largest ‖ΔP‖, ‖ΔL‖ the forces put in so far (part of
  // those scales in a forced run: `forced`).
  void save(SavedSummary& out, bool forced) const {
    out.numbers.push_back({"linear_momentum_scale", {p_scale_}});
    out.numbers.push_back({"angular_momentum_scale", {L_scale_}});
    if (forced) {
      out.numbers.push_back({"exchanged_linear_momentum", {exchanged_p_}});
      out.numbers.push_back({"exchanged_angular_momentum", {exchanged_L_}});
    }
  }
  // Throws Error naming what a checkpoint lacks.
  void restore(const SavedSummary& in, bool forced) {
    auto one = [&in](const char* key) { return in.require(key, 1)[0]; };
    p_scale_ = one("linear_momentum_scale"), L_scale_ = one("angular_momentum_scale");
    if (forced) {
      if (!in.number("exchanged_linear_momentum"))
        throw Error("saved without the momenta its forces exchanged, which the verdict's scales need");
      exchanged_p_ = one("exchanged_linear_momentum"), exchanged_L_ = one("exchanged_angular_momentum");
    }
  }

 private:
  // Each body's orbit about the body that attracts it most at t0 (attracting_pairs.hpp), with the
  // pair's two-body energy as its scale (RunSummary::orbits). Scenes of more than 64 bodies are
  // judged on E0 alone (O(n²)).
  std::vector<OrbitScale> orbit_scales(const State& state) const {
    std::vector<OrbitScale> orbits;
    const double G = system_.G();
    for (const AttractingPair& pair : attracting_pairs(system_, state)) {
      const auto i = static_cast<Eigen::Index>(pair.body), j = static_cast<Eigen::Index>(pair.about);
      const Body &a = system_.body(pair.body), &b = system_.body(pair.about);
      const double mu = a.mass * b.mass / (a.mass + b.mass);
      const Vec3 v = state.p.col(i) / a.mass - state.p.col(j) / b.mass;
      const double kinetic = 0.5 * mu * v.squaredNorm(),
                   potential = G * a.mass * b.mass / (state.x.col(i) - state.x.col(j)).norm();
      const double bound = std::abs(kinetic - potential);
      // (A near-parabolic pair: the sum of the parts.)
      orbits.push_back({a.name, b.name, bound >= 1e-3 * (kinetic + potential) ? bound : kinetic + potential, 0.0});
    }
    std::sort(orbits.begin(), orbits.end(),
              [](const OrbitScale& x, const OrbitScale& y) { return x.energy_scale < y.energy_scale; });
    return orbits;
  }

  // The forces at t0 tell what the scene conserves: a net force or a net torque about the
  // origin larger than 10⁻⁶ of the sum of their parts is an external field.
  void detect_conservation(const State& state, const Forces& forces) {
    Vec3 F = Vec3::Zero(), T = Vec3::Zero();
    double F_parts = 0.0, T_parts = 0.0;
    for (Eigen::Index i = 0; i < forces.f.cols(); ++i) {
      const Vec3 f = forces.f.col(i), torque = Vec3(state.x.col(i)).cross(f);
      F += f, F_parts += f.norm();
      T += torque, T_parts += torque.norm();
    }
    for (Eigen::Index k = 0; k < forces.M.cols(); ++k) {
      T += state.R[static_cast<std::size_t>(k)] * Vec3(forces.M.col(k));  // d(R Π)/dt = R M
      T_parts += forces.M.col(k).norm();
    }
    s_.conserves_linear_momentum = F.norm() <= 1e-6 * F_parts;
    s_.conserves_angular_momentum = T.norm() <= 1e-6 * T_parts;
  }

  const System& system_;
  RunSummary& s_;
  std::vector<Watch> contacts_;  // every pair with radii, for the smallest gap (RunSummary::min_gap)
  std::function<void(const State&, const Diagnostics&)> write_;
  std::function<void(const State&, bool)> on_frame_;
  double p_scale_ = 0.0, L_scale_ = 0.0;
  double exchanged_p_ = 0.0, exchanged_L_ = 0.0;  // the largest ‖ΔP‖, ‖ΔL‖ the forces put in so far
};

// Work counters added up; −1 (not reported) stays −1.
inline WorkCounters operator+(const WorkCounters& a, const WorkCounters& b) {
  return WorkCounters{a.steps + b.steps, a.potential_evaluations + b.potential_evaluations,
                      a.newton_iterations + b.newton_iterations,
                      a.rejected_steps < 0 || b.rejected_steps < 0 ? -1 : a.rejected_steps + b.rejected_steps};
}

}  // namespace noether::detail
