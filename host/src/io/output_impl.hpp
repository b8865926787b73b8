#pragma once
// H5Writer::Impl: the open output file — its lock, its series, what is buffered (internal to
// libnoether; output.cpp writes frames, output_layout.cpp creates the layout).
#include <noether/output.hpp>

#include "io/checksum.hpp"
#include "io/flush.hpp"
#include "io/frame_schema.hpp"
#include "io/series.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace noether {

using io::Series;
using io::FrameQuantity;
using io::check;
using io::make_group;
using io::string_attribute;
using Clock = std::chrono::steady_clock;

struct H5Writer::Impl {
  int lock = -1;     // the descriptor holding the output's lock (claim_output)
  int claimed = -1;  // the existing file's, held until the new one replaces it
  std::filesystem::path path, partial;  // where the file goes, and the hidden name it is built under
  bool published = false;
  io::H5Handle file;
  OutputOptions options;
  Clock::time_point last_flush = Clock::now();
  std::size_t n_bodies = 0, n_rigid = 0;
  std::optional<System> system;  // the bodies the frames are computed with (masses, inertias)
  std::vector<Vec3> largest_moment_axes;  // each rigid body's (io::FrameInput), found once
  io::FrameLayout layout;        // which series the file has
  std::ptrdiff_t primary = -1, secondary = -1;  // the binary, when the scene is two-body-like
  // The frame schema's series this file has (io/frame_schema.hpp), in the schema's order.
  struct Column {
    const io::FrameQuantity* quantity;
    std::unique_ptr<Series> series;
    std::ptrdiff_t feature_offset = -1;  // a series a feature fills: its numbers' start among the features'
  };
  std::vector<Column> columns;
  std::vector<const Column*> checkpointed;  // by /checkpoint/checksum column (null: absent)
  // /checkpoint/checksum [frame][column]: checksum64 of each checkpointed series' frame, so
  // that a continued run finds a damaged frame before it trusts it.
  std::unique_ptr<Series> checksum_series;
  io::RecordedFrame read_back;  // a frame of the block as a continued run reads it (complete_block)
  std::size_t buffered = 0;
  std::size_t handed = 0;  // frames handed to be written: those written and the block in flight
  // The block being written on a thread of its own while the run goes on (when HDF5 is built
  // thread-safe: every other call of the file waits for it first, H5Writer::settle); once it
  // is written, the file holds `handed` frames.
  bool background_blocks = false;
  std::future<void> block_in_flight;
  hsize_t allocated = 0;   // frames allocated in every series
  io::H5Handle complete;   // /frames_complete: the number of frames written and flushed
  struct StepRecords {     // /integrator/<name>: an integrator's per-step records
    io::H5Handle dataset;
    hsize_t width = 1, rows = 0;
  };
  std::map<std::string, StepRecords> step_records;
  io::H5Handle integrator_group;
  std::string verdict, verdict_reasons, energy_scale;  // set_verdict
  H5Writer::ParticleSource particle_source;  // checkpoint_particles
  double last_frame_t = 0.0;                  // the time of the last frame written
  int particle_slot = 0;                      // the slot of /checkpoint/particles written next
  // /checkpoint/particles, created or written in place (H5Writer::write_particle_checkpoint).
  void write_particles(const ParticleCheckpoint& particles, std::int64_t frame);
  double relative_energy_error = 0.0;

  // Sets every series' length, then flushes: one change of the file. HDF5's metadata cache
  // would otherwise write some series' new shapes early (evicting them to make room while the
  // next series is resized), and a kill in between would leave series of different lengths; so
  // evictions are off until the flush has written all of them.
  void resize_series(hsize_t frames) {
    H5AC_cache_config_t saved{}, held{};
    saved.version = H5AC__CURR_CACHE_CONFIG_VERSION;
    const bool configured = H5Fget_mdc_config(file, &saved) >= 0;
    if (configured) {
      held = saved;
      held.evictions_enabled = false;  // which HDF5 allows only with automatic resizing off
      held.incr_mode = H5C_incr__off;
      held.flash_incr_mode = H5C_flash_incr__off;
      held.decr_mode = H5C_decr__off;
      H5Fset_mdc_config(file, &held);
    }
    for (auto& c : columns) c.series->resize(frames);
    checksum_series->resize(frames);
    allocated = frames;
    flush_file("resizing the output's series");
    if (configured) H5Fset_mdc_config(file, &saved);
  }
  void flush_file(const char* what) { io::flush_extended(file, lock, what); }
  // Computes what the handed block [first, end) lacks: each frame's checksums of the
  // checkpointed series (seeded with the frame's index, the bytes a continued run reads back) and
  // the quantities of the state alone, from the frame as a continued run reads it back — so the
  // file holds what it would hold had they been computed as the frames arrived, bit for bit.
  void complete_block(hsize_t first, hsize_t end) {
    const auto frames = static_cast<std::size_t>(end - first);
    const std::size_t width = checkpointed.size();
    std::uint64_t* sums = checksum_series->handed_block(frames);
    struct Target {  // a series of the state alone: its fill, and its handed block to fill
      io::FrameFill::OfState fill;
      std::uint64_t* out;
      std::size_t frame_size;
    };
    std::vector<Target> of_state;
    for (auto& c : columns)
      if (c.quantity->fill.of_state)
        of_state.push_back({c.quantity->fill.of_state, c.series->handed_block(frames), c.series->frame_size});
    for (std::size_t i = 0; i < frames; ++i) {
      for (std::size_t k = 0; k < width; ++k) {
        sums[i * width + k] = 0;  // an absent series' column
        if (!checkpointed[k]) continue;
        const Series& s = *checkpointed[k]->series;
        sums[i * width + k] = io::checksum64(s.handed_frame(i), s.frame_size * sizeof(std::uint64_t), first + i);
        if (const auto restore = checkpointed[k]->quantity->restore)  // (a feature's series: not the state's)
          restore(s.handed_frame(i), s.frame_size, read_back);
      }
      const io::StateFrame in{*system, primary, secondary, read_back.state, largest_moment_axes};
      for (const Target& t : of_state) t.fill(in, t.out + i * t.frame_size);
    }
  }
  // Writes the handed frames [first, end) (io::Series::hand_over): the frames first, then the
  // particles where they stand at its last frame (if given), then the counter that makes them
  // part of the file, each followed by a flush, so that a kill before the last flush leaves the
  // counter at the previous block, and the particles' other slot at its last frame.
  void write_block(hsize_t first, hsize_t end, const ParticleCheckpoint* particles = nullptr) {
    complete_block(first, end);
    if (end > allocated) resize_series(std::max<hsize_t>(end, 2 * allocated));  // the only metadata change while frames are written
    for (auto& c : columns) c.series->write_handed(first);
    checksum_series->write_handed(first);
    flush_file("flushing the output file");
    if (particles) write_particles(*particles, static_cast<std::int64_t>(end) - 1);
    write_complete(static_cast<std::int64_t>(end));
    flush_file("flushing the output file");
  }
  void write_complete(std::int64_t frames) {
    check(H5Dwrite(complete, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &frames),
          "writing /frames_complete");
  }
  void close_datasets() {
    checkpointed.clear();
    columns.clear();
    checksum_series.reset();
    step_records.clear();
    integrator_group.reset();
    complete.reset();
  }

};

}  // namespace noether
