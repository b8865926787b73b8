// The chaos indicators as a run feature (host/src/run/chaos_feature.hpp), with the tangent they
// share with the state-transition matrix and the sensitivities: a run that carries all three,
// saved and loaded or interrupted and resumed, ends bit for bit where the uninterrupted run
// ends — its state, its whole tangent and its indicators (docs/derivatives.md, "Continuing").
#include "test_support.hpp"

#include "run/chaos_feature.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unistd.h>

using namespace noether;

namespace {

bool same_bits(const State& a, const State& b) {
  if (a.x != b.x || a.p != b.p || a.Pi != b.Pi || a.R.size() != b.R.size() || a.tangent != b.tangent) return false;
  for (std::size_t k = 0; k < a.R.size(); ++k)
    if (a.R[k] != b.R[k]) return false;
  return true;
}

bool same_bits(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

void expect_same_indicators(const RunSummary& a, const RunSummary& b, const std::string& what) {
  ASSERT_TRUE(a.chaos && b.chaos) << what;
  EXPECT_TRUE(same_bits(a.chaos_values.megno, b.chaos_values.megno)) << what;
  EXPECT_TRUE(same_bits(a.chaos_values.megno_y, b.chaos_values.megno_y)) << what;
  EXPECT_TRUE(same_bits(a.chaos_values.fli, b.chaos_values.fli)) << what;
  EXPECT_TRUE(same_bits(a.chaos_values.lyapunov, b.chaos_values.lyapunov)) << what;
  EXPECT_EQ(a.chaos_values.t, b.chaos_values.t) << what;
}

std::filesystem::path temporary(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("noether-" + name + "-" + std::to_string(::getpid()) + ".h5");
}

// Every number of a dataset of an output file, in its order.
std::vector<double> dataset(const std::filesystem::path& file, const char* path) {
  std::vector<double> out;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  if (const hid_t d = H5Dopen2(f, path, H5P_DEFAULT); d >= 0) {
    const hid_t space = H5Dget_space(d);
    out.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  return out;
}

// The dumbbells with the STM, the chaos indicators and sensitivities to an initial velocity and
// to a mass (a parameter of the dynamics: its stencil is made again by the continued run).
Scene tangent_scene(const std::string& integrator) {
  return test::dumbbell_scene({"integrator=" + integrator, "run.t_end=0.4", "run.output_every=0.02", "run.stm=true",
                               "run.chaos=true", "run.sensitivities=[bodies.beta.velocity, bodies.alpha.mass]"});
}

const char* const kIntegrators[] = {"{plugin: lgvi, step: 0.002}", "{plugin: lgvi, step: 0.002, order: 4}",
                                    "{plugin: lgvi, step: 0.002, form: lagrangian}",
                                    "{plugin: lgvi, step: 0.002, frame: relative}",
                                    "{plugin: rk, method: rk4, step: 0.002}"};

}  // namespace

// Its fields name every number it keeps; δ0 is a unit vector of the scaled norm (eq. 23.1), and
// a checkpoint restored into a fresh feature gives back the same indicators and δ.
TEST(ChaosFeature, FieldsRestoreTheIndicatorsAndTheDeviation) {
  const Scene scene = test::dumbbell_scene();
  const Eigen::Index N = State::tangent_rows(scene.system);
  detail::ChaosFeature feature(scene.system);
  Eigen::MatrixXd column(N, 1);
  feature.start(scene.initial, column);
  State moved = scene.initial;
  moved.t = 0.5;
  moved.tangent = 3.0 * column;  // ‖δ‖ tripled: ln 3 / 0.5 of growth
  feature.after_step(moved, moved.tangent);
  EXPECT_NEAR(feature.values().lyapunov, std::log(3.0) / 0.5, 1e-14);
  const std::vector<std::string> names = feature.fields();
  ASSERT_EQ(names.size(), 16u + static_cast<std::size_t>(N));
  EXPECT_EQ(names.front(), "chaos.length_scale");
  EXPECT_EQ(names.back(), "chaos.deviation." + std::to_string(N - 1));
  std::vector<double> fields(names.size());
  feature.save(moved.tangent, fields);
  detail::ChaosFeature restored(scene.system);
  Eigen::MatrixXd back(N, 1);
  restored.restore(fields, back);
  EXPECT_EQ(back, moved.tangent);
  EXPECT_EQ(restored.values().lyapunov, feature.values().lyapunov);
  EXPECT_EQ(restored.values().fli, feature.values().fli);
  EXPECT_EQ(detail::ChaosFeature::values_of(fields).megno, feature.values().megno);
  // A further step goes on identically from either.
  moved.t = 0.75;
  moved.tangent *= 2.0;
  feature.after_step(moved, moved.tangent);
  restored.after_step(moved, moved.tangent);
  EXPECT_EQ(restored.values().megno, feature.values().megno);
  EXPECT_THROW(restored.restore(std::vector<double>(5), back), Error);
}

// Saved at a time that is neither a frame nor the end, loaded (a fresh simulation: potential,
// integrator, the mass's stencil made again) and continued: every fixed-step form ends on the
// uninterrupted run's bits — state, STM, δ, sensitivities — and indicators.
TEST(ChaosFeature, SavedAndLoadedContinuesBitwise) {
  PluginRegistry registry = test::bundled_plugins();
  const auto file = temporary("chaos-save");
  for (const char* integrator : kIntegrators) {
    const Scene scene = tangent_scene(integrator);
    Simulation whole(scene, registry);
    whole.integrate(0.4);
    {
      Simulation first(scene, registry);
      first.integrate(0.138);
      first.save(file);
    }
    auto continued = Simulation::load(file, registry);
    EXPECT_EQ(continued->time(), 0.138);
    continued->integrate(0.4);
    EXPECT_TRUE(same_bits(whole.state(), continued->state())) << integrator;
    EXPECT_EQ(whole.state().tangent.cols(), State::tangent_rows(scene.system) + 1 + 3 + 1) << integrator;  // STM, δ, v, m
    expect_same_indicators(whole.summary(), continued->summary(), integrator);
  }
  std::filesystem::remove(file);
}

// An output file closed mid-run (as a killed run's is: its last complete frame) and resumed:
// the continued run ends where the uninterrupted one does, to the bit, its summary's indicators
// are the same, and its file holds the uninterrupted file's frames — the frames read back and
// copied (their STM, sensitivities, indicators and fields) and the frames after.
TEST(ChaosFeature, ResumedRunContinuesBitwise) {
  PluginRegistry registry = test::bundled_plugins();
  const auto whole_file = temporary("chaos-whole"), file = temporary("chaos-resumed");
  for (const char* integrator : kIntegrators) {
    const Scene scene = tangent_scene(integrator);
    RunOptions options;
    options.overwrite = true;
    options.output = whole_file;
    Simulation whole(scene, registry, options);
    whole.integrate(0.4);
    const RunSummary a = whole.finish();
    options.output = file;
    {
      Simulation first(scene, registry, options);
      first.integrate(0.16);  // a frame: where a killed run's file ends
    }
    auto resumed = Simulation::resume(file, registry, RunOptions{});
    EXPECT_EQ(resumed->time(), 0.16) << integrator;
    resumed->integrate(0.4);
    EXPECT_TRUE(same_bits(whole.state(), resumed->state())) << integrator;
    const RunSummary b = resumed->finish();
    expect_same_indicators(a, b, integrator);
    EXPECT_EQ(a.max_abs_energy_error, b.max_abs_energy_error) << integrator;
    EXPECT_EQ(a.frames, b.frames) << integrator;
    resumed.reset();
    for (const char* path : {"/particles/bodies/position/value", "/derivatives/stm/value", "/derivatives/sensitivity/value",
                             "/derivatives/megno/value", "/derivatives/fli/value", "/checkpoint/run_features"}) {
      const std::vector<double> x = dataset(whole_file, path), y = dataset(file, path);
      ASSERT_EQ(x.size(), y.size()) << integrator << " " << path;
      EXPECT_FALSE(x.empty()) << path;
      EXPECT_EQ(0, std::memcmp(x.data(), y.data(), 8 * x.size())) << integrator << " " << path;
    }
  }
  std::filesystem::remove(whole_file);
  std::filesystem::remove(file);
}

// A tangent run loaded with a new output file continues where it stood: the new file's frame 0
// holds the loaded STM, sensitivities and indicators (not a fresh start there), its later frames
// are the uninterrupted run's frames, and the state ends bit for bit where that run's does.
TEST(ChaosFeature, LoadedIntoANewFileContinuesWhereItStood) {
  PluginRegistry registry = test::bundled_plugins();
  const auto whole_file = temporary("chaos-new-whole"), file = temporary("chaos-new-saved"),
             out = temporary("chaos-new-out");
  const Scene scene = tangent_scene("{plugin: lgvi, step: 0.002}");
  RunOptions options;
  options.overwrite = true;
  options.output = whole_file;
  Simulation whole(scene, registry, options);
  whole.integrate(0.4);
  whole.finish();
  State saved;
  {
    Simulation first(scene, registry);
    first.integrate(0.2);
    saved = first.state();
    first.save(file);
  }
  options.output = out;
  auto loaded = Simulation::load(file, registry, options);
  EXPECT_TRUE(same_bits(saved, loaded->state()));
  loaded->integrate(0.4);
  EXPECT_TRUE(same_bits(whole.state(), loaded->state()));
  loaded->finish();
  loaded.reset();
  // Frames 10..20 of the whole run (every 0.02) are the new file's frames 0..10.
  for (const char* path : {"/particles/bodies/position/value", "/derivatives/stm/value", "/derivatives/sensitivity/value",
                           "/derivatives/megno/value", "/derivatives/fli/value", "/checkpoint/run_features"}) {
    const std::vector<double> x = dataset(whole_file, path), y = dataset(out, path);
    ASSERT_EQ(x.size() % 21, 0u) << path;
    ASSERT_EQ(y.size(), 11 * (x.size() / 21)) << path;
    EXPECT_EQ(0, std::memcmp(x.data() + 10 * (x.size() / 21), y.data(), 8 * y.size())) << path;
  }
  for (const auto& f : {whole_file, file, out}) std::filesystem::remove(f);
}
