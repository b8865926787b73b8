// docs/fitting.md, "Does the fit tell the truth?": 100 noisy synthetic data sets from the
// Didymos–Dimorphos scene (examples/didymos.yaml with 60 s steps, half the cost of its 30 s and
// the same scene for the truth and the fits: Dimorphos' relative position x, y, z at 30 epochs
// over 3 days, noise 1 m), each fitted for Dimorphos' density and initial velocity. A fit
// whose 1σ are honest puts each parameter within 3σ of the truth in ~99.7 of 100 data sets, its
// estimates spread as its σ says, and its χ² averages the degrees of freedom.
#include "test_support.hpp"

#include <noether/fit.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>
#include <unistd.h>

using namespace noether;

namespace {

TEST(FitRecovery, HundredSyntheticDataSetsAgreeWithTheirSigmas) {
  const std::string scene = test::source_path("examples/didymos.yaml");
  const std::vector<std::string> sixty{"integrator.step=60", "run.output_every=600"};
  const std::vector<std::string> free{"bodies.dimorphos.density", "bodies.dimorphos.velocity"};
  // The truth: the scene's own values; the epochs every 8640 s (on the LGVI's 60 s grid).
  std::vector<Observation> epochs;
  for (int k = 1; k <= 30; ++k)
    for (auto kind : {Observable::Kind::position_x, Observable::Kind::position_y, Observable::Kind::position_z}) {
      Observation o;
      o.t = 8640.0 * k;
      o.observable.kind = kind;
      o.observable.target = 1;  // dimorphos
      o.observable.center = 0;  // didymos
      o.sigma = 1.0;
      epochs.push_back(o);
    }
  PluginRegistry truth_registry = test::bundled_plugins();
  const Prediction truth = predict(scene, sixty, epochs, free, truth_registry);
  const auto P = static_cast<Eigen::Index>(truth.names.size());
  Eigen::VectorXd known(P);
  const Scene s = load_scene(scene, sixty);
  known << 0, s.root.at("bodies").items()[1].at("velocity").as_doubles()[1], 0,
      s.root.at("bodies").items()[1].at("density").as_double();
  ASSERT_EQ(truth.names, (std::vector<std::string>{"bodies.dimorphos.velocity.0", "bodies.dimorphos.velocity.1",
                                                   "bodies.dimorphos.velocity.2", "bodies.dimorphos.density"}));

  constexpr int kSets = 100;
  std::vector<FitResult> fits(kSets);
  auto work = [&](int first, int stride) {
    PluginRegistry registry = test::bundled_plugins();
    for (int k = first; k < kSets; k += stride) {
      std::mt19937_64 random(1000 + static_cast<std::uint64_t>(k));
      std::normal_distribution<double> noise;
      std::vector<Observation> data = epochs;
      for (std::size_t i = 0; i < data.size(); ++i) data[i].value = truth.values[static_cast<Eigen::Index>(i)] + noise(random);
      std::ostringstream text;
      write_observations(text, data, {"didymos", "dimorphos"});
      const auto file = std::filesystem::temp_directory_path() /
                        ("noether-fit-recovery-" + std::to_string(::getpid()) + "-" + std::to_string(k) + ".csv");
      std::ofstream(file) << text.str();
      FitOptions options;
      options.free = free;
      fits[static_cast<std::size_t>(k)] = fit(scene, sixty, file, options, registry);
      std::filesystem::remove(file);
    }
  };
  std::thread other(work, 1, 2);
  work(0, 2);
  other.join();

  std::vector<int> within(static_cast<std::size_t>(P), 0);
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(P), square = Eigen::VectorXd::Zero(P), sigma = Eigen::VectorXd::Zero(P);
  double chi2 = 0;
  for (const auto& f : fits) {
    ASSERT_TRUE(f.converged) << f.stop;
    for (Eigen::Index j = 0; j < P; ++j) {
      const double error = f.estimate[j] - known[j];
      within[static_cast<std::size_t>(j)] += std::abs(error) <= 3 * f.sigma[j];
      mean[j] += error / kSets;
      square[j] += error * error / kSets;
      sigma[j] += f.sigma[j] / kSets;
    }
    chi2 += f.chi2 / kSets;
  }
  const double dof = static_cast<double>(fits[0].degrees_of_freedom);
  std::printf("100 fits of %td parameters to 90 positions (1 m): mean chi2 %.2f for %.0f degrees of freedom\n", P, chi2, dof);
  for (Eigen::Index j = 0; j < P; ++j) {
    const double spread = std::sqrt((square[j] - mean[j] * mean[j]) * kSets / (kSets - 1));
    std::printf("  %-28s within 3σ in %3d of 100; spread of the estimates %.3e, mean reported σ %.3e (ratio %.3f); "
                "mean error %+.2f σ\n",
                truth.names[static_cast<std::size_t>(j)].c_str(), within[static_cast<std::size_t>(j)], spread, sigma[j],
                spread / sigma[j], mean[j] / sigma[j]);
    EXPECT_GE(within[static_cast<std::size_t>(j)], 97) << truth.names[static_cast<std::size_t>(j)];
    EXPECT_NEAR(spread / sigma[j], 1.0, 0.2) << truth.names[static_cast<std::size_t>(j)];
  }
  // χ²'s mean over 100 sets: dof ± 3 √(2 dof / 100).
  EXPECT_NEAR(chi2, dof, 3 * std::sqrt(2 * dof / kSets));
}

}  // namespace
