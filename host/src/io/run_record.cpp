#include "io/run_record.hpp"

#include "io/h5.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"

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
  if (read_string(file, "format", false) == "noether simulation checkpoint 1")
    throw OutputError(path.string() + " is a checkpoint saved by an older noether (format 1: its own layout), which "
                                      "this version does not read; saved simulations are now output files with one "
                                      "frame (docs/python.md, \"Saving and loading\"): run the scene again");
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
    read_pair_models(parameters);
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
    if (checkpoint.valid() && H5Aexists(checkpoint, "t_origin") > 0) {
      const H5Handle a(H5Aopen(checkpoint, "t_origin", H5P_DEFAULT));
      if (!a.valid() || H5Aread(a, H5T_NATIVE_DOUBLE, &t_origin) < 0 ||
          read_u64_attribute(checkpoint, "t_origin_checksum") != checksum64(&t_origin, sizeof(double)))
        damaged("/checkpoint's t_origin does not read or does not match its checksum");
    }
    const H5Handle complete(H5Dopen2(file, "frames_complete", H5P_DEFAULT));
    if (!complete.valid() || H5Dread(complete, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &frames) < 0)
      damaged("/frames_complete does not read");
  }
  if (frames < 1)
    throw OutputError(path.string() + " holds no complete frame (the run was killed before its first block "
                                      "was written); start it again (noether run SCENE -o FILE --force, Python force=True: the file "
                                      "exists)");
  // The shapes the frame schema gives (io/frame_schema.hpp), each series with at least
  // /frames_complete frames (exactly that many once the run ended and wrote /work).
  const auto n = static_cast<hsize_t>(frames);
  bool rigid_seen = false;
  for (const FrameQuantity* q : checkpointed_series()) {
    const std::string p = q->path;
    const H5Handle d = open_dataset(file, q->path);
    if (!d.valid()) {
      if (rigid_only(*q) || optional(*q)) continue;  // rigid bodies' and the integrator's series
      damaged(p + " is missing or does not open");
    }
    const std::vector<hsize_t> dims = extent(d);
    if (dims.empty() || dims[0] < n) damaged(p + " holds fewer frames than /frames_complete");
    if (checksummed && !outcome.empty() && dims[0] != n)
      damaged(p + " has " + std::to_string(dims[0]) + " frames, /frames_complete says " + std::to_string(frames) +
              " (a run that ended writes exactly that many)");
    const std::size_t axis = dims.size() > 1 ? dims[1] : 0;
    FrameLayout layout;
    layout.bodies = layout.rigid = layout.width = axis;
    layout.forces = axis;
    layout.features = axis;
    if (q->fill.by_feature) {  // its shape is its feature's: here, of the rank its extent has
      if (dims.size() != frame_rank(q->extent) + 1) damaged(p + " is not " + describe_extent(q->extent));
      layout.feature_series.push_back({q->name, std::vector<std::size_t>(dims.begin() + 1, dims.end())});
    }
    if (q->extent == Extent::kTangent || q->extent == Extent::kSensitivity) {  // [coordinate][column]: 6 per body
      layout.bodies = bodies;                                                  // and rigid body (read before)
      layout.rigid = rigid;
      layout.stm_columns = layout.sensitivity_columns = dims.size() > 2 ? dims[2] : 0;
    }
    const std::vector<std::size_t> shape = frame_shape(*q, layout);
    if (dims.size() != shape.size() + 1 || !std::equal(shape.begin(), shape.end(), dims.begin() + 1))
      damaged(p + " is not " + describe_extent(q->extent));
    if (q->extent == Extent::kBodyVector) {
      if (bodies != 0 && bodies != axis) damaged(p + " has " + std::to_string(axis) + " bodies, not " + std::to_string(bodies));
      bodies = axis;
    } else if (rigid_only(*q)) {
      if (rigid_seen && rigid != axis) damaged(p + " has " + std::to_string(axis) + " rigid bodies, not " + std::to_string(rigid));
      rigid = axis;
      rigid_seen = true;
    } else if (q->extent == Extent::kIntegrator) {
      integrator_width = axis;
    }
  }
  if (checksummed) {
    const std::vector<hsize_t> dims = extent(open_dataset(file, kChecksumPath));
    const std::size_t columns = checkpointed_series().size();
    // A file from before /observables/force_balance, the particles' positions, or the tangent
    // were checkpointed has fewer columns (kChecksumColumnsBeforeForces, …BeforeParticles,
    // …BeforeTangent): readable, unless it holds such a series unchecked.
    if (dims.size() != 2 ||
        (dims[1] != columns && dims[1] != kChecksumColumnsBeforeTangent && dims[1] != kChecksumColumnsBeforeParticles &&
         dims[1] != kChecksumColumnsBeforeForces) ||
        dims[0] < n)
      damaged(std::string(kChecksumPath) + " is not [frame][" + std::to_string(columns) + "]");
    checksum_columns_ = dims[1];
    for (const FrameQuantity* q : checkpointed_series())
      if (static_cast<std::size_t>(q->checksum_column) >= checksum_columns_ && open_dataset(file, q->path).valid())
        throw OutputError(path.string() + " was written by an older noether, which did not checksum " + q->path +
                          "; it cannot be continued: run it again whole");
  }
  read_summary();
  read_particles();
}

// /checkpoint/particles' slots (H5Writer::write_particle_checkpoint): the one at the last
// complete frame, else the latest that matches its checksum (a continuation then says where it
// is); damaged when no slot does.
void RunRecord::read_particles() {
  if (H5Lexists(h5_, "/checkpoint/particles", H5P_DEFAULT) <= 0) return;
  const H5Handle group(H5Gopen2(h5_, "/checkpoint/particles", H5P_DEFAULT));
  if (!group.valid()) damaged("/checkpoint/particles does not open");
  constexpr std::size_t w = ParticleCheckpoint::kColumns;
  bool slot_damaged = false;
  for (const char* slot : {"0", "1"}) {
    const std::string rows_name = std::string("rows_") + slot, header_name = std::string("header_") + slot,
                      checksum_name = std::string("checksum_") + slot;
    if (H5Lexists(group, rows_name.c_str(), H5P_DEFAULT) <= 0) continue;
    const H5Handle rows(H5Dopen2(group, rows_name.c_str(), H5P_DEFAULT));
    const std::vector<hsize_t> dims = extent(rows);
    if (dims.size() != 2 || dims[1] != w) damaged("/checkpoint/particles/" + rows_name + " is not [particle][18]");
    std::vector<double> header(5);
    const H5Handle a(H5Aexists(group, header_name.c_str()) > 0 ? H5Aopen(group, header_name.c_str(), H5P_DEFAULT) : -1);
    const H5Handle space(a.valid() ? H5Aget_space(a) : -1);
    if (!space.valid() || H5Sget_simple_extent_npoints(space) != 5 || H5Aread(a, H5T_NATIVE_DOUBLE, header.data()) < 0)
      damaged("/checkpoint/particles' " + header_name + " does not read");
    ParticleCheckpoint c;
    c.rows.resize(dims[0] * w);
    if (!c.rows.empty() && H5Dread(rows, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.rows.data()) < 0)
      damaged("/checkpoint/particles/" + rows_name + " does not read");
    if (read_u64_attribute(group, checksum_name.c_str()) != particle_checksum(header, c.rows)) {
      slot_damaged = true;  // (killed while it was written: the other slot is a block earlier)
      continue;
    }
    c.t = header[0], c.particle_steps = header[1], c.check_steps = header[2], c.seconds = header[3];
    c.frame = static_cast<std::int64_t>(header[4]);
    const bool at_last = c.frame == frames - 1;
    if (!particles || (at_last && particles->frame != frames - 1) ||
        (at_last == (particles->frame == frames - 1) && c.frame > particles->frame))
      particles = std::move(c);
  }
  if (!particles && slot_damaged) damaged("/checkpoint/particles does not match its checksum");
}

std::vector<std::string> RunRecord::body_names() const {
  std::vector<std::string> names;
  try {
    names = read_string_list(h5_, "/particles/bodies/name");
  } catch (const OutputError& e) {
    damaged(e.what());
  }
  if (names.size() != bodies) damaged("/particles/bodies/name does not name " + std::to_string(bodies) + " bodies");
  return names;
}

std::vector<double> RunRecord::body_masses() const {
  const H5Handle d = open_dataset(h5_, "/particles/bodies/mass");
  if (!d.valid()) damaged("/particles/bodies/mass is missing or does not open");
  const std::vector<hsize_t> dims = extent(d);
  std::vector<double> masses(bodies);
  if (dims.size() != 1 || dims[0] != bodies ||
      (bodies > 0 && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, masses.data()) < 0))
    damaged("/particles/bodies/mass is not [" + std::to_string(bodies) + "] numbers");
  return masses;
}

void RunRecord::read_pair_models(hid_t parameters) {

  const htri_t exists = H5Lexists(parameters, "pair_models", H5P_DEFAULT);
  if (exists < 0) damaged("/parameters does not read");
  if (exists == 0) return;
  const H5Handle group(H5Gopen2(parameters, "pair_models", H5P_DEFAULT));
  H5G_info_t info;
  if (!group.valid() || H5Gget_info(group, &info) < 0) damaged("/parameters/pair_models does not open");
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[1024];
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) < 0)
      damaged("/parameters/pair_models does not list its pairs");
    const H5Handle g(H5Gopen2(group, name, H5P_DEFAULT));
    if (!g.valid()) damaged(std::string("/parameters/pair_models/") + name + " does not open");
    const auto number = [&](const char* attribute, hid_t type, void* out) {
      if (H5Aexists(g, attribute) <= 0) return;
      const H5Handle a(H5Aopen(g, attribute, H5P_DEFAULT));
      if (!a.valid() || H5Aread(a, type, out) < 0)
        damaged(std::string("/parameters/pair_models/") + name + "'s " + attribute + " does not read");
    };
    PairModel m;
    m.body_a = read_string(g, "body_a", false);
    m.body_b = read_string(g, "body_b", false);
    m.model = read_string(g, "model", false);
    int exceeded = 0;
    number("order", H5T_NATIVE_INT, &m.order);
    number("tolerance", H5T_NATIVE_DOUBLE, &m.tolerance);
    number("estimated_error", H5T_NATIVE_DOUBLE, &m.estimated_error);
    number("separation", H5T_NATIVE_DOUBLE, &m.separation);
    number("exceeded", H5T_NATIVE_INT, &exceeded);
    m.exceeded = exceeded != 0;
    number("exceeded_time", H5T_NATIVE_DOUBLE, &m.exceeded_time);
    number("exceeded_separation", H5T_NATIVE_DOUBLE, &m.exceeded_separation);
    number("exceeded_error", H5T_NATIVE_DOUBLE, &m.exceeded_error);
    pair_models.push_back(std::move(m));
  }
}

void RunRecord::read_summary() {
  const htri_t exists = H5Lexists(h5_, "/checkpoint/summary", H5P_DEFAULT);
  if (exists < 0) damaged("/checkpoint does not read");
  if (exists == 0) return;
  const H5Handle group(H5Gopen2(h5_, "/checkpoint/summary", H5P_DEFAULT));
  H5O_info_t info{};
  if (!group.valid() || H5Oget_info2(group, &info, H5O_INFO_NUM_ATTRS) < 0) damaged("/checkpoint/summary does not open");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const H5Handle a(H5Aopen_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT));
    char name[128] = {0};
    if (!a.valid() || H5Aget_name(a, sizeof name, name) < 0) damaged("/checkpoint/summary's attributes do not read");
    const H5Handle type(H5Aget_type(a)), space(H5Aget_space(a));
    const std::string key = name;
    if (key == "checksum" || key == "description") continue;
    if (H5Tget_class(type) == H5T_STRING) {
      summary_texts.emplace_back(key, read_string(group, name, false));
    } else {
      const hssize_t n = H5Sget_simple_extent_npoints(space);
      std::vector<double> values(static_cast<std::size_t>(std::max<hssize_t>(0, n)));
      if (n < 0 || n > 1024 || (n > 0 && H5Aread(a, H5T_NATIVE_DOUBLE, values.data()) < 0))
        damaged("/checkpoint/summary's " + key + " does not read");
      summary_numbers.emplace_back(key, std::move(values));
    }
  }
  if (read_u64_attribute(group, "checksum") != summary_checksum(summary_numbers, summary_texts))
    damaged("/checkpoint/summary does not match its checksum");
  if (summary_numbers.empty()) damaged("/checkpoint/summary holds no numbers");
}

bool RunRecord::read(std::size_t first, std::size_t count,
                     const std::function<void(std::size_t, const RecordedFrame&)>& visit,
                     const volatile std::sig_atomic_t* interrupt, std::size_t block) const {
  if (first + count > static_cast<std::size_t>(frames))
    throw OutputError(file_.string() + ": frames past /frames_complete requested");
  struct Column {
    const FrameQuantity* quantity;
    H5Handle dataset;
    std::size_t width = 0;               // numbers per frame
    std::vector<std::uint64_t> values;   // a block of frames, as the file's 8-byte numbers
  };
  std::vector<Column> columns;
  for (const FrameQuantity* q : checkpointed_series()) {
    Column c{q, open_dataset(h5_, q->path), 0, {}};
    c.width = c.dataset.valid() ? frame_size(extent(c.dataset)) : 0;
    columns.push_back(std::move(c));
  }
  const H5Handle sums_dataset = checksummed ? open_dataset(h5_, kChecksumPath) : H5Handle();
  std::vector<std::uint64_t> sums;
  RecordedFrame frame;
  frame.state.R.resize(rigid);
  if (rigid == 0) frame.state.Pi.resize(3, 0);
  for (std::size_t b = first; b < first + count; b += block) {
    if (interrupt && *interrupt) return false;
    const std::size_t n = std::min(block, first + count - b);
    const std::string frames_read = "frames " + std::to_string(b) + " to " + std::to_string(b + n - 1) + " of ";
    for (Column& col : columns) {
      if (!col.dataset.valid()) continue;
      const hid_t type = is_integer(*col.quantity) ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
      if (!read_hyperslab(col.dataset, type, b, n, col.values))
        damaged(frames_read + col.quantity->path + " do not read (HDF5 found its metadata or data inconsistent)");
    }
    if (sums_dataset.valid() && !read_hyperslab(sums_dataset, H5T_NATIVE_UINT64, b, n, sums))
      damaged(frames_read + kChecksumPath + " do not read");
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t k = b + j;
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const Column& col = columns[c];
        const std::uint64_t* values = col.values.data() + col.width * j;
        if (sums_dataset.valid() && c < checksum_columns_) {
          const std::uint64_t expected = col.dataset.valid() ? checksum64(values, col.width * 8, k) : 0;
          if (sums[checksum_columns_ * j + c] != expected)
            damaged(col.dataset.valid()
                        ? "frame " + std::to_string(k) + " of " + col.quantity->path + " does not match its checksum in " +
                              kChecksumPath
                        // A series this run does not write: its column is written 0, so the damage is the table's.
                        : "frame " + std::to_string(k) + " of " + kChecksumPath + " is damaged: its column " +
                              std::to_string(c) + " (" + col.quantity->path +
                              ", a series this file does not hold) is not the 0 written there");
        }
        if (!col.dataset.valid()) continue;
        if (col.quantity->fill.by_feature)
          frame.set_series(col.quantity->name, static_cast<const double*>(static_cast<const void*>(values)), col.width);
        else
          col.quantity->restore(values, col.width, frame);
      }
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
    series.description = read_string(d, "description", false);
    const hsize_t rows_per_block = std::max<hsize_t>(1, 65536 / dims[1]);
    for (hsize_t r = 0; r < dims[0]; r += rows_per_block) {
      if (!read_hyperslab(d, H5T_NATIVE_DOUBLE, r, std::min(rows_per_block, dims[0] - r), series.values))
        damaged(std::string("/integrator/") + name + " does not read");
      visit(series);
    }
  }
}

}  // namespace noether::io
