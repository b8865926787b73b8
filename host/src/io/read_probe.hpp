#pragma once
// read_probe: reads a file that may be damaged in a child process first. HDF5 trusts parts of a
// file that carry no checksum (the 1.8 format's chunk indices, the global heap that holds
// variable-length strings): a damaged one can make the library crash or loop forever. So every
// read a continuation (`--resume`, Simulation.load) will make is first made, and verified, in
// a forked child with a time limit; the process itself reads the file only once the child has
// read all of it without a crash, a hang or a refusal (docs/reliability.md, "Checksums").
#include <csignal>
#include <filesystem>
#include <functional>

namespace noether::io {

// Runs `read` in a child process. Returns normally when it completed; throws OutputError naming
// `file` when it threw (its message), crashed (the signal) or ran past `seconds` (killed), and
// noether::Error when *interrupt became non-zero meanwhile (the child is killed).
void read_probe(const std::filesystem::path& file, const std::function<void()>& read, double seconds,
                const volatile std::sig_atomic_t* interrupt = nullptr);

// The time a probe of `file` may take: 10 s (or $NOETHER_READ_PROBE_SECONDS), and 10 s more per
// 100 MB (a healthy file reads at several hundred MB/s here).
double read_probe_seconds(const std::filesystem::path& file);

}  // namespace noether::io
