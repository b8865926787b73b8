#pragma once
// The chaos indicators as a run feature (run.chaos; docs/derivatives.md, "Chaos indicators"):
// one deviation vector δ in the tangent, MEGNO and the FLI updated from it after every step
// (ChaosIndicators), their values in every frame (its series) and the last ones in the summary. Its fields —
// δ, the norm's scales and the indicators' running sums — make a continued run's indicators the
// uninterrupted run's, bit for bit.
#include "run/chaos_indicators.hpp"
#include "run/run_feature.hpp"

#include <memory>

namespace noether::detail {

class ChaosFeature final : public RunFeature {
 public:
  explicit ChaosFeature(const System& system) : system_(system) {}
  std::string_view name() const override { return "chaos"; }
  Eigen::Index tangent_columns() const override { return 1; }
  void start(const State& state, Eigen::Ref<Eigen::MatrixXd> columns) override;
  void after_step(const State& reached, Eigen::Ref<const Eigen::MatrixXd> columns) override;
  std::vector<std::string> fields() const override;
  void save(Eigen::Ref<const Eigen::MatrixXd> columns, std::span<double> out) const override;
  void restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd> columns) override;
  void summarize(RunSummary& summary) const override;
  // MEGNO and the FLI where the run stands at each frame (/derivatives/megno, /derivatives/fli);
  // at a recorded frame, those its fields hold.
  std::vector<FeatureSeries> series() const override { return {{"megno", {}}, {"fli", {}}}; }
  void record(const State&, std::span<double> out) const override;
  void recorded(const io::RecordedFrame&, std::span<const double> fields, std::span<double> out) const override;

  // The indicators where the run stands.
  const ChaosValues& values() const { return indicators_->values(); }
  // The indicators a frame's saved fields hold (a continued run's frames read back).
  static ChaosValues values_of(std::span<const double> fields);

 private:
  const System& system_;
  std::unique_ptr<ChaosIndicators> indicators_;
};

}  // namespace noether::detail
