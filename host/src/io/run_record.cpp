#include "run_record.hpp"

#include "../h5_helpers.hpp"
#include "checkpointed.hpp"
#include "checksum.hpp"
#include "file_access.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <cstdlib>

namespace noether::io {

namespace fs = std::filesystem;

namespace {

// The extent of a dataset, empty when it does not open.
std::vector<hsize_t> extent(hid_t dataset) {
  if (dataset < 0) return {};
  const H5Handle space(H5Dget_space(dataset));
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space) : -1;
  if (rank < 1 || rank > 8) return {};
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

std::size_t frame_size(const std::vector<hsize_t>& dims) {
  std::size_t n = 1;
  for (std::size_t i = 1; i < dims.size(); ++i) n *= dims[i];
  return n;
}

// Frames [first, first + count) of a [frame][...] dataset into `out`; false when HDF5 fails.
template <class T>
bool read_hyperslab(hid_t dataset, hid_t mem_type, hsize_t first, hsize_t count, std::vector<T>& out) {
  std::vector<hsize_t> dims = extent(dataset);
  if (dims.empty()) return false;
  std::vector<hsize_t> start(dims.size(), 0);
  start[0] = first;
  dims[0] = count;
  out.resize(count * frame_size(dims));
  if (out.empty()) return true;
  const H5Handle file_space(H5Dget_space(dataset));
  const H5Handle mem_space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  if (!file_space.valid() || !mem_space.valid() ||
      H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr) < 0)
    return false;
  return H5Dread(dataset, mem_type, mem_space, file_space, H5P_DEFAULT, out.data()) >= 0;
}


}  // namespace

void RunRecord::damaged(const std::string& what) const { throw_damaged(file_, what); }

RunRecord::RunRecord(const fs::path& path) : file_(path) {
  using namespace noether::h5;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  std::error_code ec;
  if (!fs::exists(path, ec)) throw OutputError(path.string() + ": no such file");
  h5_ = H5Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, file_access(0)));  // each chunk is read once
  if (!h5_.valid())
    throw OutputError(path.string() + " is not an HDF5 file noether can read" + system_reason() +
                      " (or its first bytes, the HDF5 superblock, are damaged)");
  const hid_t file = h5_;
  const htri_t has_parameters = H5Lexists(file, "parameters", H5P_DEFAULT),
               has_complete = H5Lexists(file, "frames_complete", H5P_DEFAULT);
  if (has_parameters < 0 || has_complete < 0) damaged("its root group does not read");
  if (has_parameters == 0 || has_complete == 0)
    throw OutputError(path.string() + " is not a noether run's output (no /parameters or /frames_complete)");
  const htri_t has_checkpoint = H5Lexists(file, "checkpoint", H5P_DEFAULT);
  if (has_checkpoint < 0) damaged("its root group does not read");
  if (has_checkpoint == 0)
    throw OutputError(path.string() + " has no /checkpoint: it was written by an older noether, "
                                      "which did not keep the exact state; it cannot be continued");
  // Whether a path exists; an HDF5 error on the way (a damaged group) is damage, not absence.
  const auto exists = [this, file](const char* p) {
    const htri_t found = H5Lexists(file, p, H5P_DEFAULT);
    if (found < 0) damaged(std::string("the group holding ") + p + " does not read");
    return found > 0;
  };
  checksummed = exists("checkpoint") && exists(kChecksumPath);
  {
    const H5Handle parameters(H5Gopen2(file, "parameters", H5P_DEFAULT));
    if (!parameters.valid()) damaged("/parameters does not open");
    scene_text = read_string(parameters, "scene", true);
    scene_path = read_string(parameters, "scene_path", false);
    if (scene_path.empty()) scene_path = read_string(parameters, "scene_file", false);
    const std::string joined = read_string(parameters, "overrides", false);
    if (H5Aexists(parameters, "custom_potential") > 0) {
      int custom = 0;
      const H5Handle a(H5Aopen(parameters, "custom_potential", H5P_DEFAULT));
      H5Aread(a, H5T_NATIVE_INT, &custom);
      custom_potential = custom != 0;
    }
    overrides = lines_of(joined);
    if (checksummed && read_u64_attribute(parameters, "checksum") != scene_checksum(scene_text, scene_path, joined, custom_potential))
      damaged("/parameters (the scene's text, its path or the overrides) does not match its checksum");
  }
  if (exists("work")) {
    const H5Handle work(H5Gopen2(file, "work", H5P_DEFAULT));
    if (!work.valid()) damaged("/work does not open");
    outcome = read_string(work, "outcome", false);
    if (checksummed && read_u64_attribute(work, "outcome_checksum") != checksum64(outcome.data(), outcome.size()))
      damaged("/work's outcome does not match its checksum");
  }
  {
    const H5Handle checkpoint(H5Gopen2(file, "checkpoint", H5P_DEFAULT));
    if (checkpoint.valid()) resumed = read_string(checkpoint, "resumed", false);
    const H5Handle complete(H5Dopen2(file, "frames_complete", H5P_DEFAULT));
    if (!complete.valid() || H5Dread(complete, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &frames) < 0)
      damaged("/frames_complete does not read");
  }
  if (frames < 1)
    throw OutputError(path.string() + " holds no complete frame (the run was killed before its first block "
                                      "was written); start it again");
  // The shapes: [frame][body][3], [frame][rigid][3][3], [frame][width], each with at least
  // /frames_complete frames (exactly that many once the run ended and wrote /work).
  const auto n = static_cast<hsize_t>(frames);
  for (const auto& series : kCheckpointed) {
    const H5Handle d = open_dataset(file, series.path);
    if (!d.valid()) {
      if (series.rigid_only || series.optional) continue;
      damaged(std::string(series.path) + " is missing or does not open");
    }
    const std::vector<hsize_t> dims = extent(d);
    if (dims.empty() || dims[0] < n) damaged(std::string(series.path) + " holds fewer frames than /frames_complete");
    if (checksummed && !outcome.empty() && dims[0] != n)
      damaged(std::string(series.path) + " has " + std::to_string(dims[0]) + " frames, /frames_complete says " +
              std::to_string(frames) + " (a run that ended writes exactly that many)");
    const std::string p = series.path;
    if (p == kCheckpointed[kPosition].path) {
      if (dims.size() != 3 || dims[2] != 3) damaged(p + " is not [frame][body][3]");
      bodies = dims[1];
    } else if (p == kCheckpointed[kAttitude].path) {
      if (dims.size() != 4 || dims[2] != 3 || dims[3] != 3) damaged(p + " is not [frame][rigid body][3][3]");
      rigid = dims[1];
    } else if (p == kCheckpointed[kIntegrator].path) {
      if (dims.size() != 2) damaged(p + " is not [frame][width]");
      integrator_width = dims[1];
    } else if (p == kCheckpointed[kWork].path) {
      if (dims.size() != 2 || dims[1] != 5) damaged(p + " is not [frame][5]");
    }
  }
  if (checksummed) {
    const std::vector<hsize_t> dims = extent(open_dataset(file, kChecksumPath));
    if (dims.size() != 2 || dims[1] != kCheckpointedCount || dims[0] < n)
      damaged(std::string(kChecksumPath) + " is not [frame][" + std::to_string(kCheckpointedCount) + "]");
  }
}

bool RunRecord::read(std::size_t first, std::size_t count,
                     const std::function<void(std::size_t, const RecordedFrame&)>& visit,
                     const volatile std::sig_atomic_t* interrupt, std::size_t block) const {
  if (first + count > static_cast<std::size_t>(frames))
    throw OutputError(file_.string() + ": frames past /frames_complete requested");
  struct Column {
    H5Handle dataset;
    std::size_t width = 0;  // numbers per frame
    std::vector<double> values;
    std::vector<std::int64_t> integers;  // /checkpoint/work
  };
  std::vector<Column> columns(kCheckpointedCount);
  for (std::size_t c = 0; c < kCheckpointedCount; ++c) {
    columns[c].dataset = open_dataset(h5_, kCheckpointed[c].path);
    columns[c].width = columns[c].dataset.valid() ? frame_size(extent(columns[c].dataset)) : 0;
  }
  const H5Handle sums_dataset = checksummed ? open_dataset(h5_, kChecksumPath) : H5Handle();
  std::vector<std::uint64_t> sums;
  RecordedFrame frame;
  const auto nb = static_cast<Eigen::Index>(bodies), nr = static_cast<Eigen::Index>(rigid);
  frame.state.R.resize(rigid);
  for (std::size_t b = first; b < first + count; b += block) {
    if (interrupt && *interrupt) return false;
    const std::size_t n = std::min(block, first + count - b);
    for (std::size_t c = 0; c < kCheckpointedCount; ++c) {
      Column& col = columns[c];
      if (!col.dataset.valid()) continue;
      const bool ok = c == kWork ? read_hyperslab(col.dataset, H5T_NATIVE_INT64, b, n, col.integers)
                                 : read_hyperslab(col.dataset, H5T_NATIVE_DOUBLE, b, n, col.values);
      if (!ok)
        damaged("frames " + std::to_string(b) + " to " + std::to_string(b + n - 1) + " of " +
                kCheckpointed[c].path + " do not read (HDF5 found its metadata or data inconsistent)");
    }
    if (sums_dataset.valid() && !read_hyperslab(sums_dataset, H5T_NATIVE_UINT64, b, n, sums))
      damaged("frames " + std::to_string(b) + " to " + std::to_string(b + n - 1) + " of " + kChecksumPath +
              " do not read");
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t k = b + j;
      if (sums_dataset.valid()) {
        for (std::size_t c = 0; c < kCheckpointedCount; ++c) {
          const Column& col = columns[c];
          const void* data = c == kWork ? static_cast<const void*>(col.integers.data() + 5 * j)
                                        : static_cast<const void*>(col.values.data() + col.width * j);
          const std::uint64_t expected = col.dataset.valid() ? checksum64(data, col.width * 8, k) : 0;
          if (sums[kCheckpointedCount * j + c] != expected)
            damaged("frame " + std::to_string(k) + " of " + kCheckpointed[c].path +
                    " does not match its checksum in " + kChecksumPath);
        }
      }
      State& s = frame.state;
      s.t = columns[kTime].values[j];
      s.x = Eigen::Map<const Eigen::Matrix3Xd>(columns[kPosition].values.data() + 3 * bodies * j, 3, nb);
      s.p = Eigen::Map<const Eigen::Matrix3Xd>(columns[kMomentum].values.data() + 3 * bodies * j, 3, nb);
      if (rigid > 0) {
        s.Pi = Eigen::Map<const Eigen::Matrix3Xd>(columns[kSpin].values.data() + 3 * rigid * j, 3, nr);
        const double* R = columns[kAttitude].values.data() + 9 * rigid * j;
        for (std::size_t r = 0; r < rigid; ++r)  // row-major [row][column]
          for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 3; ++col) s.R[r](row, col) = R[9 * r + static_cast<std::size_t>(3 * row + col)];
      } else {
        s.Pi.resize(3, 0);
      }
      frame.U = columns[kPotential].values[j];
      const std::int64_t* w = columns[kWork].integers.data() + 5 * j;
      frame.work = WorkCounters{w[0], w[1], w[2], w[3]};
      frame.interpolated = w[4];
      frame.wall_seconds = columns[kWall].values[j];
      const Column& own = columns[kIntegrator];
      frame.integrator.assign(own.values.begin() + static_cast<std::ptrdiff_t>(own.width * j),
                              own.values.begin() + static_cast<std::ptrdiff_t>(own.width * (j + 1)));
      visit(k, frame);
    }
  }
  return true;
}

void RunRecord::read_step_records(const std::function<void(const StepSeries&)>& visit) const {
  if (H5Lexists(h5_, "integrator", H5P_DEFAULT) <= 0) return;
  const H5Handle group(H5Gopen2(h5_, "integrator", H5P_DEFAULT));
  H5G_info_t info{};
  if (!group.valid() || H5Gget_info(group, &info) < 0) damaged("/integrator does not open");
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256] = {0};
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0)
      damaged("/integrator's entries do not read");
    const H5Handle d(H5Dopen2(group, name, H5P_DEFAULT));
    const std::vector<hsize_t> dims = extent(d);
    if (dims.size() != 2 || dims[1] == 0) damaged(std::string("/integrator/") + name + " is not [step][width]");
    StepSeries series;
    series.name = name;
    series.width = dims[1];
    series.description = noether::h5::read_string(d, "description", false);
    const hsize_t rows_per_block = std::max<hsize_t>(1, 65536 / dims[1]);
    for (hsize_t r = 0; r < dims[0]; r += rows_per_block) {
      if (!read_hyperslab(d, H5T_NATIVE_DOUBLE, r, std::min(rows_per_block, dims[0] - r), series.values))
        damaged(std::string("/integrator/") + name + " does not read");
      visit(series);
    }
  }
}

}  // namespace noether::io
