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
};

class H5Writer {
 public:
  H5Writer(const std::filesystem::path& file, const Scene& scene, OutputOptions options = {});
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  void write_frame(std::int64_t step, const State& state, const Diagnostics& diagnostics);
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
  std::unique_ptr<Impl> impl_;
  std::size_t frames_written_ = 0;
  std::vector<double> frame_;  // scratch for one frame of a derived field
};

}  // namespace noether
