#pragma once
// Lyapunov orbits (docs/equations.md §19.3): the relative periodic orbits that grow out of an
// oscillating normal mode of a relative equilibrium — a librating secondary, a tilt, an
// epicycle — on any integrator's map. The guess is the equilibrium displaced along the mode's
// eigenvector by `amplitude` (its largest component in the equilibrium chart's scaled
// coordinates: radians for a libration or a tilt) with T = 2π/ν and α = ωT; Newton then solves
// (19.1) for (s, α, T), with L·k̂ and the displacement along the mode held. Lyapunov (1892);
// for the full two-body problem, Scheeres (2009) §5 and Bellerose & Scheeres (2008). Newton's
// Jacobian comes from the integrator's tangent map where it carries one (T's column differenced),
// else (or with `differenced`) from central differences of the map.
#include <noether/relative_equilibrium.hpp>
#include <noether/relative_periodic_orbit.hpp>

namespace noether {

// With a fixed-step integrator (a `step` key) the number of steps per period is held and the
// step follows T, so the orbit found is one of the discrete map with the step T/N it reports.
struct LyapunovOrbit {
  RelativePeriodicOrbit orbit;
  double linear_period = 0;  // 2π/ν of the mode
  double step = 0;           // the fixed step T/N the orbit belongs to (0 for adaptive integrators)
  long steps = 0;            // N
};

LyapunovOrbit lyapunov_orbit(const FullBodyModel& model, const PluginConfig& integrator, const RelativeEquilibrium& eq,
                             const NormalMode& mode, double amplitude, double tolerance = 1e-12,
                             int max_iterations = 30, bool differenced = false);

// The integrator the orbit belongs to: `integrator` with the step T/N for a fixed-step method.
PluginConfig lyapunov_integrator(const PluginConfig& integrator, const LyapunovOrbit& orbit);

// The orbit's multipliers (19.2). On a map that conserves E the energy and the flow are projected
// out; on one that does not (the LGVI conserves a modified energy) the family and the phase leave
// a pair at 1 — a Jordan block, split by the differencing into 1 ± O(√ε) — which is set apart as
// `family` (when within 1e-3 of 1) and the verdict is taken over the others.
OrbitMultipliers lyapunov_multipliers(const FullBodyModel& model, const PluginConfig& integrator,
                                      const LyapunovOrbit& orbit, double tolerance = 1e-6);

}  // namespace noether
