#pragma once
// Each pair of bodies' closest approach as a run feature (RunSummary::closest_approaches;
// docs/user-guide.md "Closest approaches"): the distance between their centres followed frame by
// frame and its least value located between frames — where the relative position r turns from
// approaching (r·ṙ < 0) to receding — on the cubic Hermite of r through the two frames'
// positions and velocities (docs/equations.md eq. 16.9), with a bound on that interpolation's
// error, twice Δt⁴ Ω⁴ |r| / 384 (Ω² the largest of the relative angular rate², G(m_a + m_b)/|r|³ and the
// relative acceleration over the interval per unit distance, |Δṙ| / (Δt |r|): the Hermite
// remainder with |r''''| ≈ Ω⁴ |r|), and on its time (that of r·ṙ, twice |r| Δt³ Ω⁴ |r| / 72 +
// |ṙ| times the first, over d(r·ṙ)/dt). Built from the frames alone, a continued run's
// replayed frames rebuild it; its running values are kept in a saved simulation. Scenes of 2 to
// 12 bodies (66 pairs).
#include "run/run_feature.hpp"

#include <noether/closest_approach.hpp>

#include <vector>

namespace noether::detail {

class ClosestApproachFeature final : public RunFeature {
 public:
  explicit ClosestApproachFeature(const System& system);
  std::string_view name() const override { return "closest_approach"; }
  void start(const State&, Eigen::Ref<Eigen::MatrixXd>) override {}
  void observe_frame(const State& state, bool first_of_segment, RunSummary&) override;
  void save_running(SavedSummary& out) const override;
  void restore_running(const SavedSummary& in) override;
  void summarize(RunSummary& summary) const override;

 private:
  struct Track {
    std::size_t a = 0, b = 0;
    double distance = 0.0, t = 0.0, frames_error = 0.0, frames_time_error = 0.0;
    ClosestApproach::Where where = ClosestApproach::Where::kStart;
    double t_prev = 0.0;
    Vec3 r_prev = Vec3::Zero(), v_prev = Vec3::Zero();  // at the last frame
  };
  Vec3 relative(const State& s, const Track& p) const;
  Vec3 relative_velocity(const State& s, const Track& p) const;
  void offer(Track& p, double distance, double t, ClosestApproach::Where where, double frames_error,
             double frames_time_error) const;

  const System& system_;
  std::vector<Track> pairs_;
};

}  // namespace noether::detail
