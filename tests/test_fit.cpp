// noether fit (docs/fitting.md; docs/equations.md §28): the model's Jacobian against differences
// of whole runs, recovery of known parameters, and what is refused.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/ensemble.hpp>
#include <noether/fit.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace noether;

namespace {

// A file in the temporary folder, removed with it.
struct TempFile {
  std::filesystem::path path;
  TempFile(const std::string& name, const std::string& text)
      : path(std::filesystem::temp_directory_path() / ("noether-fit-" + std::to_string(::getpid()) + "-" + name)) {
    std::ofstream(path) << text;
  }
  ~TempFile() { std::filesystem::remove(path); }
};

// A planet on an inclined, eccentric orbit about a star (G = 1), the LGVI at h = 0.01, frames
// every 0.1, and an impulse at t = 1.5 (along-track, RTN): the fit's model at its most general —
// a mass (a parameter of the dynamics), an initial velocity, an impulse's Δv.
const char* kPlanet = R"(G: 1
bodies:
  - {name: star, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}
  - {name: planet, mass: 1.0e-2, position: [1, 0, 0], velocity: [0, 1.2, 0.2]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.01}
impulses:
  - {body: planet, time: 1.5, delta_v: [0, 0.05, 0], frame: rtn}
run: {t_end: 4, output_every: 0.1}
)";

// Observations at times on the step grid, between steps, at and just around the impulse.
std::vector<Observation> observations_of(const std::vector<double>& times) {
  std::vector<Observation> out;
  for (double t : times)
    for (auto kind : {Observable::Kind::position_x, Observable::Kind::position_y, Observable::Kind::range,
                      Observable::Kind::range_rate, Observable::Kind::sky_north}) {
      Observation o;
      o.t = t;
      o.observable.kind = kind;
      o.observable.target = 1;
      o.observable.center = 0;
      o.observable.line_of_sight = Eigen::Vector3d(0.6, 0.8, 0).normalized();
      o.sigma = 1;
      out.push_back(o);
    }
  return out;
}

const std::vector<double> kTimes{0.3, 0.7234, 1.49, 1.5, 1.5037, 2.2, 3.18, 3.5};

// Every column of the model's Jacobian (28.1)–(28.2) against central differences of whole runs
// with the key moved: a mass (whose column also moves v = γ/m), a velocity, an impulse's Δv —
// for observables on the grid, between frames and on both sides of the impulse.
TEST(Fit, TheModelsJacobianAgreesWithDifferencesOfWholeRuns) {
  const TempFile scene("planet.yaml", kPlanet);
  PluginRegistry registry = test::bundled_plugins();
  const auto obs = observations_of(kTimes);
  const std::vector<std::string> free{"bodies.planet.mass", "bodies.planet.velocity.1", "impulses.0.delta_v.1"};
  const std::vector<double> base{1e-2, 1.2, 0.05}, step{1e-5, 1e-5, 1e-5};
  const Prediction p = predict(scene.path, {}, obs, free, registry);
  // The initial state's keys first, the parameters of the dynamics last (docs/derivatives.md).
  ASSERT_EQ(p.names, (std::vector<std::string>{free[1], free[2], free[0]}));
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto column = std::find(p.names.begin(), p.names.end(), free[j]) - p.names.begin();
    auto moved = [&](double by) {
      char set[96];
      std::snprintf(set, sizeof set, "%s=%.17g", free[j].c_str(), base[j] + by);
      return predict(scene.path, {set}, obs, free, registry).values;
    };
    const Eigen::VectorXd differenced = (moved(step[j]) - moved(-step[j])) / (2 * step[j]);
    const double scale = differenced.cwiseAbs().maxCoeff();
    const double worst = (p.jacobian.col(column) - differenced).cwiseAbs().maxCoeff() / scale;
    if (std::getenv("NOETHER_TEST_VERBOSE")) std::printf("%s: relative difference %.1e\n", free[j].c_str(), worst);
    EXPECT_LT(worst, 1e-6) << free[j];
  }
}

// Observations made by the model at known values (noise-free) are fitted from the scene's own
// values: the fit recovers the known values to a millionth of their 1σ, χ² → 0; the estimate's
// covariance is (AᵀA)⁻¹, symmetric with a unit-diagonal correlation.
TEST(Fit, RecoversKnownValuesFromNoiseFreeData) {
  const TempFile scene("planet.yaml", kPlanet);
  PluginRegistry registry = test::bundled_plugins();
  auto obs = observations_of(kTimes);
  const std::vector<std::string> truth{"bodies.planet.mass=0.0102", "bodies.planet.velocity.1=1.19",
                                       "impulses.0.delta_v.1=0.052"};
  const Prediction at_truth = predict(scene.path, truth, obs, {"bodies.planet.mass"}, registry);
  std::ostringstream text;
  for (std::size_t i = 0; i < obs.size(); ++i) obs[i].value = at_truth.values[static_cast<Eigen::Index>(i)], obs[i].sigma = 1e-3;
  write_observations(text, obs, {"star", "planet"});
  const TempFile data("data.csv", text.str());
  FitOptions options;
  options.free = {"bodies.planet.mass", "bodies.planet.velocity.1", "impulses.0.delta_v.1"};
  options.tolerance = 1e-6;
  const FitResult r = fit(scene.path, {}, data.path, options, registry);
  ASSERT_TRUE(r.converged) << r.stop;
  const std::vector<double> known{1.19, 0.052, 0.0102};  // in the fit's order of names
  ASSERT_EQ(r.names, (std::vector<std::string>{"bodies.planet.velocity.1", "impulses.0.delta_v.1", "bodies.planet.mass"}));
  for (std::size_t j = 0; j < known.size(); ++j) {
    const auto k = static_cast<Eigen::Index>(j);
    EXPECT_LT(std::abs(r.estimate[k] - known[j]), 1e-4 * r.sigma[k]) << r.names[j];
    EXPECT_NEAR(r.correlation(k, k), 1.0, 1e-12);
  }
  EXPECT_LT(r.chi2, 1e-8);
  EXPECT_LT((r.covariance - r.covariance.transpose()).cwiseAbs().maxCoeff(), 1e-12 * r.covariance.cwiseAbs().maxCoeff());
  EXPECT_LE(r.iterations, 6);
  EXPECT_EQ(r.residuals.size(), obs.size());
  // The JSON names what a reader needs.
  const std::string json = fit_json(r);
  for (const char* field : {"\"estimate\"", "\"sigma\"", "\"correlation\"", "\"covariance\"", "\"chi2\"", "\"residuals\"",
                            "\"degrees_of_freedom\"", "\"converged\": true"})
    EXPECT_NE(json.find(field), std::string::npos) << field;
}

// A tide's Love number and time lag (parameters of the forces beyond the potential, docs/equations.md
// eq. 33.9) from the moon's range and range rate over about four orbits of the tidal spin-down
// example: observations made at k2 = 0.55, Δt = 0.12 and fitted from the scene's 0.5, 0.1. The
// static bulge (∝ k2) and the lag (∝ k2 Δt) move the orbit differently, so both are determined.
TEST(Fit, RecoversATidesLoveNumberAndTimeLagFromTheMoonsRange) {
  PluginRegistry registry = test::bundled_plugins();
  const std::string scene = test::source_path("examples/tidal-spin-down.yaml");
  const std::vector<std::string> span{"run.t_end=36", "run.output_every=0.5"};
  std::vector<Observation> obs;
  for (int k = 1; k <= 36; ++k)
    for (auto kind : {Observable::Kind::range, Observable::Kind::range_rate}) {
      Observation o;
      o.t = k;
      o.observable.kind = kind;
      o.observable.target = 1;
      o.observable.center = 0;
      o.sigma = 1e-4;
      obs.push_back(o);
    }
  std::vector<std::string> truth = span;
  truth.insert(truth.end(), {"forces.0.k2=0.55", "forces.0.time_lag=0.12"});
  const Prediction at_truth = predict(scene, truth, obs, {"forces.0.k2"}, registry);
  for (std::size_t i = 0; i < obs.size(); ++i) obs[i].value = at_truth.values[static_cast<Eigen::Index>(i)];
  std::ostringstream text;
  write_observations(text, obs, {"planet", "moon"});
  const TempFile data("tides.csv", text.str());
  FitOptions options;
  options.free = {"forces.0.k2", "forces.0.time_lag"};
  options.tolerance = 1e-6;
  const FitResult r = fit(scene, span, data.path, options, registry);
  ASSERT_TRUE(r.converged) << r.stop;
  ASSERT_EQ(r.names, options.free);
  EXPECT_NEAR(r.initial[0], 0.5, 0.0);
  EXPECT_NEAR(r.initial[1], 0.1, 0.0);
  const double known[] = {0.55, 0.12};
  for (Eigen::Index k = 0; k < 2; ++k) {
    std::printf("%s: %.12f ± %.2e (known %.2f)\n", r.names[static_cast<std::size_t>(k)].c_str(), r.estimate[k], r.sigma[k],
                known[k]);
    EXPECT_LT(std::abs(r.estimate[k] - known[k]), 1e-4 * r.sigma[k]) << r.names[static_cast<std::size_t>(k)];
  }
  EXPECT_LT(r.chi2, 1e-8);
}

std::string refusal(const std::string& observations, const std::vector<std::string>& free,
                    const std::vector<std::string>& overrides = {}) {
  const TempFile scene("planet.yaml", kPlanet);
  const TempFile data("refused.csv", observations);
  PluginRegistry registry = test::bundled_plugins();
  FitOptions options;
  options.free = free;
  try {
    fit(scene.path, overrides, data.path, options, registry);
  } catch (const SceneError& e) {
    std::string what = e.what();
    const auto at = what.find(data.path.string());
    if (at != std::string::npos) what.replace(at, data.path.string().size(), "DATA");
    return what;
  }
  return "accepted";
}

// What a fit refuses, by name: parameters the observations cannot separate (G and the star's
// mass enter a point-mass orbit only as G M), a parameter they do not see, an observation before
// the run's start, a key that cannot be varied, more parameters than observations.
TEST(Fit, RefusesWhatItCannotDetermine) {
  std::string rows = "t,observable,target,center,value,sigma\n";
  for (double t : {0.5, 1.0, 2.0, 3.0}) rows += std::to_string(t) + ",range,planet,star,1,0.1\n" +
                                                std::to_string(t) + ",position.y,planet,star,0.5,0.1\n";
  EXPECT_NE(refusal(rows, {"G", "bodies.star.mass"}).find("the observations do not determine G, bodies.star.mass separately"),
            std::string::npos) << refusal(rows, {"G", "bodies.star.mass"});
  // Before the impulse (t ≤ 1) only: its Δv is invisible.
  std::string early = "t,observable,target,center,value,sigma\n0.5,range,planet,star,1,0.1\n1.0,range,planet,star,1,0.1\n";
  EXPECT_EQ(refusal(early, {"impulses.0.delta_v.1"}),
            "the observations do not depend on impulses.0.delta_v.1 (its column of the Jacobian is zero): it cannot be "
            "fitted; fix it, or add observations that see it");
  EXPECT_EQ(refusal("t,observable,target,center,value,sigma\n-1,range,planet,star,1,0.1\n", {"bodies.planet.mass"}),
            "DATA:2: t = -1 is before the run starts (t0 = 0)");
  EXPECT_NE(refusal(rows, {"bodies.planet.attitude"}).find("--free 'bodies.planet.attitude'"), std::string::npos)
      << refusal(rows, {"bodies.planet.attitude"});
  EXPECT_NE(refusal(rows, {"bodies.planet.colour"}).find("--free 'bodies.planet.colour'"), std::string::npos);
  EXPECT_EQ(refusal(early, {"bodies.planet.velocity"}),
            "--free: 3 parameters from 2 observations: a fit needs at least as many observations as parameters");
}

}  // namespace

namespace {

// An ensemble from a fit (docs/ensembles.md, "From a fit"): 20000 samples of a fit's keys have
// the fit's estimate as their mean and its covariance as theirs, within 5 of their standard
// errors; a covariance that is not positive definite is refused.
TEST(Fit, AnEnsembleDrawsFromTheFitsCovariance) {
  FitResult r;
  r.names = {"bodies.b.velocity.1", "bodies.b.mass", "impulses.0.delta_v.1"};
  r.bodies = {"a", "b"};
  r.estimate = Eigen::Vector3d(0.17, 4.3e9, -2.7e-3);
  r.initial = r.estimate;
  r.sigma = Eigen::Vector3d(3e-5, 6e7, 2e-6);
  Eigen::Matrix3d rho;
  rho << 1, 0.95, -0.3, 0.95, 1, -0.2, -0.3, -0.2, 1;
  r.correlation = rho;
  r.covariance = r.sigma.asDiagonal() * rho * r.sigma.asDiagonal();
  const TempFile json("fit.json", fit_json(r));
  const std::vector<Variation> vary = variations_from_fit(json.path);
  ASSERT_EQ(vary.size(), 3u);
  EXPECT_EQ(vary[1].key, "bodies.b.mass");
  constexpr int kSamples = 20000;
  Eigen::MatrixXd x(3, kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const auto v = sample_values(vary, 7, static_cast<std::size_t>(i));
    x.col(i) = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  const Eigen::Vector3d mean = x.rowwise().mean();
  const Eigen::MatrixXd centred = x.colwise() - mean;
  const Eigen::Matrix3d cov = centred * centred.transpose() / (kSamples - 1);
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(mean[j], r.estimate[j], 5 * r.sigma[j] / std::sqrt(kSamples)) << j;
    for (int k = 0; k < 3; ++k) {  // a sample covariance's standard error: √((C_jj C_kk + C_jk²)/N)
      const double se = std::sqrt((r.covariance(j, j) * r.covariance(k, k) + r.covariance(j, k) * r.covariance(j, k)) / kSamples);
      EXPECT_NEAR(cov(j, k), r.covariance(j, k), 5 * se) << j << "," << k;
    }
  }
  r.covariance(0, 1) = r.covariance(1, 0) = 2 * r.sigma[0] * r.sigma[1];  // a correlation of 2
  const TempFile bad("bad-fit.json", fit_json(r));
  EXPECT_THROW(variations_from_fit(bad.path), SceneError);
}

}  // namespace
