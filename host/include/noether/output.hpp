#pragma once
// Output: the HDF5 writer (layout after H5MD, docs/user-guide.md "Output"). Frames are buffered
// and written in blocks into series allocated up front (on a thread of their own while the run
// goes on, when HDF5 is thread-safe); after each block the file is flushed and then
// /frames_complete advanced, so a run killed at any moment leaves a readable file whose
// series all have one length and whose first /frames_complete frames are complete. Every frame
// of what a continued run reads back is checksummed (/checkpoint/checksum).
#include <noether/diagnostics.hpp>
#include <noether/integrator.hpp>
#include <noether/potential.hpp>
#include <noether/scene.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace noether {

class ParticleSwarm;

// A series of the output file that a run feature fills (the chaos indicators, the particles'
// positions: rows of the frame schema, io/frame_schema.cpp): its name there and the shape of
// one frame.
struct FeatureSeries {
  std::string name;
  std::vector<std::size_t> shape;
  std::size_t size() const;  // the numbers in one frame
};

struct OutputOptions {
  std::size_t block_frames = 1024; // write a block at least every this many frames
  double block_seconds = 1.0;      // and at least this often in wall time
  // Write each block on a thread of its own while the run goes on (used only when the HDF5
  // library is thread-safe, as Debian's is); false: in line, as the frames arrive.
  bool background_blocks = true;
  // Frames the run will write at most (0: unknown); the series are allocated for them up front,
  // within `preallocate_bytes`, so that a kill at any moment leaves a consistent file.
  std::uint64_t expected_frames = 0;
  double preallocate_bytes = 256.0 * 1024 * 1024;
  bool overwrite = false;          // replace an existing file (--force); never a link or an input
  std::vector<std::filesystem::path> inputs;  // files the run reads (the scene): never overwritten
  std::size_t checkpoint_width = 0;  // Integrator::checkpoint()'s size: /checkpoint/integrator [frame][width]
  // State::tangent's columns: the state-transition matrix's first (/derivatives/stm; 0: run.stm
  // off), then one per sensitivity (/derivatives/sensitivity, named by /derivatives/parameters).
  std::size_t stm_columns = 0;
  std::vector<std::string> sensitivity_names;
  // The run features' checkpointed fields, one name per number: /checkpoint/run_features
  // [frame][field] and its attribute `fields` (none: no such series).
  std::vector<std::string> feature_fields;
  std::vector<std::string> force_names;  // the scene's forces: /observables/force_balance, /parameters/forces
  // The series the run features fill, in the order write_frame takes their values.
  std::vector<FeatureSeries> feature_series;
  bool custom_potential = false;     // the run's potential was given in code (Python), not by the scene
  // Build the file under its hidden name until publish() (a continued run: the old file stays
  // as it is until its frames have been read back, verified and copied).
  bool defer_publish = false;
  std::string resumed;  // /checkpoint/resumed: the continuations so far, one line each
  // /checkpoint/t_origin: the time the run's step grid starts from (a fixed-step method's
  // t = t_origin + n h); NaN: frame 0's time.
  double t_origin = std::numeric_limits<double>::quiet_NaN();
};

class H5Writer {
 public:
  H5Writer(const std::filesystem::path& file, const Scene& scene, OutputOptions options = {});
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  // One frame: the state, its diagnostics, and the work and wall time spent to reach it (the
  // checkpoint a continued run starts from); the run features' series there (the numbers of
  // options.feature_series, one after another) and their fields (options.feature_fields').
  void write_frame(const State& state, const Diagnostics& diagnostics, const WorkCounters& work,
                   double wall_seconds, std::int64_t interpolated_frames = 0,
                   const std::vector<double>& integrator_checkpoint = {}, std::span<const double> series = {},
                   std::span<const double> features = {});
  // Moves the file from its hidden name to its path (done by the constructor unless
  // options.defer_publish); until then the path holds what it held before.
  void publish();
  // Writes buffered frames and flushes the file.
  void flush();
  // Writes /work and the run's outcome ("completed" or the error message), then closes.
  // /parameters/pair_models/<a>–<b>: the model chosen for each pair (rewritten when called
  // again, e.g. at the end of the run with what the run saw).
  void write_pair_models(const std::vector<PairModel>& models);
  // /test_particles: the scene's massless particles, where they started and what became of them.
  void write_particles(const ParticleSwarm& swarm, const Scene& scene);
  void finish(const WorkCounters& work, double wall_seconds, const std::string& outcome);
  // The run's verdict, written with /work by finish().
  void set_verdict(const std::string& verdict, const std::string& reasons, double relative_energy_error,
                   const std::string& energy_scale);
  // /checkpoint/summary: named numbers and texts a saved simulation continues its summary from
  // (Simulation::save), checksummed together (attribute checksum).
  void write_summary_values(const std::vector<std::pair<std::string, std::vector<double>>>& numbers,
                            const std::vector<std::pair<std::string, std::string>>& texts);
  // /checkpoint/particles: the massless particles where they stand at frame `frame`, checksummed
  // (Simulation::save; a continued run's first frame), written in place of the last.
  void write_particle_checkpoint(const ParticleCheckpoint& particles, std::int64_t frame);
  // The particles where they stand when a block of frames is written, if they stand at its last
  // frame's time `t` (a step's end; none between an adaptive method's steps): written with the
  // block, after /frames_complete, so that a continued run finds them at its last frame.
  using ParticleSource = std::function<std::optional<ParticleCheckpoint>(double t)>;
  void checkpoint_particles(ParticleSource source);
  // Appends an integrator's per-step records to /integrator/<name> (created on first use).
  void append_step_series(const std::vector<StepSeries>& records);
  std::size_t frames_written() const { return frames_written_; }

 private:
  struct Impl;
  void create_layout(const Scene& scene);  // every group, attribute and series, then a flush
  void create_series(const Scene& scene);  // the frame schema's series (io/frame_schema.hpp)
  void abandon();  // closes the file; removes it if it was never published
  // The buffered frames become the block to write (and the buffers take the next frames).
  void hand_over();
  // Waits for the block written in the background, if any (rethrowing its error): every call
  // that touches the file makes this first, so the file has one writer at a time.
  void settle();
  std::unique_ptr<Impl> impl_;
  std::size_t frames_written_ = 0;
};

}  // namespace noether
