#pragma once
// The acceptance check of tolerance-driven orders (docs/choosing-a-model.md): along a
// simulated orbit of a scene, the order mutual-series chose for each tolerance is compared
// with the exact reference at every configuration. Shared by the default and slow tests.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/exact_mutual.hpp>
#include <noether/order_selection.hpp>
#include <noether/simulation.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace noether::test {

struct ToleranceRow {
  double tolerance = 0;
  int order = -1;          // −1: refused (no order up to max_order met it)
  double within = 0;       // fraction of configurations whose actual error ≤ tolerance
  bool minimal = false;    // order − 2 fails the tolerance somewhere on the orbit (or order < 2)
  double lower_worst = 0;  // the largest actual error of order − 2
  double worst = 0;        // largest actual error seen
};

// 50 configurations (R, C) of bodies 0 and 1 along `t_end` of the scene's own integration.
inline std::vector<std::pair<Vec3, Mat3>> orbit_configurations(const Scene& scene, double t_end, int count) {
  struct Collect final : Observer {
    std::vector<std::pair<Vec3, Mat3>> out;
    void observe(const State& s, const Forces&, bool) override {
      const Mat3 RA = s.R[0], RB = s.R[1];
      out.emplace_back(RA.transpose() * (s.x.col(1) - s.x.col(0)), RA.transpose() * RB);
    }
  } collect;
  auto registry = bundled_plugins();
  auto potential = registry.make_potential("mutual-series", scene.system, parse_params("{order: 4}", "test"));
  auto integrator = registry.make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  State s = scene.initial;
  const double h = scene.integrator.params.at("step").as_double();
  const double every = std::max(h, std::round(t_end / count / h) * h);
  advance(*integrator, *potential, scene.system, s, {every * count, every}, collect);
  collect.out.resize(static_cast<std::size_t>(count));
  return collect.out;
}

inline std::vector<ToleranceRow> check_tolerances(const std::string& scene_file, double t_end,
                                                  const std::vector<double>& tolerances, int max_order) {
  const Scene scene = load_scene(source_path(scene_file));
  const System& sys = scene.system;
  const auto configs = orbit_configurations(scene, t_end, 50);
  const auto &A = sys.body(0).solid, &B = sys.body(1).solid;
  ExactMutualOptions o;
  o.tolerance = 1e-13;
  o.max_level = 9;
  ExactMutual exact(sys.G(), A, A->mass, B, B->mass, o);
  std::vector<MutualTerms> reference;
  for (const auto& [R, C] : configs) reference.push_back(exact.evaluate(R, C));
  const auto TA = A->integrals(max_order + 2), TB = B->integrals(max_order + 2);
  SeriesBank bank;
  auto registry = bundled_plugins();
  std::vector<ToleranceRow> rows;
  std::printf("%s (50 configurations along the orbit)\n  tolerance  order  within  worst error  two orders lower\n",
              scene_file.c_str());
  for (const double tol : tolerances) {
    ToleranceRow row;
    row.tolerance = tol;
    char spec[160];
    std::snprintf(spec, sizeof spec, "{plugin: mutual-series, tolerance: %.17g, max_order: %d}", tol, max_order);
    noether::PotentialEvaluator evaluate(registry.make_potential("mutual-series", sys, parse_params(spec, "test")));
    Forces f;
    f.resize(sys);
    try {
      evaluate(scene.initial, f);  // the choice is made at the initial state
    } catch (const SceneError&) {
      std::printf("  %9.0e  refused: no order up to %d meets it\n", tol, max_order);
      rows.push_back(row);
      continue;
    }
    row.order = evaluate.pair_models().at(0).order;
    int within = 0;
    for (std::size_t k = 0; k < configs.size(); ++k) {
      const auto& [R, C] = configs[k];
      const double e = mutual_error(bank.at(row.order).evaluate(sys.G(), TA, TB, R, C), reference[k], R.norm());
      row.worst = std::max(row.worst, e);
      within += e <= tol;
      if (row.order >= 2)
        row.lower_worst = std::max(row.lower_worst, mutual_error(bank.at(row.order - 2).evaluate(sys.G(), TA, TB, R, C),
                                                                 reference[k], R.norm()));
    }
    row.within = within / 50.0;
    row.minimal = row.order < 2 || row.lower_worst > tol;
    std::printf("  %9.0e  %5d  %5.0f%%  %.2e  %s (order %d: %.2e)\n", tol, row.order, 100 * row.within, row.worst,
                row.minimal ? "minimal" : "not minimal", row.order - 2, row.lower_worst);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace noether::test
