// Real shapes in motion (docs/numerical-results.md, "Real shapes"): the KW4 energy of Hou
// et al. 2017, the LGVI on SO(3) and with bounded energy over 100 mutual orbits in both
// frames, its second order against rk/cvode, and the Didymos example against GUBAS-RS.
#include "test_support.hpp"

#include <noether/diagnostics.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

namespace {

struct Track final : Observer {
  const System* system = nullptr;
  std::vector<double> t, E, orth;
  State last;
  void observe(const State& s, const Forces& f, bool) override {
    const Diagnostics d = diagnose(*system, s, f.U);
    t.push_back(s.t);
    E.push_back(d.energy);
    orth.push_back(d.orthogonality_error);
    last = s;
  }
  double max_rel_dE(std::size_t from, std::size_t to) const {
    double m = 0;
    for (std::size_t k = from; k < to; ++k) m = std::max(m, std::abs(E[k] - E[0]) / std::abs(E[0]));
    return m;
  }
  double drift() const {  // least-squares slope of (E − E0)/|E0| times the duration
    const double n = static_cast<double>(t.size());
    double st = 0, se = 0, stt = 0, ste = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double e = (E[k] - E[0]) / std::abs(E[0]);
      st += t[k], se += e, stt += t[k] * t[k], ste += t[k] * e;
    }
    return (n * ste - st * se) / (n * stt - st * st) * (t.back() - t.front());
  }
};

Track run(const std::string& scene_file, const std::vector<std::string>& overrides) {
  const Scene scene = load_scene(test::source_path(scene_file), overrides);
  auto registry = test::bundled_plugins();
  auto potential = make_scene_potential(scene, registry);
  auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential,
                                             scene.integrator.params);
  Track track;
  track.system = &scene.system;
  State s = scene.initial;
  advance(*integrator, *potential, scene.system, s, {scene.run.t_end, scene.run.output_every}, track);
  return track;
}

// B's centre of mass relative to A's, in A's frame.
Vec3 relative_position(const State& s) { return s.R[0].transpose() * (s.x.col(1) - s.x.col(0)); }

constexpr double kKw4Orbit = 62400.0;  // the mutual period, s (a = 2540.5 m)

}  // namespace

TEST(ShapeDynamics, Kw4EnergyAtHousInitialConditions) {
  // Hou et al. 2017 §5.2: E ≈ 8.7670e10 J at order 6; the decomposition of the research
  // notes gives 8.76695e10 J (K_rot,A 9.18512e10, K_orb 4.09220e9, U −8.29277e9).
  const Scene scene = load_scene(test::source_path("examples/kw4-polyhedra.yaml"), {"potential.order=6"});
  auto registry = test::bundled_plugins();
  auto potential = make_scene_potential(scene, registry);
  Forces f;
  f.resize(scene.system);
  potential->evaluate(scene.initial, f);
  const Diagnostics d = diagnose(scene.system, scene.initial, f.U);
  EXPECT_NEAR(d.energy, 8.76695e10, 1e6);
  EXPECT_NEAR(f.U, -8.29277e9, 1e5);
  EXPECT_NEAR(d.kinetic_translational, 4.09220e9, 1e5);
}

TEST(ShapeDynamics, Kw4LgviStaysOnSO3WithBoundedEnergyForAHundredOrbits) {
  for (const std::string frame : {"inertial", "relative"}) {
    const Track track = run("examples/kw4-polyhedra.yaml",
                            {"integrator.frame=" + frame, "run.t_end=" + std::to_string(100 * kKw4Orbit),
                             "run.output_every=" + std::to_string(kKw4Orbit / 20)});
    const std::size_t n = track.t.size(), tenth = n / 10;
    ASSERT_GE(track.t.back(), 100 * kKw4Orbit - 1);
    EXPECT_LE(*std::max_element(track.orth.begin(), track.orth.end()), 1e-12) << frame;
    // Bounded: no secular drift, the last tenth no worse than the first.
    const double worst = track.max_rel_dE(0, n);
    EXPECT_LT(worst, 1e-6) << frame;
    EXPECT_LT(std::abs(track.drift()), 0.05 * worst) << frame;
    EXPECT_LT(track.max_rel_dE(n - tenth, n), 1.5 * track.max_rel_dE(0, tenth)) << frame;
    std::printf("KW4 %s frame, 100 orbits: max |dE/E0| %.3e, fitted drift %.3e, max orth %.3e\n",
                frame.c_str(), worst, track.drift(), *std::max_element(track.orth.begin(), track.orth.end()));
  }
}

TEST(ShapeDynamics, Kw4LgviIsSecondOrderAgainstRkAndCvode) {
  // Over the first mutual orbit: the LGVI's final relative position error against a tight
  // dopri5 reference falls 4× per halving of h; cvode agrees with the reference; the
  // relative-frame LGVI matches the inertial one far below its own error.
  const std::vector<std::string> base = {"run.t_end=" + std::to_string(kKw4Orbit), "run.output_every=" + std::to_string(kKw4Orbit)};
  auto with = [&](const std::string& integrator) {
    auto o = base;
    o.push_back("integrator=" + integrator);
    return relative_position(run("examples/kw4-polyhedra.yaml", o).last);
  };
  const Vec3 ref = with("{plugin: rk, method: dopri5, rtol: 1.0e-12, atol: 1.0e-9}");
  const Vec3 cvode = with("{plugin: cvode, method: adams, rtol: 1.0e-11, atol: 1.0e-8}");
  const double e120 = (with("{plugin: lgvi, step: 120}") - ref).norm();
  const double e60 = (with("{plugin: lgvi, step: 60}") - ref).norm();
  const double e30 = (with("{plugin: lgvi, step: 30}") - ref).norm();
  const double e60rel = (with("{plugin: lgvi, step: 60, frame: relative}") - with("{plugin: lgvi, step: 60}")).norm();
  std::printf("KW4 one orbit: |Δr| lgvi h=120 %.3e, h=60 %.3e, h=30 %.3e m; cvode %.3e m; relative vs inertial %.3e m\n",
              e120, e60, e30, (cvode - ref).norm(), e60rel);
  EXPECT_NEAR(std::log2(e120 / e60), 2.0, 0.1);
  EXPECT_NEAR(std::log2(e60 / e30), 2.0, 0.1);
  EXPECT_LT((cvode - ref).norm(), 0.01 * e30);
  EXPECT_LT(e60rel, 1e-3 * e60);
}

TEST(ShapeDynamics, DidymosMatchesTheGubasRsExample) {
  // GUBAS-RS example/output_x (LGVI, h = 30 s, order 4) at t = 7200 s, in Didymos' frame:
  // r = (−0.244896377, 1.17561112, 7.78854114e-5) km, printed to 9 digits. An independent
  // implementation of the same model (order 4, Didymos_A polyhedron + ellipsoid) and the same
  // method and step: measured agreement 3.0e-6 m, at the digits GUBAS-RS printed.
  const Track track = run("examples/didymos.yaml", {"run.t_end=7200"});
  const Vec3 r = relative_position(track.last);
  const Vec3 gubas(-244.896377, 1175.61112, 0.0778854114);
  std::printf("Didymos at 7200 s: r = (%.6f, %.6f, %.6f) m, |r − GUBAS-RS| = %.3e m\n", r.x(), r.y(), r.z(),
              (r - gubas).norm());
  EXPECT_LT((r - gubas).norm(), 2e-5);
}
