#pragma once
// The series a continued run reads back from an output file (noether run --resume), in the order
// of the columns of /checkpoint/checksum: column c of frame k is checksum64 of frame k of series
// c, seeded with k (docs/user-guide.md, "Output": /checkpoint). The writer (output.cpp) and the
// reader (run_record.cpp) both take the list from here.
#include <cstddef>

namespace noether::io {

struct CheckpointedSeries {
  const char* path;
  bool rigid_only;  // present when the scene has rigid bodies
  bool optional;    // present when the integrator has variables of its own
};

inline constexpr CheckpointedSeries kCheckpointed[] = {
    {"/particles/bodies/position/time", false, false},          // t
    {"/particles/bodies/position/value", false, false},         // x [body][xyz]
    {"/checkpoint/linear_momentum", false, false},              // γ [body][xyz]
    {"/checkpoint/attitude", true, false},                      // R [rigid][row][column]
    {"/particles/bodies/angular_momentum/value", true, false},  // Π [rigid][xyz]
    {"/observables/potential_energy/value", false, false},      // U
    {"/checkpoint/work", false, false},                         // int64 [5]
    {"/checkpoint/wall_time", false, false},                    // s
    {"/checkpoint/integrator", false, true},                    // Integrator::checkpoint()
};
inline constexpr std::size_t kCheckpointedCount = sizeof(kCheckpointed) / sizeof(kCheckpointed[0]);
enum CheckpointColumn : std::size_t { kTime, kPosition, kMomentum, kAttitude, kSpin, kPotential, kWork, kWall, kIntegrator };

inline constexpr const char* kChecksumPath = "/checkpoint/checksum";

}  // namespace noether::io
