#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/version.hpp>

#include "h5_helpers.hpp"
#include "io/checkpointed.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <limits>
#include <map>
#include <cstring>
#include <cstdio>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace noether {

namespace {

using Clock = std::chrono::steady_clock;
using namespace noether::h5;

// A series [frame][shape...]: a chunked dataset whose chunks are all allocated (and filled
// with `fill`) when it is created or grown, so that writing frames changes raw data only, never
// the file's metadata (docs/user-guide.md, "Output files": a kill at any moment leaves a
// consistent file).
template <class T>
struct Series {
  hid_t dataset = -1;
  hid_t type = -1;
  std::vector<hsize_t> frame_shape;
  std::size_t frame_size = 1;
  std::vector<T> buffer;

  Series(hid_t parent, const char* name, hid_t h5type, std::vector<hsize_t> shape, hsize_t frames,
         T fill)
      : type(h5type), frame_shape(std::move(shape)) {
    for (auto d : frame_shape) frame_size *= d;
    std::vector<hsize_t> dims{frames}, maxdims{H5S_UNLIMITED}, chunk;
    const hsize_t frames_per_chunk =
        std::max<hsize_t>(1, std::min<hsize_t>(1024, 8192 / std::max<std::size_t>(1, frame_size)));
    chunk.push_back(frames_per_chunk);
    for (auto d : frame_shape) {
      dims.push_back(d);
      maxdims.push_back(d);
      chunk.push_back(std::max<hsize_t>(1, d));
    }
    hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data());
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data());
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_value(plist, type, &fill);
    H5Pset_fill_time(plist, H5D_FILL_TIME_ALLOC);
    dataset = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT),
                       name);
    H5Pclose(plist);
    H5Sclose(space);
  }
  // An existing series (a continued run's file).
  Series(hid_t file, const char* path, hid_t h5type) : type(h5type) {
    dataset = check_id(H5Dopen2(file, path, H5P_DEFAULT), path);
    hid_t space = H5Dget_space(dataset);
    std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    H5Sclose(space);
    frame_shape.assign(dims.begin() + 1, dims.end());
    for (auto d : frame_shape) frame_size *= d;
  }
  hsize_t frames() const {
    hid_t space = H5Dget_space(dataset);
    hsize_t dims[8] = {0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    return dims[0];
  }
  ~Series() {
    if (dataset >= 0) H5Dclose(dataset);
  }
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;

  void push(const T* values) { buffer.insert(buffer.end(), values, values + frame_size); }

  // Sets the number of frames (growing allocates and fills the new chunks).
  void resize(hsize_t frames) {
    std::vector<hsize_t> dims{frames};
    dims.insert(dims.end(), frame_shape.begin(), frame_shape.end());
    check(H5Dset_extent(dataset, dims.data()), "resizing a dataset");
  }

  // Writes the buffered frames from `first_frame` on (inside the allocated frames).
  void write(hsize_t first_frame) {
    if (buffer.empty() || frame_size == 0) {
      buffer.clear();
      return;
    }
    const hsize_t frames = buffer.size() / frame_size;
    std::vector<hsize_t> start{first_frame}, count{frames};
    for (auto d : frame_shape) {
      start.push_back(0);
      count.push_back(d);
    }
    hid_t file_space = H5Dget_space(dataset);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
    hid_t mem_space = H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr);
    check(H5Dwrite(dataset, type, mem_space, file_space, H5P_DEFAULT, buffer.data()),
          "writing a block of frames");
    H5Sclose(mem_space);
    H5Sclose(file_space);
    buffer.clear();
  }
};

}  // namespace

// Claiming and publishing an output file (docs/user-guide.md, "Output files"). The file is
// built under a hidden name in the same folder and renamed into place once its layout is
// complete and flushed, so the path holds either what was there before or a readable file; an
// existing file is locked (flock) from the claim until it is replaced, and the new file from its
// creation until it is closed, so a second run on the same path is refused and loses nothing.
// (HDF5 1.10 locks only after opening with O_TRUNC, and a record lock would be dropped when
// HDF5 closes any descriptor of the file, so the lock is ours and HDF5's own is switched off for
// the files noether writes: HDF5_USE_FILE_LOCKING=FALSE unless the user set it.)
namespace {

namespace fs = std::filesystem;

int lock_or_refuse(int fd, const fs::path& path) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return fd;
  const int e = errno;
  ::close(fd);
  if (e == EWOULDBLOCK)
    throw OutputError("another process is writing " + path.string() +
                      " (a second noether run on the same output, or a reader holding HDF5's lock); "
                      "the file is left untouched");
  throw OutputError("cannot lock the output file " + path.string() + ": " + std::strerror(e));
}

// Refuses a symbolic link, anything but a regular file, one of the run's inputs, and an
// existing file unless `overwrite`; locks an existing file. Returns its descriptor, or −1.
int claim_output(const fs::path& path, const OutputOptions& options) {
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (fs::is_symlink(link))
    throw OutputError(path.string() + " is a symbolic link; noether does not write through links: give the file "
                      "it points to, or another path");
  const bool exists = fs::exists(link);
  if (exists && !fs::is_regular_file(link))
    throw OutputError(path.string() + " exists and is not a regular file");
  for (const auto& input : options.inputs)
    if (exists && fs::equivalent(path, input, ec))
      throw OutputError("the output " + path.string() + " is the run's input " + input.string() +
                        "; choose another output file");
  if (exists && !options.overwrite)
    throw OutputError(path.string() + " exists; noether does not overwrite output unless asked: pass --force, "
                      "or choose another output file");
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  if (!exists) return -1;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) throw OutputError("cannot open the existing output file " + path.string() + ": " + std::strerror(errno));
  return lock_or_refuse(fd, path);
}

// The hidden name the file is built under: .<name>.partial-<pid>, next to it.
fs::path partial_name(const fs::path& path) {
  std::string name = ".";
  name += path.filename().string();
  name += ".partial-";
  name += std::to_string(::getpid());
  return path.parent_path() / name;
}

int create_partial(const fs::path& partial, const fs::path& path) {
  const int fd = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0)
    throw OutputError("cannot create the output file " + path.string() + ": " + std::strerror(errno) +
                      " (does its folder exist, and is it writable?)");
  return lock_or_refuse(fd, path);
}

// Moves the finished layout to `path`: replacing the claimed file, or only if no other
// process created `path` meanwhile.
void publish_file(const fs::path& partial, const fs::path& path, bool replace) {
  if (replace) {
    if (::rename(partial.c_str(), path.c_str()) != 0)
      throw OutputError("cannot replace " + path.string() + ": " + std::strerror(errno));
    return;
  }
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) == 0) return;
  int e = errno;
  if (e == EINVAL || e == ENOSYS) {  // a file system without RENAME_NOREPLACE: link, then unlink
    if (::link(partial.c_str(), path.c_str()) == 0) {
      ::unlink(partial.c_str());
      return;
    }
    e = errno;
  }
  if (e == EEXIST)
    throw OutputError("another process created " + path.string() +
                      " while this run was starting; nothing was overwritten");
  throw OutputError("cannot create the output file " + path.string() + ": " + std::strerror(e));
}

}  // namespace

struct H5Writer::Impl {
  int lock = -1;     // the descriptor holding the output's lock (claim_output)
  int claimed = -1;  // the existing file's, held until the new one replaces it
  fs::path path, partial;  // where the file goes, and the hidden name it is built under
  bool published = false;
  hid_t file = -1;
  OutputOptions options;
  Clock::time_point last_flush = Clock::now();
  std::size_t n_bodies = 0, n_rigid = 0;
  std::vector<double> masses;
  std::vector<std::unique_ptr<Series<double>>> doubles;  // all double series, for flushing
  Series<std::int64_t>* step = nullptr;
  Series<double>* time = nullptr;
  Series<double>*position = nullptr, *velocity = nullptr, *orientation = nullptr,
  *angular_momentum = nullptr, *energy = nullptr, *kinetic_translational = nullptr,
  *kinetic_rotational = nullptr, *potential_energy = nullptr, *linear_momentum_total = nullptr,
  *angular_momentum_total = nullptr, *orthogonality = nullptr;
  // /checkpoint: the exact state (γ, R) and the work and wall time at each frame (--resume).
  Series<double>*exact_momentum = nullptr, *exact_attitude = nullptr, *wall_time = nullptr,
  *integrator_checkpoint = nullptr;
  std::unique_ptr<Series<std::int64_t>> step_series, work_series;
  // /checkpoint/checksum [frame][column]: checksum64 of each checkpointed series' frame
  // (io/checkpointed.hpp), so that a continued run finds a damaged frame before it trusts it.
  std::unique_ptr<Series<std::uint64_t>> checksum_series;
  std::size_t buffered = 0;
  hsize_t allocated = 0;   // frames allocated in every series
  hid_t complete = -1;     // /frames_complete: the number of frames written and flushed
  struct StepRecords {     // /integrator/<name>: an integrator's per-step records
    hid_t dataset = -1;
    hsize_t width = 1, rows = 0;
  };
  std::map<std::string, StepRecords> step_records;
  hid_t integrator_group = -1;
  std::string verdict, verdict_reasons, energy_scale;  // set_verdict
  double relative_energy_error = 0.0;

  // A series of doubles, described, with its unit (the scene's, docs/user-guide.md "Units").
  Series<double>* add(hid_t parent, const char* name, std::vector<hsize_t> shape, const std::string& unit,
                      const std::string& description) {
    doubles.push_back(std::make_unique<Series<double>>(parent, name, H5T_NATIVE_DOUBLE, std::move(shape),
                                                       allocated, std::numeric_limits<double>::quiet_NaN()));
    string_attribute(doubles.back()->dataset, "unit", unit);
    string_attribute(doubles.back()->dataset, "description", description);
    return doubles.back().get();
  }
  void resize_series(hsize_t frames) {
    step_series->resize(frames);
    work_series->resize(frames);
    checksum_series->resize(frames);
    for (auto& s : doubles) s->resize(frames);
    allocated = frames;
  }
  // Flushes the file, having first extended it to HDF5's end of allocation: the superblock the
  // flush writes records that address, and HDF5 refuses to open a file shorter than it says
  // ("truncated file"), which a kill between the superblock and the last block of metadata
  // would otherwise leave.
  void flush_file(const char* what) {
    haddr_t eoa = 0;
    struct stat st {};
    if (H5Fget_eoa(file, &eoa) >= 0 && ::fstat(lock, &st) == 0 && static_cast<haddr_t>(st.st_size) < eoa &&
        ::ftruncate(lock, static_cast<off_t>(eoa)) != 0)
      throw OutputError(std::string("cannot extend the output file while ") + what + ": " + std::strerror(errno));
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), what);
  }
  void write_complete(std::int64_t frames) {
    check(H5Dwrite(complete, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &frames),
          "writing /frames_complete");
  }
  void close_datasets() {
    doubles.clear();
    step_series.reset();
    work_series.reset();
    checksum_series.reset();
    for (auto& [name, records] : step_records) H5Dclose(records.dataset);
    step_records.clear();
    if (integrator_group >= 0) H5Gclose(integrator_group);
    integrator_group = -1;
    if (complete >= 0) H5Dclose(complete);
    complete = -1;
  }

  // An H5MD time-series group: {step, time, value}; step and time are hard links to one pair.
  hid_t element(hid_t parent, const char* name) {
    hid_t g = make_group(parent, name);
    if (step) {
      check(H5Lcreate_hard(file, "/particles/bodies/position/step", g, "step", H5P_DEFAULT,
                           H5P_DEFAULT), "linking step");
      check(H5Lcreate_hard(file, "/particles/bodies/position/time", g, "time", H5P_DEFAULT,
                           H5P_DEFAULT), "linking time");
    }
    return g;
  }
};

H5Writer::H5Writer(const std::filesystem::path& path, const Scene& scene, OutputOptions options)
    : impl_(std::make_unique<Impl>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become OutputError, not stderr noise
  Impl& m = *impl_;
  m.options = options;
  m.path = path;
  m.claimed = claim_output(path, options);
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

void H5Writer::create_layout(const Scene& scene) {
  Impl& m = *impl_;
  const OutputOptions& options = m.options;
  const System& sys = scene.system;
  m.n_bodies = sys.size();
  m.n_rigid = sys.rigid_count();
  // Every series is allocated for the frames the run will write, up to a budget; a run that
  // writes more grows them (in doubling steps, each flushed at once).
  const double frame_bytes = 8.0 * static_cast<double>(18 + 9 * m.n_bodies + 16 * m.n_rigid);
  const double budget = std::max(1.0, std::floor(options.preallocate_bytes / frame_bytes));
  m.allocated = static_cast<hsize_t>(
      std::min(options.expected_frames > 0 ? static_cast<double>(options.expected_frames) : 1024.0, budget));

  hid_t h5md = make_group(m.file, "h5md");
  numeric_attribute<int>(h5md, "version", H5T_NATIVE_INT, {1, 1});
  hid_t creator = make_group(h5md, "creator");
  string_attribute(creator, "name", "noether");
  string_attribute(creator, "version", NOETHER_VERSION);
  H5Gclose(creator);
  H5Gclose(h5md);

  hid_t parameters = make_group(m.file, "parameters");
  string_attribute(parameters, "scene_file", scene.file);
  // Where the scene was, so that a continued run finds its shape files from any folder.
  std::error_code ec;
  const fs::path absolute = scene.file.empty() ? fs::path() : fs::absolute(scene.file, ec);
  const std::string scene_path = ec ? scene.file : absolute.string();
  string_attribute(parameters, "scene_path", scene_path);
  string_dataset(parameters, "scene", scene.text, "the scene file's text, as given");
  string_dataset(parameters, "scene_as_run", scene_as_run(scene),
                 "the scene as run: after the --set overrides (YAML)");
  std::string overrides;
  for (const auto& o : scene.overrides) overrides += (overrides.empty() ? "" : "\n") + o;
  string_attribute(parameters, "overrides", overrides);
  // What a continued run rebuilds its scene from, checksummed (io/run_record.cpp).
  numeric_attribute<std::uint64_t>(parameters, "checksum", H5T_NATIVE_UINT64,
                                   {io::scene_checksum(scene.text, scene_path, overrides, options.custom_potential)});
  std::string potentials;
  for (const auto& p : scene.potentials) potentials += (potentials.empty() ? "" : "+") + p.plugin;
  string_attribute(parameters, "potential", options.custom_potential ? "python (given in code, not the scene's)" : potentials);
  numeric_attribute<int>(parameters, "custom_potential", H5T_NATIVE_INT, {options.custom_potential ? 1 : 0});
  string_attribute(parameters, "integrator", scene.integrator.plugin);
  scalar_attribute(parameters, "G", sys.G());
  string_attribute(parameters, "units", scene.units.describe());
  string_attribute(parameters, "unit_length", scene.units.of_length());
  string_attribute(parameters, "unit_mass", scene.units.of_mass());
  string_attribute(parameters, "unit_time", scene.units.of_time());
  string_attribute(parameters, "unit_G", scene.units.of_G());
  scalar_attribute(parameters, "t_end", scene.run.t_end);
  scalar_attribute(parameters, "output_every", scene.run.output_every);
  // Bodies with a solid shape: what it is and how its mesh was placed in the body frame
  // (x_file = offset + rotation · x_body).
  hid_t shapes = -1;
  for (const auto& b : sys.bodies()) {
    if (!b.solid) continue;
    if (shapes < 0) shapes = make_group(parameters, "shapes");
    hid_t g = make_group(shapes, b.name.c_str());
    string_attribute(g, "kind", b.solid->kind == Solid::Kind::Ellipsoid ? "ellipsoid" : "polyhedron");
    string_attribute(g, "description", b.solid->describe());
    numeric_attribute<double>(g, "density", H5T_NATIVE_DOUBLE, {b.solid->density});
    numeric_attribute<double>(g, "volume", H5T_NATIVE_DOUBLE, {b.solid->volume});
    numeric_attribute<double>(g, "semi_axes", H5T_NATIVE_DOUBLE,
                              {b.solid->semi_axes.x(), b.solid->semi_axes.y(), b.solid->semi_axes.z()});
    numeric_attribute<double>(g, "offset", H5T_NATIVE_DOUBLE,
                              {b.solid->offset.x(), b.solid->offset.y(), b.solid->offset.z()});
    std::vector<double> rotation;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) rotation.push_back(b.solid->rotation(r, c));
    numeric_attribute<double>(g, "rotation", H5T_NATIVE_DOUBLE, rotation);  // row-major
    H5Gclose(g);
  }
  if (shapes >= 0) H5Gclose(shapes);
  H5Gclose(parameters);

  hid_t particles = make_group(m.file, "particles");
  hid_t bodies = make_group(particles, "bodies");
  std::vector<std::string> names;
  for (const auto& b : sys.bodies()) {
    names.push_back(b.name);
    m.masses.push_back(b.mass);
  }
  string_list_dataset(bodies, "name", names);
  double_dataset(bodies, "mass", m.masses);
  {
    hid_t d = H5Dopen2(bodies, "mass", H5P_DEFAULT);
    string_attribute(d, "unit", scene.units.of_mass());
    string_attribute(d, "description", "mass of each body");
    H5Dclose(d);
    d = H5Dopen2(bodies, "name", H5P_DEFAULT);
    string_attribute(d, "description", "the bodies' names, in the order of every [body] axis");
    H5Dclose(d);
  }
  if (m.n_rigid > 0) {  // J_k, principal-axes body frame, [rigid body][3][3]
    std::vector<double> inertia;
    std::vector<int> rigid_index;
    for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
      const Body& b = sys.body(sys.body_of_rigid(k));
      rigid_index.push_back(static_cast<int>(sys.body_of_rigid(k)));
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) inertia.push_back(b.inertia(r, c));
    }
    const hsize_t dims[3] = {m.n_rigid, 3, 3};
    hid_t space = H5Screate_simple(3, dims, nullptr);
    hid_t d = check_id(H5Dcreate2(bodies, "inertia", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                                  H5P_DEFAULT), "inertia");
    check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, inertia.data()), "inertia");
    numeric_attribute<int>(d, "body_index", H5T_NATIVE_INT, rigid_index);
    string_attribute(d, "description", "inertia tensor J of each rigid body in its body frame");
    string_attribute(d, "unit", scene.units.of_inertia());
    H5Dclose(d);
    H5Sclose(space);
  }
  const hsize_t nb = m.n_bodies, nr = m.n_rigid;
  hid_t pos = make_group(bodies, "position");
  m.step_series = std::make_unique<Series<std::int64_t>>(pos, "step", H5T_NATIVE_INT64,
                                                         std::vector<hsize_t>{}, m.allocated, -1);
  m.step = m.step_series.get();
  string_attribute(m.step->dataset, "description", "the integrator's step count at each frame");
  const Units& u = scene.units;
  m.time = m.add(pos, "time", {}, u.of_time(), "time of each frame");
  m.position = m.add(pos, "value", {nb, 3}, u.of_length(),
                     "position x of each body's centre of mass, inertial frame [frame][body][xyz]");
  H5Gclose(pos);
  hid_t g = m.element(bodies, "velocity");
  m.velocity = m.add(g, "value", {nb, 3}, u.of_velocity(),
                     "velocity of each body's centre of mass, inertial frame [frame][body][xyz]");
  H5Gclose(g);
  if (m.n_rigid > 0) {
    std::vector<int> rigid_index;
    for (std::size_t k = 0; k < sys.rigid_count(); ++k)
      rigid_index.push_back(static_cast<int>(sys.body_of_rigid(k)));
    g = m.element(bodies, "orientation");  // quaternion (w, x, y, z), rigid bodies only
    numeric_attribute<int>(g, "body_index", H5T_NATIVE_INT, rigid_index);
    m.orientation = m.add(g, "value", {nr, 4}, "1",
                          "attitude R (body to inertial frame) of each rigid body as a unit quaternion "
                          "(w, x, y, z) [frame][rigid body][wxyz]; body_index names the bodies");
    H5Gclose(g);
    g = m.element(bodies, "angular_momentum");  // Π, body frame, rigid bodies only
    numeric_attribute<int>(g, "body_index", H5T_NATIVE_INT, rigid_index);
    m.angular_momentum = m.add(g, "value", {nr, 3}, u.of_angular_momentum(),
                               "spin angular momentum Π = J Ω of each rigid body, body frame "
                               "[frame][rigid body][xyz]");
    H5Gclose(g);
  }
  H5Gclose(bodies);
  H5Gclose(particles);

  hid_t obs = make_group(m.file, "observables");
  const std::string energy_unit = u.of_energy();
  const struct {
    const char* name;
    Series<double>** target;
    std::string unit, description;
  } scalars[] = {
      {"energy", &m.energy, energy_unit, "total energy E = T + U at each frame"},
      {"kinetic_energy_translational", &m.kinetic_translational, energy_unit, "Σ |γ|²/(2m)"},
      {"kinetic_energy_rotational", &m.kinetic_rotational, energy_unit, "Σ Π·J⁻¹Π/2"},
      {"potential_energy", &m.potential_energy, energy_unit, "the mutual potential U"},
      {"orthogonality_error", &m.orthogonality, "1", "max over rigid bodies of ‖I − RᵀR‖_F"}};
  for (const auto& scalar : scalars) {
    g = m.element(obs, scalar.name);
    *scalar.target = m.add(g, "value", {}, scalar.unit, scalar.description);
    H5Gclose(g);
  }
  g = m.element(obs, "linear_momentum");
  m.linear_momentum_total = m.add(g, "value", {3}, u.of_momentum(), "total linear momentum Σ γ, inertial frame");
  H5Gclose(g);
  g = m.element(obs, "angular_momentum");
  m.angular_momentum_total = m.add(g, "value", {3}, u.of_angular_momentum(),
                                   "total angular momentum about the origin, Σ x × γ + R Π, inertial frame");
  H5Gclose(g);
  H5Gclose(obs);

  // The checkpoint of every frame: what the derived series lose (γ, not v = γ/m; R, not its
  // quaternion) and the work done, so that a continued run starts exactly where this one was.
  hid_t checkpoint = make_group(m.file, "checkpoint");
  string_attribute(checkpoint, "description",
                   "the exact state and the work at every frame, from which `noether run --resume` "
                   "continues a run");
  m.exact_momentum = m.add(checkpoint, "linear_momentum", {nb, 3}, u.of_momentum(),
                           "linear momentum γ = m v of each body, inertial frame [frame][body][xyz], exact");
  if (m.n_rigid > 0)
    m.exact_attitude = m.add(checkpoint, "attitude", {nr, 3, 3}, "1",
                             "attitude matrix R (body to inertial) of each rigid body [frame][rigid body][row][column], "
                             "exact");
  m.wall_time = m.add(checkpoint, "wall_time", {}, "s", "wall time spent by the run up to each frame");
  if (options.checkpoint_width > 0)
    m.integrator_checkpoint =
        m.add(checkpoint, "integrator", {options.checkpoint_width}, "mixed",
              "the integrator's own variables at each frame (Integrator::checkpoint: a relative frame's "
              "coordinates, a two-step form's previous step), from which a continued run restores it");
  m.work_series = std::make_unique<Series<std::int64_t>>(checkpoint, "work", H5T_NATIVE_INT64,
                                                         std::vector<hsize_t>{5}, m.allocated, -1);
  string_attribute(m.work_series->dataset, "description",
                   "work up to each frame: steps, potential evaluations, Newton iterations, rejected steps, "
                   "frames interpolated between the method's steps");
  {
    std::vector<std::string> columns;
    for (const auto& c : io::kCheckpointed) columns.push_back(c.path);
    m.checksum_series = std::make_unique<Series<std::uint64_t>>(
        checkpoint, "checksum", H5T_NATIVE_UINT64, std::vector<hsize_t>{io::kCheckpointedCount}, m.allocated, 0);
    string_attribute(m.checksum_series->dataset, "description",
                     "checksum64 of each frame of the series named in `columns`, seeded with the frame's index "
                     "(0: the series is absent); `noether run --resume` verifies every frame it reads");
    std::string joined;
    for (const auto& c : columns) joined += (joined.empty() ? "" : "\n") + c;
    string_attribute(m.checksum_series->dataset, "columns", joined);
  }
  if (!options.resumed.empty()) string_attribute(checkpoint, "resumed", options.resumed);
  H5Gclose(checkpoint);

  // The commit counter: frames [0, frames_complete) are complete; a killed run's series keep
  // their allocated length, with fill (NaN, step −1) or an unfinished block after it.
  {
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_layout(plist, H5D_CONTIGUOUS);
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    m.complete = check_id(H5Dcreate2(m.file, "frames_complete", H5T_NATIVE_INT64, space, H5P_DEFAULT,
                                     plist, H5P_DEFAULT), "frames_complete");
    H5Pclose(plist);
    H5Sclose(space);
    string_attribute(m.complete, "description",
                     "the number of complete frames: every series holds exactly this many after a "
                     "run that ended; after a killed run, read series[:frames_complete]");
    m.write_complete(0);
  }
  m.flush_file("flushing the output file");
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
    m.flush_file("flushing the output file");
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

void H5Writer::write_pair_models(const std::vector<PairModel>& models) {
  if (models.empty()) return;
  Impl& m = *impl_;
  hid_t parameters = H5Gopen2(m.file, "parameters", H5P_DEFAULT);
  if (H5Lexists(parameters, "pair_models", H5P_DEFAULT) > 0) H5Ldelete(parameters, "pair_models", H5P_DEFAULT);
  hid_t group = make_group(parameters, "pair_models");
  for (const auto& p : models) {
    hid_t g = make_group(group, (p.body_a + "–" + p.body_b).c_str());
    string_attribute(g, "body_a", p.body_a);
    string_attribute(g, "body_b", p.body_b);
    string_attribute(g, "model", p.model);
    numeric_attribute<int>(g, "order", H5T_NATIVE_INT, {p.order});
    numeric_attribute<double>(g, "tolerance", H5T_NATIVE_DOUBLE, {p.tolerance});
    numeric_attribute<double>(g, "estimated_error", H5T_NATIVE_DOUBLE, {p.estimated_error});
    numeric_attribute<double>(g, "separation", H5T_NATIVE_DOUBLE, {p.separation});
    numeric_attribute<int>(g, "exceeded", H5T_NATIVE_INT, {p.exceeded ? 1 : 0});
    if (p.exceeded) {
      numeric_attribute<double>(g, "exceeded_time", H5T_NATIVE_DOUBLE, {p.exceeded_time});
      numeric_attribute<double>(g, "exceeded_separation", H5T_NATIVE_DOUBLE, {p.exceeded_separation});
      numeric_attribute<double>(g, "exceeded_error", H5T_NATIVE_DOUBLE, {p.exceeded_error});
    }
    H5Gclose(g);
  }
  H5Gclose(group);
  H5Gclose(parameters);
  m.flush_file("flushing the output file");
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
  m.resize_series(frames_written_);
  m.close_datasets();
  m.flush_file("closing the output file");
  check(H5Fclose(m.file), "closing the output file");
  m.file = -1;
  ::close(m.lock);
  m.lock = -1;
}

}  // namespace noether
