// The verdict on a run (docs/user-guide.md, "Verdict"): what the scene conserves is read off
// the forces at t0, only that is judged, and the thresholds of run.trust decide.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>

using namespace noether;

namespace {

RunSummary run(const std::string& file, std::vector<std::string> overrides, const RunOptions& options = {}) {
  auto registry = test::bundled_plugins();
  return run_scene(load_scene(test::source_path(file), overrides), registry, options);
}

std::string string_attribute(hid_t obj, const char* name) {
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t type = H5Aget_type(a);
  std::string value;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    H5Aread(a, type, &text);
    value = text ? text : "";
    H5free_memory(text);
  } else {
    value.resize(H5Tget_size(type));
    H5Aread(a, type, value.data());
  }
  H5Tclose(type);
  H5Aclose(a);
  return value;
}

}  // namespace

// Mutual gravity conserves both momenta; a central field at the origin conserves only the
// angular momentum about it, one elsewhere neither. The summary reports only what is conserved.
TEST(Verdict, ConservedQuantitiesReadOffTheForces) {
  const RunSummary mutual = run("examples/dumbbells.yaml", {"run.t_end=0.1"});
  EXPECT_TRUE(mutual.conserves_linear_momentum);
  EXPECT_TRUE(mutual.conserves_angular_momentum);
  EXPECT_NE(format_summary(mutual).find("linear momentum"), std::string::npos);

  const RunSummary central = run("examples/kepler-jm.yaml", {"run.t_end=1"});
  EXPECT_FALSE(central.conserves_linear_momentum);
  EXPECT_TRUE(central.conserves_angular_momentum);
  EXPECT_EQ(format_summary(central).find("linear momentum"), std::string::npos);
  EXPECT_EQ(format_summary(central).find("closest approach"), std::string::npos);  // one body

  const RunSummary off_centre = run("examples/kepler-jm.yaml", {"run.t_end=1", "potential.center=[0.3, 0, 0]"});
  EXPECT_FALSE(off_centre.conserves_linear_momentum);
  EXPECT_FALSE(off_centre.conserves_angular_momentum);
  EXPECT_EQ(format_summary(off_centre).find("angular momentum"), std::string::npos);
}

// The relative energy error is judged against |E0|, or T0 when E0 ≈ 0; a threshold crossed
// makes the run untrustworthy, with the reason, also in the output file.
TEST(Verdict, EnergyThresholdAndOutputAttribute) {
  const RunSummary ok = run("examples/dumbbells.yaml", {});
  EXPECT_TRUE(ok.verdict.trustworthy);
  EXPECT_EQ(ok.energy_scale, "|E0|");
  EXPECT_NEAR(ok.max_rel_energy_error, ok.max_abs_energy_error / std::abs(ok.initial.energy), 1e-20);

  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("noether-verdict-" + std::to_string(::getpid()) + ".h5");
  std::filesystem::remove(file);
  RunOptions options;
  options.output = file;
  const RunSummary strict = run("examples/dumbbells.yaml", {"run.trust.energy=1e-8"}, options);
  ASSERT_FALSE(strict.verdict.trustworthy);
  ASSERT_EQ(strict.verdict.reasons.size(), 1u);
  EXPECT_NE(strict.verdict.reasons[0].find("relative energy error 6.12e-07"), std::string::npos)
      << strict.verdict.reasons[0];
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  hid_t work = H5Gopen2(f, "work", H5P_DEFAULT);
  EXPECT_EQ(string_attribute(work, "verdict"), "untrustworthy");
  EXPECT_NE(string_attribute(work, "verdict_reasons").find("relative energy error"), std::string::npos);
  H5Gclose(work);
  H5Fclose(f);
  std::filesystem::remove(file);
}

// A parabolic pair (E0 = 0 to round-off) has no |E0| to compare with: the scale is T0.
TEST(Verdict, ZeroEnergyUsesTheKineticEnergy) {
  // Equal masses, G = 1, separation 2, speeds √½ each: T0 = ½ = G m1 m2 / r.
  const char* text = R"(G: 1
bodies:
  - {name: a, mass: 1, position: [-1, 0, 0], velocity: [0, -0.7071067811865476, 0]}
  - {name: b, mass: 1, position: [1, 0, 0], velocity: [0, 0.7071067811865476, 0]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.001}
run: {t_end: 1, output_every: 0.1}
)";
  auto registry = test::bundled_plugins();
  const RunSummary s = run_scene(parse_scene(text, "parabolic"), registry, {});
  EXPECT_NEAR(s.initial.energy, 0.0, 1e-15);
  EXPECT_EQ(s.energy_scale, "T0");
  EXPECT_NEAR(s.max_rel_energy_error, s.max_abs_energy_error / 0.5, 1e-18);
  EXPECT_TRUE(s.verdict.trustworthy);
}
