// Slow (label `slow`, run by `ctest --preset slow`): the exact mutual potential of the two
// KW4 radar polyhedra at Hou et al.'s initial configuration (≈ 10 s per evaluation on two
// cores), computed with either body's surface, and the series converging to it.
#include "mutual_configurations.hpp"

#include <noether/exact_mutual.hpp>
#include <noether/mutual_series.hpp>

#include <gtest/gtest.h>

#include <cstdio>

using namespace noether;
using namespace noether::test;

TEST(Kw4Exact, SeriesConvergesToTheExactReferenceAndBothSurfacesAgree) {
  const Configuration c = kw4_polyhedra();
  constexpr double G = 6.674e-11;
  ExactMutualOptions options;
  options.tolerance = 1e-12;
  options.surface = ExactMutualOptions::Surface::B;  // Beta's surface in Alpha's field
  ExactMutual beta_surface(G, c.A, c.A->mass, c.B, c.B->mass, options);
  const MutualTerms ref = beta_surface.evaluate(c.R, c.C);
  options.surface = ExactMutualOptions::Surface::A;  // Alpha's surface in Beta's field
  options.tolerance = 1e-9;
  ExactMutual alpha_surface(G, c.A, c.A->mass, c.B, c.B->mass, options);
  const MutualTerms swapped = alpha_surface.evaluate(c.R, c.C);
  const double F = ref.dU_dR.norm(), M = F * c.R.norm();
  std::printf("KW4 exact: U = %.12e J, |F| = %.6e N; Alpha's surface vs Beta's: U %.2e, F %.2e, torques %.2e\n",
              ref.U, F, std::abs(swapped.U - ref.U) / std::abs(ref.U), (swapped.dU_dR - ref.dU_dR).norm() / F,
              std::max((swapped.torque_A - ref.torque_A).norm(), (swapped.torque_B - ref.torque_B).norm()) / M);
  EXPECT_LT(std::abs(swapped.U - ref.U) / std::abs(ref.U), 1e-11);
  EXPECT_LT((swapped.dU_dR - ref.dU_dR).norm() / F, 1e-9);
  EXPECT_LT((swapped.torque_B - ref.torque_B).norm() / M, 1e-8);
  // The order-6 potential behind Hou's energy: −8.29277e9 J.
  EXPECT_NEAR(ref.U, -8.29277e9, 1e5);

  double last[3] = {1, 1, 1};
  std::printf("KW4  N   rel U      rel F      torque\n");
  for (int N = 2; N <= 12; N += 2) {
    MutualSeries s(N);
    const MutualTerms m = s.evaluate(G, c.A->integrals(N), c.B->integrals(N), c.R, c.C);
    const double e[3] = {std::abs(m.U - ref.U) / std::abs(ref.U), (m.dU_dR - ref.dU_dR).norm() / F,
                         std::max((m.torque_A - ref.torque_A).norm(), (m.torque_B - ref.torque_B).norm()) / M};
    std::printf("    %2d  %.3e  %.3e  %.3e\n", N, e[0], e[1], e[2]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(e[k], last[k]) << "N = " << N << " quantity " << k;
      last[k] = e[k];
    }
  }
  EXPECT_LT(last[0], 1e-9);
  EXPECT_LT(last[1], 1e-8);
}

#include "order_selection_check.hpp"

// The exact reference along KW4's orbit: 50 evaluations of ≈ 10 s each on the radar meshes,
// cached in tests/data (CI's budget, docs/reliability.md "CI"); the next test recomputes two.
const char* const kKw4Reference = "tests/data/kw4-polyhedra-exact-orbit.csv";

TEST(Kw4Exact, ToleranceDrivenOrdersMeetTheirTolerance) {
  // KW4 radar meshes along one mutual orbit.
  const auto rows = check_tolerances("examples/kw4-polyhedra.yaml", 62400,
                                     {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}, 16, kKw4Reference);
  int chosen = 0, minimal = 0;
  for (const auto& r : rows) {
    if (r.order < 0) continue;
    ++chosen;
    EXPECT_GE(r.within, 0.95) << r.tolerance;
    minimal += r.minimal;
  }
  EXPECT_GE(chosen, 6);
  std::printf("KW4 polyhedra: %d tolerances chosen, %d minimal\n", chosen, minimal);
}

TEST(Kw4Exact, CachedReferenceIsTheExactModels) {
  // Two of the cached configurations (the first and one half an orbit on) recomputed by the
  // exact model (now its expansion, docs/equations.md §37; the cache is the quadrature's): the
  // cache is what ExactMutual gives, to its tolerance.
  const Scene scene = load_scene(source_path("examples/kw4-polyhedra.yaml"));
  const CachedReference cached = read_reference(source_path(kKw4Reference));
  ASSERT_EQ(cached.configs.size(), 50u);
  ExactMutual exact = exact_reference(scene.system);
  for (const std::size_t k : {std::size_t{0}, std::size_t{25}}) {
    const auto& [R, C] = cached.configs[k];
    const MutualTerms now = exact.evaluate(R, C), then = cached.terms[k];
    EXPECT_NEAR(now.U, then.U, 1e-12 * std::abs(then.U)) << k;
    // The torques against |R||∂U/∂R|, as the tolerance measures them (docs/equations.md (14.7)):
    // Alpha's torque is ~1e-3 of that scale, so its own relative difference is ~1e3 larger.
    const double f = then.dU_dR.norm(), scale = f * R.norm();
    EXPECT_LT((now.dU_dR - then.dU_dR).norm(), 1e-11 * f) << k;
    EXPECT_LT((now.torque_A - then.torque_A).norm(), 1e-12 * scale) << k;
    EXPECT_LT((now.torque_B - then.torque_B).norm(), 1e-12 * scale) << k;
    std::printf("configuration %zu: exact model against the cache: U %.1e, force %.1e, torques %.1e, %.1e of |R||F|\n", k,
                std::abs(now.U - then.U) / std::abs(then.U), (now.dU_dR - then.dU_dR).norm() / f,
                (now.torque_A - then.torque_A).norm() / scale, (now.torque_B - then.torque_B).norm() / scale);
  }
}
