// H5Writer: the output file's life — claimed, built under a hidden name and published, frames
// buffered and written in blocks, finished (docs/user-guide.md, "Output files"); the layout it
// creates is in output_layout.cpp.
#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/particles.hpp>

#include "io/h5.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/h5.hpp"
#include "io/safe_publish.hpp"
#include "io/output_impl.hpp"

#include <algorithm>
#include <cmath>

#include <unistd.h>

namespace noether {

namespace fs = std::filesystem;
using namespace noether::io;
using io::claim_output;
using io::create_partial;
using io::partial_name;
using io::publish_file;

H5Writer::H5Writer(const std::filesystem::path& path, const Scene& scene, OutputOptions options)
    : impl_(std::make_unique<Impl>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become OutputError, not stderr noise
  Impl& m = *impl_;
  m.options = options;
  m.path = path;
  m.claimed = claim_output(path, options.overwrite, options.inputs);
  m.partial = partial_name(path);
  try {
    m.lock = create_partial(m.partial, path);
    m.file = io::H5Handle(H5Fcreate(m.partial.c_str(), H5F_ACC_TRUNC, io::file_creation(), io::file_access(64 * 1024)));
    if (!m.file.valid())
      throw OutputError("cannot create the output file " + path.string() + system_reason() +
                        " (does its folder exist, and is it writable?)");
    create_layout(scene);
    hbool_t threadsafe = false;
    m.background_blocks = options.background_blocks && H5is_library_threadsafe(&threadsafe) >= 0 && threadsafe;
    if (!options.defer_publish) publish();
  } catch (...) {
    abandon();
    throw;
  }
}

void H5Writer::publish() {
  Impl& m = *impl_;
  if (m.published) return;
  // Every frame so far complete before the file takes the path: a continuation's file replaces
  // the run it continues, and a kill just after must find all the frames it copied.
  flush();
  m.flush_file("flushing the output file");
  publish_file(m.partial, m.path, m.claimed >= 0);
  m.published = true;
  if (m.claimed >= 0) ::close(m.claimed);
  m.claimed = -1;
}

void H5Writer::abandon() {
  Impl& m = *impl_;
  if (m.block_in_flight.valid()) {  // the file closes after the block in flight, whatever became of it
    try {
      settle();
    } catch (...) {
    }
  }
  if (m.file.valid()) {
    m.close_datasets();
    m.file.reset();
    if (m.published) io::trim_extension(m.path, m.lock);
  }
  if (m.lock >= 0) {
    if (!m.published) ::unlink(m.partial.c_str());
    ::close(m.lock);
    m.lock = -1;
  }
  if (m.claimed >= 0) ::close(m.claimed);
  m.claimed = -1;
}

H5Writer::~H5Writer() {
  if (!impl_) return;
  if (impl_->file >= 0 && impl_->published) {
    try {
      flush();
    } catch (...) {
    }
    try {
      impl_->resize_series(frames_written_);
    } catch (...) {
    }
  }
  abandon();  // an unpublished file is removed; the path keeps what it held
}

// /checkpoint/particles (H5Writer::write_particle_checkpoint): two slots, 0 and 1, written in
// turn in place (each created at its first use) — its rows, its header (t, the Verlet steps, the
// check's steps, seconds, the frame) and the checksum of both, then a flush. A kill while one is
// written leaves it not matching its checksum and the other as it was, a block of frames earlier.
void H5Writer::Impl::write_particles(const ParticleCheckpoint& particles, std::int64_t frame) {
  Impl& m = *this;
  constexpr auto w = static_cast<hsize_t>(ParticleCheckpoint::kColumns);
  const std::vector<double> header{particles.t, particles.particle_steps, particles.check_steps, particles.seconds,
                                   static_cast<double>(frame)};
  const std::uint64_t checksum = io::particle_checksum(header, particles.rows);
  const char* const path = "/checkpoint/particles";
  const std::string slot = std::to_string(particle_slot), rows_name = "rows_" + slot, header_name = "header_" + slot,
                    checksum_name = "checksum_" + slot;
  particle_slot = 1 - particle_slot;
  if (H5Lexists(m.file, path, H5P_DEFAULT) <= 0) {
    const io::H5Handle g(make_group(m.file, path));
    string_attribute(g, "description",
                     "the massless particles where they stood at an output frame, from which Simulation.load or a "
                     "continued run carries them on, in two slots written in turn: 'rows_K' [particle][18] (x, v, a, "
                     "fate, t, body, impact point, impact velocity), the particles then the check's at half the step; "
                     "'header_K' t, Verlet steps, the check's steps, seconds, frame; 'checksum_K'");
  }
  const io::H5Handle g(check_id(H5Gopen2(m.file, path, H5P_DEFAULT), path));
  if (H5Lexists(g, rows_name.c_str(), H5P_DEFAULT) <= 0) {
    const hsize_t dims[2] = {particles.rows.size() / w, w};
    const io::H5Handle space(H5Screate_simple(2, dims, nullptr));
    check_id(H5Dcreate2(g, rows_name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             "/checkpoint/particles' rows");  // closed at once: written below
    numeric_attribute<double>(g, header_name.c_str(), H5T_NATIVE_DOUBLE, header);
    numeric_attribute<std::uint64_t>(g, checksum_name.c_str(), H5T_NATIVE_UINT64, {0});
  }
  const io::H5Handle rows(check_id(H5Dopen2(g, rows_name.c_str(), H5P_DEFAULT), "/checkpoint/particles' rows"));
  if (!particles.rows.empty())
    check(H5Dwrite(rows, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, particles.rows.data()),
          "/checkpoint/particles' rows");
  const io::H5Handle h(check_id(H5Aopen(g, header_name.c_str(), H5P_DEFAULT), "/checkpoint/particles' header"));
  check(H5Awrite(h, H5T_NATIVE_DOUBLE, header.data()), "/checkpoint/particles' header");
  const io::H5Handle c(check_id(H5Aopen(g, checksum_name.c_str(), H5P_DEFAULT), "/checkpoint/particles' checksum"));
  check(H5Awrite(c, H5T_NATIVE_UINT64, &checksum), "/checkpoint/particles' checksum");
  m.flush_file("flushing the particles' checkpoint");
}

void H5Writer::write_frame(const State& state, const Diagnostics& d, const WorkCounters& work,
                           double wall_seconds, std::int64_t interpolated_frames,
                           const std::vector<double>& integrator_checkpoint, std::span<const double> series,
                           std::span<const double> features) {
  Impl& m = *impl_;
  if (m.options.checkpoint_width > 0 && integrator_checkpoint.size() != m.options.checkpoint_width)
    throw OutputError("the integrator's checkpoint changed its size during the run");
  if (features.size() != m.layout.features)
    throw OutputError("the frame holds " + std::to_string(features.size()) + " fields of the run features, not the " +
                      std::to_string(m.layout.features) + " the file was made for");
  std::size_t series_size = 0;
  for (const auto& s : m.options.feature_series) series_size += s.size();
  if (series.size() != series_size)
    throw OutputError("the frame holds " + std::to_string(series.size()) + " numbers of the run features' series, not the " +
                      std::to_string(series_size) + " the file was made for");
  const io::FrameInput in{state, d, work, interpolated_frames, wall_seconds, integrator_checkpoint,
                          m.layout.stm_columns, m.layout.sensitivity_columns, features};
  // The run's own numbers, copied in place; the quantities of the state alone and the checksums
  // are computed when the block is written (Impl::complete_block), off the run's thread.
  for (auto& column : m.columns) {
    if (const auto fill = column.quantity->fill.of_run) {
      fill(in, column.series->append_frame());
    } else if (column.feature_offset >= 0) {
      const auto values = series.subspan(static_cast<std::size_t>(column.feature_offset), column.series->frame_size);
      std::copy(values.begin(), values.end(), static_cast<double*>(static_cast<void*>(column.series->append_frame())));
    }
  }
  ++m.buffered;
  m.last_frame_t = state.t;
  const double since = std::chrono::duration<double>(Clock::now() - m.last_flush).count();
  if (m.buffered < m.options.block_frames && since < m.options.block_seconds) return;
  if (!m.background_blocks || !m.published) return flush();
  // The block is written on a thread of its own while the run goes on; the previous one first
  // (its error, if any, is this call's).
  settle();
  const hsize_t first = m.handed, end = first + m.buffered;
  auto swarm = m.particle_source ? m.particle_source(m.last_frame_t) : std::nullopt;
  hand_over();
  m.block_in_flight = std::async(std::launch::async, [&m, first, end, swarm = std::move(swarm)] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // each thread has its own error stack
    m.write_block(first, end, swarm ? &*swarm : nullptr);
  });
}

void H5Writer::hand_over() {
  Impl& m = *impl_;
  for (auto& c : m.columns) c.series->hand_over();
  m.checksum_series->hand_over();
  m.handed += m.buffered;
  m.buffered = 0;
  m.last_flush = Clock::now();
}

void H5Writer::settle() {
  Impl& m = *impl_;
  if (!m.block_in_flight.valid()) return;
  auto block = std::move(m.block_in_flight);
  block.get();  // rethrows the block's error; then its frames are in the file
  frames_written_ = m.handed;  // (nothing is handed over while a block is in flight)
}

void H5Writer::flush() {
  Impl& m = *impl_;
  if (!m.file.valid()) return;
  settle();
  if (m.buffered == 0) return;
  const hsize_t first = m.handed, end = first + m.buffered;
  const auto particles = m.particle_source ? m.particle_source(m.last_frame_t) : std::nullopt;
  hand_over();
  m.write_block(first, end, particles ? &*particles : nullptr);
  frames_written_ = end;
}

void H5Writer::checkpoint_particles(ParticleSource source) { impl_->particle_source = std::move(source); }

void H5Writer::append_step_series(const std::vector<StepSeries>& records) {
  Impl& m = *impl_;
  settle();
  for (const auto& series : records) {
    const hsize_t width = std::max<std::size_t>(1, series.width), rows = series.values.size() / width;
    auto found = m.step_records.find(series.name);
    if (found == m.step_records.end()) {  // /integrator/<name> [row][width], extendible
      if (!m.integrator_group.valid()) m.integrator_group = make_group(m.file, "integrator");
      const hsize_t dims[2] = {0, width}, maxdims[2] = {H5S_UNLIMITED, width},
                    chunk[2] = {std::max<hsize_t>(1, 8192 / width), width};
      const io::H5Handle space(H5Screate_simple(2, dims, maxdims)), plist(H5Pcreate(H5P_DATASET_CREATE));
      H5Pset_chunk(plist, 2, chunk);
      io::H5Handle d = check_id(H5Dcreate2(m.integrator_group, series.name.c_str(), H5T_NATIVE_DOUBLE, space,
                                           H5P_DEFAULT, plist, H5P_DEFAULT),
                                series.name.c_str());
      string_attribute(d, "description", series.description);
      found = m.step_records.emplace(series.name, Impl::StepRecords{std::move(d), width, 0}).first;
    }
    Impl::StepRecords& out = found->second;
    if (out.width != width)
      throw OutputError("the integrator's per-step series '" + series.name + "' changed its width");
    if (rows == 0) continue;
    const hsize_t dims[2] = {out.rows + rows, width}, start[2] = {out.rows, 0}, count[2] = {rows, width};
    check(H5Dset_extent(out.dataset, dims), "extending /integrator");
    const io::H5Handle file_space(H5Dget_space(out.dataset));
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    const io::H5Handle mem_space(H5Screate_simple(2, count, nullptr));
    check(H5Dwrite(out.dataset, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, series.values.data()),
          "writing /integrator");
    out.rows += rows;
  }
}

void H5Writer::write_summary_values(const std::vector<std::pair<std::string, std::vector<double>>>& numbers,
                                    const std::vector<std::pair<std::string, std::string>>& texts) {
  Impl& m = *impl_;
  settle();
  const io::H5Handle g(make_group(m.file, "/checkpoint/summary"));
  string_attribute(g, "description",
                   "the summary's running values where Simulation.save was called, from which "
                   "Simulation.load continues it");
  for (const auto& [name, values] : numbers) numeric_attribute<double>(g, name.c_str(), H5T_NATIVE_DOUBLE, values);
  for (const auto& [name, text] : texts) string_attribute(g, name.c_str(), text);
  numeric_attribute<std::uint64_t>(g, "checksum", H5T_NATIVE_UINT64, {io::summary_checksum(numbers, texts)});
  m.flush_file("flushing the output file");
}

void H5Writer::write_particle_checkpoint(const ParticleCheckpoint& particles, std::int64_t frame) {
  settle();
  impl_->write_particles(particles, frame);
}

void H5Writer::set_verdict(const std::string& verdict, const std::string& reasons,
                           double relative_energy_error, const std::string& energy_scale) {
  Impl& m = *impl_;
  m.verdict = verdict;
  m.verdict_reasons = reasons;
  m.relative_energy_error = relative_energy_error;
  m.energy_scale = energy_scale;
}

void H5Writer::finish(const WorkCounters& work, double wall_seconds, const std::string& outcome) {
  Impl& m = *impl_;
  if (!m.published) {  // never published (a continuation that failed before it began): nothing to finish
    abandon();
    return;
  }
  flush();
  // The series at their final length first (flushed), then /work: a kill in between leaves a
  // killed run's file, never a finished one whose series are longer than its frames.
  m.resize_series(frames_written_);
  // /work is built unlinked and flushed, then linked and flushed: HDF5 writes a flush's
  // metadata in no fixed order, and a kill after the root group's new link but before /work's
  // own header left a link to unwritten metadata (docs/reliability.md, "Kills").
  io::H5Handle g = check_id(H5Gcreate_anon(m.file, io::late_group_creation(), H5P_DEFAULT), "work");
  scalar_attribute<std::int64_t>(g, "steps", H5T_NATIVE_INT64, work.steps);
  scalar_attribute<std::int64_t>(g, "potential_evaluations", H5T_NATIVE_INT64, work.potential_evaluations);
  scalar_attribute<std::int64_t>(g, "newton_iterations", H5T_NATIVE_INT64, work.newton_iterations);
  scalar_attribute<std::int64_t>(g, "rejected_steps", H5T_NATIVE_INT64, work.rejected_steps);
  scalar_attribute(g, "wall_time", wall_seconds);
  string_attribute(g, "outcome", outcome);
  scalar_attribute<std::uint64_t>(g, "outcome_checksum", H5T_NATIVE_UINT64, io::checksum64(outcome.data(), outcome.size()));
  if (!m.verdict.empty()) {
    string_attribute(g, "verdict", m.verdict);
    string_attribute(g, "verdict_reasons", m.verdict_reasons);
    scalar_attribute(g, "relative_energy_error", m.relative_energy_error);
    string_attribute(g, "energy_scale", m.energy_scale);
  }
  m.close_datasets();
  m.flush_file("closing the output file");
  check(H5Olink(g, m.file, "work", H5P_DEFAULT, H5P_DEFAULT), "linking /work");
  g.reset();
  m.flush_file("closing the output file");
  if (!m.file.close()) check(-1, "closing the output file");
  io::trim_extension(m.path, m.lock);
  ::close(m.lock);
  m.lock = -1;
}

}  // namespace noether
