#pragma once
// Output: the HDF5 writer (layout after H5MD, docs/user-guide.md "Output"). Frames are buffered
// and written in blocks into series allocated up front; after each block the file is flushed and
// then /frames_complete advanced, so a run killed at any moment leaves a readable file whose
// series all have one length and whose first /frames_complete frames are complete.
#include <noether/diagnostics.hpp>
#include <noether/integrator.hpp>
#include <noether/potential.hpp>
#include <noether/scene.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace noether {

struct OutputOptions {
  std::size_t block_frames = 256;  // write a block at least every this many frames
  double block_seconds = 1.0;      // and at least this often in wall time
  // Frames the run will write at most (0: unknown); the series are allocated for them up front,
  // within `preallocate_bytes`, so that a kill at any moment leaves a consistent file.
  std::uint64_t expected_frames = 0;
  double preallocate_bytes = 256.0 * 1024 * 1024;
  bool overwrite = false;          // replace an existing file (--force); never a link or an input
  std::vector<std::filesystem::path> inputs;  // files the run reads (the scene): never overwritten
  std::size_t checkpoint_width = 0;
  bool custom_potential = false;  // the run's potential was given in code (Python), not by the scene  // Integrator::checkpoint()'s size: /checkpoint/integrator [frame][width]
};

// A run as its output file holds it, for continuing it (noether run --resume): the scene as
// given, and the exact state of every complete frame (/checkpoint keeps γ and R bit for bit;
// the velocity and quaternion series are derived from them and are not exact).
struct RecordedRun {
  std::filesystem::path file;
  std::string scene_text, scene_path;        // the scene file's text and where it was
  std::vector<std::string> overrides;
  std::string outcome;                       // /work/outcome, empty when the run was killed
  bool custom_potential = false;             // its potential was given in code, not by the scene
  std::int64_t frames = 0;                   // /frames_complete
  std::size_t bodies = 0, rigid = 0;
  std::vector<double> time, x, p, R, Pi, U;  // [frame][...] row-major, as in the file
  std::vector<std::int64_t> work;            // [frame][5]: steps, evaluations, Newton, rejected,
                                             // frames interpolated so far
  std::vector<double> wall_seconds;          // [frame]
  std::vector<double> integrator;            // [frame][integrator_width]: Integrator::checkpoint()
  std::size_t integrator_width = 0;
  State state(std::size_t frame) const;
  std::vector<double> integrator_at(std::size_t frame) const;
  WorkCounters work_at(std::size_t frame) const;
  std::int64_t interpolated_at(std::size_t frame) const;
};

// Reads an output file for --resume; OutputError names what is missing (a file from an older
// noether without /checkpoint, a run with no complete frame).
RecordedRun read_recorded_run(const std::filesystem::path& file);

class H5Writer {
 public:
  H5Writer(const std::filesystem::path& file, const Scene& scene, OutputOptions options = {});
  // Continues the output of `run` (locked, as a new file is): the frames after its first
  // `run.frames` are overwritten as the continued run writes; /work is written again at the end.
  // The scene's overrides, t_end and scene_as_run are recorded again (--t-end extends a run).
  H5Writer(const RecordedRun& run, const Scene& scene, OutputOptions options = {});
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  // One frame: the state, its diagnostics, and the work and wall time spent to reach it (the
  // checkpoint a continued run starts from).
  void write_frame(const State& state, const Diagnostics& diagnostics, const WorkCounters& work,
                   double wall_seconds, std::int64_t interpolated_frames = 0,
                   const std::vector<double>& integrator_checkpoint = {});
  // Writes buffered frames and flushes the file.
  void flush();
  // Writes /work and the run's outcome ("completed" or the error message), then closes.
  // /parameters/pair_models/<a>–<b>: the model chosen for each pair (rewritten when called
  // again, e.g. at the end of the run with what the run saw).
  void write_pair_models(const std::vector<PairModel>& models);
  void finish(const WorkCounters& work, double wall_seconds, const std::string& outcome);
  // The run's verdict, written with /work by finish().
  void set_verdict(const std::string& verdict, const std::string& reasons, double relative_energy_error,
                   const std::string& energy_scale);
  // Appends an integrator's per-step records to /integrator/<name> (created on first use).
  void append_step_series(const std::vector<StepSeries>& records);
  std::size_t frames_written() const { return frames_written_; }

 private:
  struct Impl;
  void create_layout(const Scene& scene);  // every group, attribute and series, then a flush
  void open_layout(const RecordedRun& run, const Scene& scene);  // the same, of an existing file
  std::unique_ptr<Impl> impl_;
  std::size_t frames_written_ = 0;
  std::vector<double> frame_;  // scratch for one frame of a derived field
};

}  // namespace noether
