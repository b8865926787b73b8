#pragma once
// RunRecord: an output file opened read-only to continue its run (noether run --resume). It
// gives the scene the run was made from and reads its complete frames back in blocks of
// bounded size, each frame checked against /checkpoint/checksum before it is handed on
// (docs/reliability.md, "Checksums"); memory does not grow with the number of frames.
#include "io/frame_schema.hpp"
#include "io/h5.hpp"

#include <noether/integrator.hpp>
#include <noether/particles.hpp>
#include <noether/potential.hpp>
#include <noether/state.hpp>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace noether::io {

class RunRecord {
 public:
  // Opens the file and reads what the run was (OutputError: not an output of noether, written
  // by one too old to keep /checkpoint, no complete frame, damaged).
  explicit RunRecord(const std::filesystem::path& file);

  const std::filesystem::path& file() const { return file_; }
  std::string scene_text, scene_path, outcome, resumed;
  std::vector<std::string> overrides;
  bool custom_potential = false;
  bool checksummed = false;  // false: a file from a noether before checksums, read unverified
  std::int64_t frames = 0;   // /frames_complete
  double t_origin = std::numeric_limits<double>::quiet_NaN();  // /checkpoint/t_origin (NaN: frame 0's time)
  std::size_t bodies = 0, rigid = 0, integrator_width = 0;
  // A saved simulation's file (Simulation::save): /checkpoint/summary's numbers and texts by
  // name, verified; empty for a run's output.
  std::vector<std::pair<std::string, std::vector<double>>> summary_numbers;
  std::vector<std::pair<std::string, std::string>> summary_texts;
  bool saved() const { return !summary_numbers.empty(); }
  // A saved simulation's massless particles (/checkpoint/particles), verified; none when absent.
  std::optional<ParticleCheckpoint> particles;
  // /parameters/pair_models as the file's run last wrote them (when it finished, was interrupted
  // or was saved): what a tolerance chose, and whether it was exceeded before the file ended.
  std::vector<PairModel> pair_models;

  // Visits frames [first, first + count) in order, reading at most `block` frames at a time;
  // OutputError names the dataset and frame that does not read or does not match its checksum.
  // Returns false, having stopped between blocks, when *interrupt became non-zero.
  bool read(std::size_t first, std::size_t count,
            const std::function<void(std::size_t, const RecordedFrame&)>& visit,
            const volatile std::sig_atomic_t* interrupt = nullptr, std::size_t block = 4096) const;
  // The bodies' names and masses (/particles/bodies/name, mass), in scene order.
  std::vector<std::string> body_names() const;
  std::vector<double> body_masses() const;
  // The integrator's per-step records (/integrator/<name>), a block of rows at a time.
  void read_step_records(const std::function<void(const StepSeries&)>& visit) const;

 private:
  void read_summary();
  void read_particles();
  void read_pair_models(hid_t parameters);
  [[noreturn]] void damaged(const std::string& what) const;
  std::filesystem::path file_;
  H5Handle h5_;
  std::size_t checksum_columns_ = 0;  // /checkpoint/checksum's columns in this file
};

// The columns of /checkpoint/checksum before /observables/force_balance became column 9.
inline constexpr std::size_t kChecksumColumnsBeforeForces = 9;
// … and before /particles/test_particles/position became column 10.
inline constexpr std::size_t kChecksumColumnsBeforeParticles = 10;
// … and before the run features' fields and the tangent's columns were (a run with run.stm,
// run.sensitivities or run.chaos could not be continued then).
inline constexpr std::size_t kChecksumColumnsBeforeTangent = 11;

}  // namespace noether::io
