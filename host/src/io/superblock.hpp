#pragma once
// The end of allocation recorded in an HDF5 file's superblock, rewritten in place so that a kill
// in the middle of an HDF5 flush leaves a file whose metadata lies inside the recorded end
// (docs/reliability.md, "Kills").
//
// HDF5 writes the superblock last in a flush (its ring is flushed after every other piece of
// metadata), so until then the file on disk records the end of allocation of the previous flush
// while the metadata already written may point past it ("addr overflow" when the file is read).
// noether writes the 1.8 file format: a version 2 superblock, whose layout (HDF5 File Format
// Specification, "Version 2 Superblock", 8-byte offsets) is
//   0 signature (8) · 8 version · 9 size of offsets · 10 size of lengths · 11 flags ·
//   12 base address · 20 superblock extension address · 28 end-of-file address ·
//   36 root group object header address · 44 checksum (Jenkins' lookup3 of bytes 0–43).
#include <algorithm>
#include <cstdint>
#include <cstring>

#include <unistd.h>

namespace noether::io {

// Bob Jenkins' lookup3 hash ("hashlittle", 2006, public domain), read byte by byte: the checksum
// of HDF5's metadata (H5_checksum_lookup3 with initial value 0).
inline std::uint32_t lookup3(const unsigned char* k, std::size_t length, std::uint32_t initval = 0) {
  auto rot = [](std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); };
  std::uint32_t a, b, c;
  a = b = c = 0xdeadbeefu + static_cast<std::uint32_t>(length) + initval;
  auto word = [&](std::size_t i, std::size_t n) {
    std::uint32_t w = 0;
    for (std::size_t j = 0; j < n; ++j) w += static_cast<std::uint32_t>(k[i + j]) << (8 * j);
    return w;
  };
  while (length > 12) {
    a += word(0, 4);
    b += word(4, 4);
    c += word(8, 4);
    a -= c; a ^= rot(c, 4);  c += b;  // mix(a, b, c)
    b -= a; b ^= rot(a, 6);  a += c;
    c -= b; c ^= rot(b, 8);  b += a;
    a -= c; a ^= rot(c, 16); c += b;
    b -= a; b ^= rot(a, 19); a += c;
    c -= b; c ^= rot(b, 4);  b += a;
    length -= 12;
    k += 12;
  }
  if (length == 0) return c;
  a += word(0, std::min<std::size_t>(length, 4));
  if (length > 4) b += word(4, std::min<std::size_t>(length - 4, 4));
  if (length > 8) c += word(8, length - 8);
  c ^= b; c -= rot(b, 14);  // final(a, b, c)
  a ^= c; a -= rot(c, 11);
  b ^= a; b -= rot(a, 25);
  c ^= b; c -= rot(b, 16);
  a ^= c; a -= rot(c, 4);
  b ^= a; b -= rot(a, 14);
  c ^= b; c -= rot(b, 24);
  return c;
}

// Rewrites the end-of-file address of the version 2 or 3 superblock at the start of the file
// open as `fd` to `end`, with its checksum, in one write of 48 bytes. Returns false, changing
// nothing, unless the superblock is one it recognises (signature, version, 8-byte offsets, base
// address 0, a checksum that verifies).
inline bool record_end_of_allocation(int fd, std::uint64_t end) {
  constexpr std::size_t size = 48, eof_at = 28, checksum_at = 44;
  unsigned char sb[size];
  if (::pread(fd, sb, size, 0) != static_cast<ssize_t>(size)) return false;
  static const unsigned char signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  if (std::memcmp(sb, signature, 8) != 0 || (sb[8] != 2 && sb[8] != 3) || sb[9] != 8) return false;
  auto little_endian = [&](std::size_t at, std::size_t bytes) {  // HDF5 stores integers little-endian
    std::uint64_t v = 0;
    for (std::size_t j = bytes; j-- > 0;) v = (v << 8) | sb[at + j];
    return v;
  };
  const auto stored = static_cast<std::uint32_t>(little_endian(checksum_at, 4));
  if (little_endian(12, 8) != 0 || lookup3(sb, checksum_at) != stored) return false;
  if (little_endian(eof_at, 8) == end) return true;
  for (std::size_t j = 0; j < 8; ++j) sb[eof_at + j] = static_cast<unsigned char>(end >> (8 * j));
  const std::uint32_t sum = lookup3(sb, checksum_at);
  for (std::size_t j = 0; j < 4; ++j) sb[checksum_at + j] = static_cast<unsigned char>(sum >> (8 * j));
  return ::pwrite(fd, sb, size, 0) == static_cast<ssize_t>(size);
}

}  // namespace noether::io
