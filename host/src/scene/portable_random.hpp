#pragma once
// Random numbers that depend on (seed, index, stream) alone — not on the order of the draws, the
// thread or the platform — so that sample or particle i is the same whatever else is drawn
// (ensembles, docs/ensembles.md; ejecta, docs/user-guide.md "Particles").
#include <cstdint>

namespace noether {

// splitmix64 (Steele, Lea & Flood 2014): a stateless, portable 64-bit mixing function.
inline std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A uniform double in (0, 1) from (seed, index, stream): 53 bits, never 0 or 1.
inline double uniform01(std::uint64_t seed, std::uint64_t index, std::uint64_t stream) {
  const std::uint64_t bits = mix(mix(mix(seed) ^ index) ^ (stream * 0x632be59bd9b4e019ULL));
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1p-53;
}

}  // namespace noether
