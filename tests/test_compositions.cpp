// The LGVI's compositions (plugins/integrators/lgvi/compositions.hpp): each converges at its
// order, measured as the slope of the final-state differences of successive step halvings
// (self-convergence: no reference solution's error in the way), on the two dumbbells.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace noether;

namespace {

Eigen::Matrix3Xd final_positions(PluginRegistry& registry, const std::string& integrator, double t_end) {
  const RunSummary s = run_scene(test::dumbbell_scene({"integrator=" + integrator, "run.t_end=" + std::to_string(t_end),
                                                       "run.output_every=" + std::to_string(t_end)}),
                                 registry, {});
  return s.final_state.x;
}

struct Case {
  int order;
  const char* composition;
  double h0;  // the largest step of the four halvings
};

}  // namespace

TEST(Compositions, EachConvergesAtItsOrder) {
  auto registry = test::bundled_plugins();
  const Case cases[] = {{4, "yoshida", 2e-2}, {4, "suzuki", 2e-2}, {4, "mclachlan", 2e-2},
                        {6, "yoshida", 4e-2}, {6, "kahan-li", 4e-2}};
  const double t_end = 4.0;
  for (const Case& c : cases) {
    std::vector<Eigen::Matrix3Xd> x;
    for (int k = 0; k < 4; ++k) {
      const double h = c.h0 / (1 << k);
      char spec[160];
      std::snprintf(spec, sizeof spec, "{plugin: lgvi, step: %.17g, order: %d, composition: %s}", h, c.order,
                    c.composition);
      x.push_back(final_positions(registry, spec, t_end));
    }
    std::vector<double> d;  // ‖x(h/2^k) − x(h/2^{k+1})‖ ∝ (h/2^k)^p
    for (int k = 0; k + 1 < 4; ++k) d.push_back((x[k] - x[k + 1]).cwiseAbs().maxCoeff());
    for (std::size_t k = 0; k + 1 < d.size(); ++k) {
      const double slope = std::log2(d[k] / d[k + 1]);
      std::printf("order %d %-9s h0/%d: difference %.3e, slope %.2f\n", c.order, c.composition, 1 << k, d[k], slope);
      EXPECT_NEAR(slope, c.order, 0.35) << c.composition << " order " << c.order << " at h0/" << (1 << k);
    }
  }
}
