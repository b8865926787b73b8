// H5Writer: the output file's life — claimed, built under a hidden name and published, frames
// buffered and written in blocks, finished (docs/user-guide.md, "Output files"); the layout it
// creates is in output_layout.cpp.
#include <noether/error.hpp>
#include <noether/output.hpp>

#include "h5_helpers.hpp"
#include "io/checkpointed.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/safe_publish.hpp"
#include "output_impl.hpp"

#include <algorithm>
#include <cmath>

#include <unistd.h>

namespace noether {

namespace fs = std::filesystem;
using namespace noether::h5;
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
    m.file = H5Fcreate(m.partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, io::file_access(64 * 1024));
    if (m.file < 0)
      throw OutputError("cannot create the output file " + path.string() + system_reason() +
                        " (does its folder exist, and is it writable?)");
    create_layout(scene);
    if (!options.defer_publish) publish();
  } catch (...) {
    abandon();
    throw;
  }
}

void H5Writer::publish() {
  Impl& m = *impl_;
  if (m.published) return;
  m.flush_file("flushing the output file");
  publish_file(m.partial, m.path, m.claimed >= 0);
  m.published = true;
  if (m.claimed >= 0) ::close(m.claimed);
  m.claimed = -1;
}

void H5Writer::abandon() {
  Impl& m = *impl_;
  if (m.file >= 0) {
    m.close_datasets();
    H5Fclose(m.file);
    m.file = -1;
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

void H5Writer::write_frame(const State& state, const Diagnostics& d, const WorkCounters& work,
                           double wall_seconds, std::int64_t interpolated_frames,
                           const std::vector<double>& integrator_checkpoint) {
  Impl& m = *impl_;
  using namespace io;
  // Column c of /checkpoint/checksum: checksum64 of this frame of kCheckpointed[c], seeded with
  // the frame's index (the bytes the reader will read back: the state, U, work, wall time).
  const std::uint64_t seed = frames_written_ + m.buffered;
  std::uint64_t sums[kCheckpointedCount] = {};
  const auto sum = [seed](const void* data, std::size_t bytes) { return checksum64(data, bytes, seed); };
  const std::size_t nb = m.n_bodies, nr = m.n_rigid;
  m.step->push(&work.steps);
  const std::int64_t counters[5] = {work.steps, work.potential_evaluations, work.newton_iterations,
                                    work.rejected_steps, interpolated_frames};
  sums[kTime] = sum(&state.t, sizeof(double));
  sums[kPosition] = sum(state.x.data(), 3 * nb * sizeof(double));
  sums[kMomentum] = sum(state.p.data(), 3 * nb * sizeof(double));
  sums[kPotential] = sum(&d.potential, sizeof(double));
  sums[kWork] = sum(counters, sizeof counters);
  sums[kWall] = sum(&wall_seconds, sizeof(double));
  if (m.integrator_checkpoint) sums[kIntegrator] = sum(integrator_checkpoint.data(), integrator_checkpoint.size() * sizeof(double));
  m.work_series->push(counters);
  m.wall_time->push(&wall_seconds);
  if (m.integrator_checkpoint) {
    if (integrator_checkpoint.size() != m.integrator_checkpoint->frame_size)
      throw OutputError("the integrator's checkpoint changed its size during the run");
    m.integrator_checkpoint->push(integrator_checkpoint.data());
  }
  m.exact_momentum->push(state.p.data());
  m.time->push(&state.t);
  m.position->push(state.x.data());
  frame_.resize(3 * m.n_bodies + 9 * m.n_rigid);
  for (std::size_t i = 0; i < m.n_bodies; ++i)  // v = γ/m
    for (int a = 0; a < 3; ++a)
      frame_[3 * i + a] = state.p(a, static_cast<Eigen::Index>(i)) / m.masses[i];
  m.velocity->push(frame_.data());
  if (m.orientation) {
    for (std::size_t k = 0; k < m.n_rigid; ++k) {
      const Vec4 q = quaternion_from_rotation(state.R[k]);
      for (int a = 0; a < 4; ++a) frame_[4 * k + a] = q[a];
    }
    m.orientation->push(frame_.data());
    m.angular_momentum->push(state.Pi.data());
    for (std::size_t k = 0; k < m.n_rigid; ++k)  // row-major, as the file's [row][column]
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) frame_[9 * k + static_cast<std::size_t>(3 * r + c)] = state.R[k](r, c);
    m.exact_attitude->push(frame_.data());
    sums[kAttitude] = sum(frame_.data(), 9 * nr * sizeof(double));
    sums[kSpin] = sum(state.Pi.data(), 3 * nr * sizeof(double));
  }
  m.checksum_series->push(sums);
  m.energy->push(&d.energy);
  m.kinetic_translational->push(&d.kinetic_translational);
  m.kinetic_rotational->push(&d.kinetic_rotational);
  m.potential_energy->push(&d.potential);
  m.orthogonality->push(&d.orthogonality_error);
  m.linear_momentum_total->push(d.linear_momentum.data());
  m.angular_momentum_total->push(d.angular_momentum.data());
  ++m.buffered;
  const double since = std::chrono::duration<double>(Clock::now() - m.last_flush).count();
  if (m.buffered >= m.options.block_frames || since >= m.options.block_seconds) flush();
}

void H5Writer::flush() {
  Impl& m = *impl_;
  if (m.file < 0) return;
  if (m.buffered == 0) return;
  const hsize_t first = frames_written_, needed = first + m.buffered;
  if (needed > m.allocated) {  // grow: the only metadata change while frames are written
    m.resize_series(std::max<hsize_t>(needed, 2 * m.allocated));
  }
  // The frames first, then the counter that makes them part of the file: a kill before the
  // second flush leaves the counter at the previous block.
  m.step->write(first);
  m.work_series->write(first);
  m.checksum_series->write(first);
  for (auto& s : m.doubles) s->write(first);
  m.flush_file("flushing the output file");
  frames_written_ = needed;
  m.buffered = 0;
  m.write_complete(static_cast<std::int64_t>(frames_written_));
  m.flush_file("flushing the output file");
  m.last_flush = Clock::now();
}

void H5Writer::append_step_series(const std::vector<StepSeries>& records) {
  Impl& m = *impl_;
  for (const auto& series : records) {
    const hsize_t width = std::max<std::size_t>(1, series.width), rows = series.values.size() / width;
    auto found = m.step_records.find(series.name);
    if (found == m.step_records.end()) {  // /integrator/<name> [row][width], extendible
      if (m.integrator_group < 0) m.integrator_group = make_group(m.file, "integrator");
      const hsize_t dims[2] = {0, width}, maxdims[2] = {H5S_UNLIMITED, width},
                    chunk[2] = {std::max<hsize_t>(1, 8192 / width), width};
      hid_t space = H5Screate_simple(2, dims, maxdims);
      hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
      H5Pset_chunk(plist, 2, chunk);
      hid_t d = check_id(H5Dcreate2(m.integrator_group, series.name.c_str(), H5T_NATIVE_DOUBLE, space,
                                    H5P_DEFAULT, plist, H5P_DEFAULT), series.name.c_str());
      H5Pclose(plist);
      H5Sclose(space);
      string_attribute(d, "description", series.description);
      found = m.step_records.emplace(series.name, Impl::StepRecords{d, width, 0}).first;
    }
    Impl::StepRecords& out = found->second;
    if (out.width != width)
      throw OutputError("the integrator's per-step series '" + series.name + "' changed its width");
    if (rows == 0) continue;
    const hsize_t dims[2] = {out.rows + rows, width}, start[2] = {out.rows, 0}, count[2] = {rows, width};
    check(H5Dset_extent(out.dataset, dims), "extending /integrator");
    hid_t file_space = H5Dget_space(out.dataset);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t mem_space = H5Screate_simple(2, count, nullptr);
    check(H5Dwrite(out.dataset, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, series.values.data()),
          "writing /integrator");
    H5Sclose(mem_space);
    H5Sclose(file_space);
    out.rows += rows;
  }
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
  hid_t g = make_group(m.file, "work");
  numeric_attribute<std::int64_t>(g, "steps", H5T_NATIVE_INT64, {work.steps});
  numeric_attribute<std::int64_t>(g, "potential_evaluations", H5T_NATIVE_INT64,
                                  {work.potential_evaluations});
  numeric_attribute<std::int64_t>(g, "newton_iterations", H5T_NATIVE_INT64,
                                  {work.newton_iterations});
  numeric_attribute<std::int64_t>(g, "rejected_steps", H5T_NATIVE_INT64, {work.rejected_steps});
  numeric_attribute<double>(g, "wall_time", H5T_NATIVE_DOUBLE, {wall_seconds});
  string_attribute(g, "outcome", outcome);
  numeric_attribute<std::uint64_t>(g, "outcome_checksum", H5T_NATIVE_UINT64,
                                   {io::checksum64(outcome.data(), outcome.size())});
  if (!m.verdict.empty()) {
    string_attribute(g, "verdict", m.verdict);
    string_attribute(g, "verdict_reasons", m.verdict_reasons);
    numeric_attribute<double>(g, "relative_energy_error", H5T_NATIVE_DOUBLE, {m.relative_energy_error});
    string_attribute(g, "energy_scale", m.energy_scale);
  }
  H5Gclose(g);
  m.close_datasets();
  m.flush_file("closing the output file");
  check(H5Fclose(m.file), "closing the output file");
  m.file = -1;
  ::close(m.lock);
  m.lock = -1;
}

}  // namespace noether
