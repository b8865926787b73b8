#pragma once
// What halving the particles' step changes (particles.check; docs/user-guide.md, "Particles" and
// "Verdict"): ParticleSwarm fills it, the verdict judges it.
#include <cstddef>
#include <cstdint>

namespace noether {

// The step-halving check of the particles (docs/user-guide.md, "Particles", "Verdict"): the
// `particles.check` particles spread evenly through the list are carried a second time, beside
// the others, at half the Verlet step (the same bodies, interpolated the same way), and compared.
struct ParticleCheck {
  std::size_t checked = 0;       // particles carried twice
  std::size_t fates_differ = 0;  // whose fate differs: in flight, landed (on which body), escaped
  // Of those in flight both times: the largest |x_h − x_{h/2}| / |x_h − c| (c: `around`, or the
  // bodies' barycentre), where the run stands.
  double position = 0.0;
  // Of those landed on the same body both times: the largest distance between the two landing
  // points over the body's bounding radius, and between the two landing times.
  double landing_point = 0.0, landing_time = 0.0;
  std::int64_t steps = 0;  // their Verlet steps at half the step
};

}  // namespace noether
