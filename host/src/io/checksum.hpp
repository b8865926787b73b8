#pragma once
// checksum64: a 64-bit checksum of bytes, for finding damage in files noether reads back
// (docs/reliability.md, "Checksums"). Not cryptographic: it detects flipped bits, zeroed or
// shifted blocks and data moved between frames (the seed is the frame), not deliberate forgery.
// Word-wise multiply-rotate mixing with MurmurHash3's 64-bit finaliser (Appleby 2011); a frame of
// a few hundred bytes costs well under a microsecond.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace noether::io {

inline std::uint64_t checksum_mix(std::uint64_t h) {  // MurmurHash3 fmix64
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}

inline std::uint64_t checksum64(const void* data, std::size_t bytes, std::uint64_t seed = 0) {
  constexpr std::uint64_t k1 = 0x9e3779b97f4a7c15ULL, k2 = 0x87c37b91114253d5ULL;
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = checksum_mix(seed ^ k1) ^ (bytes * k2);
  for (; bytes >= 8; bytes -= 8, p += 8) {
    std::uint64_t w;
    std::memcpy(&w, p, 8);
    h ^= w * k1;
    h = ((h << 31) | (h >> 33)) * k2;
  }
  std::uint64_t tail = 0;
  if (bytes > 0) std::memcpy(&tail, p, bytes);  // (p may be null when nothing is left)
  h ^= tail * k1 + bytes;
  return checksum_mix(h);
}

// Several texts, each followed by its length (so that moving a byte between them changes it).
inline std::uint64_t checksum_of_texts(std::initializer_list<const std::string*> texts) {
  std::uint64_t h = 0;
  for (const std::string* t : texts) h = checksum64(t->data(), t->size(), h ^ t->size());
  return h;
}

// What a continued run rebuilds its scene from: /parameters' scene text, scene path and
// overrides, and whether its potential was given in code.
inline std::uint64_t scene_checksum(const std::string& text, const std::string& path, const std::string& overrides,
                                    bool custom_potential) {
  const std::string custom = custom_potential ? "1" : "0";
  return checksum_of_texts({&text, &path, &overrides, &custom});
}

// /checkpoint/particles: its header (time and counters) and its rows.
inline std::uint64_t particle_checksum(const std::vector<double>& header, const std::vector<double>& rows) {
  return checksum64(rows.data(), rows.size() * sizeof(double), checksum64(header.data(), header.size() * sizeof(double)));
}

// /checkpoint/summary's named numbers and texts, names included, in order.
// Order does not matter (HDF5 lists attributes by name).
inline std::uint64_t summary_checksum(std::vector<std::pair<std::string, std::vector<double>>> numbers,
                                      std::vector<std::pair<std::string, std::string>> texts) {
  std::sort(numbers.begin(), numbers.end());
  std::sort(texts.begin(), texts.end());
  std::uint64_t h = 0;
  for (const auto& [name, values] : numbers) {
    h = checksum64(name.data(), name.size(), h ^ name.size());
    h = checksum64(values.data(), values.size() * sizeof(double), h ^ values.size());
  }
  for (const auto& [name, text] : texts) h = checksum_of_texts({&name, &text}) ^ checksum_mix(h);
  return h;
}

}  // namespace noether::io
