// Continuing a run: Simulation::resume (an output file read back, verified and copied,
// docs/reliability.md "Checksums"), Simulation::save and Simulation::load (a checkpoint file).
#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "h5_helpers.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/read_probe.hpp"
#include "io/run_record.hpp"
#include "io/safe_publish.hpp"
#include "simulation_impl.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <unistd.h>

namespace noether {

std::unique_ptr<Simulation> Simulation::resume(const std::filesystem::path& file, PluginRegistry& registry,
                                               RunOptions options, double t_end) {
  // The file is read, verified frame by frame and copied into a new file that replaces it only
  // once every recorded frame is in (docs/user-guide.md, "Continuing a run"): a damaged file is
  // refused, and neither it nor an interrupted continuation is ever half-changed.
  // Every read below is made first in a child (io/read_probe.hpp): a damaged file must not crash
  // or hang this process.
  io::read_probe(file, [&file] {
    const io::RunRecord run(file);
    run.read(0, static_cast<std::size_t>(run.frames), [](std::size_t, const io::RecordedFrame&) {});
    run.read_step_records([](const StepSeries&) {});
  }, io::read_probe_seconds(file), options.interrupt);
  const io::RunRecord run(file);
  const std::string& outcome = run.outcome;
  std::vector<std::string> overrides = run.overrides;
  const bool extend = !std::isnan(t_end);
  if (extend) {
    std::ostringstream o;
    o.precision(17);
    o << "run.t_end=" << t_end;
    overrides.push_back(o.str());
  }
  if (run.custom_potential)
    throw Error(file.string() + ": the run's potential was given in code (a Python function), not by its scene, "
                "so it cannot be continued from the file alone; save() the Simulation and load() it with the potential");
  if (outcome.rfind("failed", 0) == 0)
    throw Error(file.string() + ": the run " + outcome +
                "; continuing it would fail again — change the scene and run it afresh");
  if (outcome.rfind("stopped: collision", 0) == 0 || outcome.rfind("stopped: close approach", 0) == 0)
    throw Error(file.string() + ": the run ended at an event (" + outcome.substr(9) + "); there is nothing to continue");
  if (!run.checksummed)
    spdlog::warn("{} was written by a noether without checksums: its frames are continued unverified (the "
                 "continued file has them)", file.string());
  Scene scene = parse_scene(run.scene_text, run.scene_path, overrides);
  if (scene.system.size() != run.bodies || scene.system.rigid_count() != run.rigid)
    throw Error(file.string() + ": its scene (" + run.scene_path + ") no longer gives the bodies the run had");
  const std::size_t last = static_cast<std::size_t>(run.frames - 1);
  io::RecordedFrame at_last;
  run.read(last, 1, [&at_last](std::size_t, const io::RecordedFrame& f) { at_last = f; });
  const double t_last = at_last.state.t;
  if (!(scene.run.t_end > t_last)) {
    std::ostringstream why;
    why.precision(10);
    why << file.string() << ": the run is already at t = " << t_last << ", its t_end"
        << (extend ? " is not later" : "; give a later --t-end to extend it");
    throw Error(why.str());
  }

  // The run rebuilt, its recorded frames replayed into the summary and copied into the new
  // file, block by block.
  const std::optional<std::filesystem::path> no_output;
  RunOptions rebuilt = options;
  rebuilt.output = no_output;
  auto sim = std::unique_ptr<Simulation>(new Simulation(std::move(scene), registry, rebuilt));
  Impl& m = *sim->impl_;
  m.new_segment();
  const Scene& sc = m.scene;
  OutputOptions output = m.output_options(true);
  char line[128];
  std::snprintf(line, sizeof line, "frame %zu at t = %.17g", last, t_last);
  output.resumed = run.resumed + (run.resumed.empty() ? "" : "\n") + line;
  m.writer = std::make_unique<H5Writer>(file, sc, output);
  Forces forces;
  forces.resize(sc.system);
  double t0 = 0.0;
  const bool complete = run.read(0, last + 1, [&](std::size_t k, const io::RecordedFrame& f) {
    if (k == 0) {  // frame 0 with its forces (what the scene conserves), the others with U alone
      auto workspace = m.potential->make_workspace();
      m.potential->evaluate(f.state, forces, *workspace);
      t0 = f.state.t;
    }
    forces.U = f.U;
    const Diagnostics d = m.observer->account(f.state, forces);
    m.writer->write_frame(f.state, d, f.work, f.wall_seconds, f.interpolated, f.integrator);
  }, options.interrupt);
  if (!complete) {
    m.writer.reset();  // the new file is dropped; the old one was only read
    throw Error(file.string() + " was being read back when the continuation was interrupted; it is unchanged");
  }
  run.read_step_records([&m](const StepSeries& records) { m.writer->append_step_series({records}); });
  m.writer->write_pair_models(m.summary.pair_models);
  m.writer->publish();

  m.summary.interpolated_frames = at_last.interpolated;
  m.state = at_last.state;
  m.t_origin = t0;
  const double h = m.integrator->fixed_step();
  m.steps_before = h > 0 && t_last > m.t_origin ? whole_steps(t_last - m.t_origin, h, "the recorded time") : 0;
  // The integrator continues from its own variables where it has any (relative frame,
  // Lagrangian forms), else from the state.
  if (at_last.integrator.size() != m.integrator->checkpoint().size())
    throw Error(file.string() + ": its integrator checkpoint does not fit the scene's integrator");
  const std::int64_t evaluations = m.integrator->work().potential_evaluations;
  m.integrator->restore(m.state, at_last.integrator);
  m.integrator_at_state = true;
  m.base_work = at_last.work + WorkCounters{0, -evaluations, 0, 0};
  m.wall_seconds = at_last.wall_seconds;
  m.options = std::move(options);
  m.options.output = file;
  return sim;
}
// Saving and loading ------------------------------------------------------------------------
// A checkpoint file: the scene as given, the exact state, where the run stands (t0, steps), its
// work and the summary's running values, so that a loaded simulation continues as this one would.
namespace {

using namespace noether::h5;

// A dataset of doubles with the checksum of its values (attribute "checksum").
void write_doubles(hid_t parent, const char* name, const double* data, std::vector<hsize_t> dims) {
  const io::H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  const io::H5Handle d(
      check_id(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name));
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  if (n) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), name);
  numeric_attribute<std::uint64_t>(d, "checksum", H5T_NATIVE_UINT64, {io::checksum64(data, n * sizeof(double))});
}


// Reads a dataset written by write_doubles, verifying its checksum when it has one (a
// checkpoint from an older noether has none).
std::vector<double> read_doubles(const std::filesystem::path& file, hid_t parent, const char* group, const char* name,
                                 std::size_t expected) {
  const io::H5Handle d = io::open_dataset(parent, name);
  if (!d.valid()) throw OutputError(std::string("the checkpoint has no ") + name);
  const io::H5Handle space(H5Dget_space(d));
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  if (n != expected)
    throw OutputError(std::string("the checkpoint's ") + name + " has " + std::to_string(n) + " numbers, the scene needs " +
                      std::to_string(expected));
  std::vector<double> out(n);
  const std::string where = std::string("/") + group + "/" + name;
  if (n && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    io::throw_damaged(file, where + " does not read");
  if (H5Aexists(d, "checksum") > 0 &&
      io::read_u64_attribute(d, "checksum") != io::checksum64(out.data(), n * sizeof(double)))
    io::throw_damaged(file, where + " does not match its checksum");
  return out;
}


double read_scalar(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) throw OutputError(std::string("the checkpoint has no attribute ") + name);
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t space = H5Aget_space(a);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(1, H5Sget_simple_extent_npoints(space))));
  H5Sclose(space);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  return v[0];
}

std::vector<double> read_vector(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) throw OutputError(std::string("the checkpoint has no attribute ") + name);
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t space = H5Aget_space(a);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Sclose(space);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  return v;
}

// The diagnostics as 13 numbers and back.
std::vector<double> pack(const Diagnostics& d) {
  return {d.kinetic_translational, d.kinetic_rotational, d.potential, d.energy, d.linear_momentum.x(),
          d.linear_momentum.y(), d.linear_momentum.z(), d.angular_momentum.x(), d.angular_momentum.y(),
          d.angular_momentum.z(), d.orthogonality_error};
}
Diagnostics unpack(const std::vector<double>& v) {
  if (v.size() != 11) throw OutputError("the checkpoint's diagnostics have the wrong size");
  Diagnostics d;
  d.kinetic_translational = v[0], d.kinetic_rotational = v[1], d.potential = v[2], d.energy = v[3];
  d.linear_momentum = Vec3(v[4], v[5], v[6]);
  d.angular_momentum = Vec3(v[7], v[8], v[9]);
  d.orthogonality_error = v[10];
  return d;
}

}  // namespace

void Simulation::save(const std::filesystem::path& path) const {
  const Impl& m = *impl_;
  if (m.scene.text.empty())
    throw Error("save: this simulation's scene has no text to save (it was not read from YAML)");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  // Built under a hidden name and renamed into place (io/safe_publish.hpp): a kill while saving
  // leaves the previous checkpoint; a link, or the simulation's own output file, is refused.
  std::vector<std::filesystem::path> own_output;
  if (m.options.output) own_output.push_back(*m.options.output);
  const int claimed = io::claim_output(path, true, own_output);
  const std::filesystem::path partial = io::partial_name(path);
  int lock = -1;
  hid_t file = -1;
  try {
    lock = io::create_partial(partial, path);
    file = H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, io::file_access(0));
    if (file < 0) throw OutputError("cannot create " + path.string() + system_reason());
    string_attribute(file, "format", "noether simulation checkpoint 1");
    numeric_attribute<int>(file, "custom_potential", H5T_NATIVE_INT, {m.custom_potential ? 1 : 0});
    hid_t g = make_group(file, "parameters");
    string_dataset(g, "scene", m.scene.text, "the scene file's text, as given");
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(m.scene.file, ec);
    const std::string scene_path = ec ? m.scene.file : absolute.string();
    string_attribute(g, "scene_path", scene_path);
    std::string overrides;
    for (const auto& o : m.scene.overrides) overrides += (overrides.empty() ? "" : "\n") + o;
    string_attribute(g, "overrides", overrides);
    numeric_attribute<std::uint64_t>(g, "checksum", H5T_NATIVE_UINT64,
                                     {io::scene_checksum(m.scene.text, scene_path, overrides, m.custom_potential)});
    H5Gclose(g);
    const State& st = m.state;
    const hsize_t nb = static_cast<hsize_t>(st.x.cols()), nr = st.R.size();
    g = make_group(file, "state");
    scalar_attribute(g, "t", st.t);
    write_doubles(g, "x", st.x.data(), {nb, 3});
    write_doubles(g, "p", st.p.data(), {nb, 3});
    std::vector<double> R;
    for (const auto& Rk : st.R)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R.push_back(Rk(r, c));
    write_doubles(g, "R", R.data(), {nr, 3, 3});
    write_doubles(g, "Pi", st.Pi.data(), {nr, 3});
    const std::vector<double> own = m.integrator->checkpoint();  // Integrator::checkpoint
    write_doubles(g, "integrator", own.data(), {own.size()});
    H5Gclose(g);
    g = make_group(file, "run");
    scalar_attribute(g, "t_origin", m.t_origin);
    scalar_attribute(g, "steps_before", static_cast<double>(m.steps_before));
    const WorkCounters w = m.work();
    numeric_attribute<double>(g, "work", H5T_NATIVE_DOUBLE,
                              {static_cast<double>(w.steps), static_cast<double>(w.potential_evaluations),
                               static_cast<double>(w.newton_iterations), static_cast<double>(w.rejected_steps)});
    scalar_attribute(g, "wall_seconds", m.wall_now());
    const RunSummary& s = m.summary;
    numeric_attribute<double>(g, "initial", H5T_NATIVE_DOUBLE, pack(s.initial));
    numeric_attribute<double>(g, "final", H5T_NATIVE_DOUBLE, pack(s.final));
    const auto [p_scale, L_scale] = m.observer->scales();
    numeric_attribute<double>(g, "statistics", H5T_NATIVE_DOUBLE,
                              {s.max_abs_energy_error, s.max_rel_linear_momentum_error, s.max_rel_angular_momentum_error,
                               s.max_orthogonality_error, s.conserves_linear_momentum ? 1.0 : 0.0,
                               s.conserves_angular_momentum ? 1.0 : 0.0, s.min_gap, s.min_gap_reach, s.min_distance,
                               s.t_of_min_distance, static_cast<double>(s.frames),
                               static_cast<double>(s.interpolated_frames), p_scale, L_scale});
    string_attribute(g, "min_gap_pair", s.min_gap_pair);
    string_attribute(g, "stop_reason", s.stop_reason);
    numeric_attribute<std::uint64_t>(g, "checksum", H5T_NATIVE_UINT64, {io::checksum_of_texts({&s.min_gap_pair, &s.stop_reason})});
    H5Gclose(g);
    check(H5Fclose(file), "closing the checkpoint");
    file = -1;
    io::publish_file(partial, path, claimed >= 0);
  } catch (...) {
    if (file >= 0) H5Fclose(file);
    if (lock >= 0) ::unlink(partial.c_str());
    if (lock >= 0) ::close(lock);
    if (claimed >= 0) ::close(claimed);
    throw;
  }
  ::close(lock);
  if (claimed >= 0) ::close(claimed);
}

namespace {

// What Simulation::save wrote, read back and verified.
struct SavedSimulation {
  Scene scene;  // its initial state is where the saved simulation stood
  std::vector<double> integrator, work, stats;
  double t_origin = 0.0, steps_before = 0.0, wall = 0.0;
  Diagnostics initial, final_;
  std::string min_gap_pair, stop_reason;
};

SavedSimulation read_saved_simulation(const std::filesystem::path& path, bool potential_given) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  const io::H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, io::file_access(0)));
  if (!file.valid())
    throw OutputError(path.string() + " is not an HDF5 file" + system_reason() +
                      " (or its first bytes, the HDF5 superblock, are damaged)");
  if (read_string(file, "format", false) != "noether simulation checkpoint 1")
    throw OutputError(path.string() + " is not a checkpoint saved by Simulation.save (an output file continues "
                                      "with `noether run --resume`)");
  const bool custom = read_scalar(file, "custom_potential") != 0;
  if (custom && !potential_given)
    throw Error(path.string() + " was saved from a simulation whose potential was given in code (a Python "
                                "function), not by the scene: pass the same potential to load it");
  // A checksum attribute, verified when the checkpoint has one (an older noether's has none).
  const auto verify = [&path](hid_t group, const char* where, std::uint64_t expected) {
    if (H5Aexists(group, "checksum") > 0 && io::read_u64_attribute(group, "checksum") != expected)
      io::throw_damaged(path, std::string(where) + " does not match its checksum");
  };
  const auto open_group = [&path, &file](const char* name) {
    io::H5Handle g(H5Gopen2(file, name, H5P_DEFAULT));
    if (!g.valid()) io::throw_damaged(path, std::string("/") + name + " does not open");
    return g;
  };
  SavedSimulation saved;
  {
    const io::H5Handle g = open_group("parameters");
    const std::string text = read_string(g, "scene", true), scene_path = read_string(g, "scene_path", false),
                      joined = read_string(g, "overrides", false);
    verify(g, "/parameters (the scene's text, its path or the overrides)",
           io::scene_checksum(text, scene_path, joined, custom));
    saved.scene = parse_scene(text, scene_path, lines_of(joined));
  }
  const std::size_t nb = saved.scene.system.size(), nr = saved.scene.system.rigid_count();
  State st = State::zeros(saved.scene.system);
  {
    const io::H5Handle g = open_group("state");
    st.t = read_scalar(g, "t");
    const auto x = read_doubles(path, g, "state", "x", 3 * nb), p = read_doubles(path, g, "state", "p", 3 * nb),
               R = read_doubles(path, g, "state", "R", 9 * nr), Pi = read_doubles(path, g, "state", "Pi", 3 * nr);
    std::size_t own_size = 0;
    if (const io::H5Handle own = io::open_dataset(g, "integrator"); own.valid()) {
      const io::H5Handle space(H5Dget_space(own));
      own_size = static_cast<std::size_t>(std::max<hssize_t>(0, H5Sget_simple_extent_npoints(space)));
    }
    saved.integrator = read_doubles(path, g, "state", "integrator", own_size);
    st.x = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, static_cast<Eigen::Index>(nb));
    st.p = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, static_cast<Eigen::Index>(nb));
    st.Pi = Eigen::Map<const Eigen::Matrix3Xd>(Pi.data(), 3, static_cast<Eigen::Index>(nr));
    for (std::size_t k = 0; k < nr; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) st.R[k](r, c) = R[9 * k + static_cast<std::size_t>(3 * r + c)];
  }
  saved.scene.initial = st;  // frame 0 of the loaded simulation is where the saved one stood
  {
    const io::H5Handle g = open_group("run");
    saved.t_origin = read_scalar(g, "t_origin");
    saved.steps_before = read_scalar(g, "steps_before");
    saved.wall = read_scalar(g, "wall_seconds");
    saved.work = read_vector(g, "work");
    saved.stats = read_vector(g, "statistics");
    saved.initial = unpack(read_vector(g, "initial"));
    saved.final_ = unpack(read_vector(g, "final"));
    saved.min_gap_pair = read_string(g, "min_gap_pair", false);
    saved.stop_reason = read_string(g, "stop_reason", false);
    verify(g, "/run's texts", io::checksum_of_texts({&saved.min_gap_pair, &saved.stop_reason}));
  }
  if (saved.work.size() != 4 || saved.stats.size() != 14) io::throw_damaged(path, "/run's work or statistics");
  return saved;
}

}  // namespace

std::unique_ptr<Simulation> Simulation::load(const std::filesystem::path& path, PluginRegistry& registry,
                                             RunOptions options, std::shared_ptr<const Potential> potential) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw OutputError(path.string() + ": no such file");
  SavedSimulation saved;
  try {  // read in a child first: a damaged file must not crash or hang this process (io/read_probe.hpp)
    const bool given = potential != nullptr;
    io::read_probe(path, [&path, given] { read_saved_simulation(path, given); }, io::read_probe_seconds(path),
                   options.interrupt);
    saved = read_saved_simulation(path, given);
  } catch (const OutputError& e) {  // every refusal names the file
    const std::string what = e.what();
    if (what.rfind(path.string(), 0) == 0) throw;
    throw OutputError(path.string() + ": " + what + " (a damaged checkpoint, or not one that Simulation.save wrote)");
  }
  const std::vector<double>& stats = saved.stats;
  const bool with_output = options.output.has_value();
  auto sim = std::make_unique<Simulation>(std::move(saved.scene), registry, options, std::move(potential));
  Impl& m = *sim->impl_;
  RunSummary& s = m.summary;
  if (!with_output) {  // the frame the constructor observed is the saved state's: not counted again
    s.initial = saved.initial;
    s.final = saved.final_;
    s.max_abs_energy_error = stats[0], s.max_rel_linear_momentum_error = stats[1];
    s.max_rel_angular_momentum_error = stats[2], s.max_orthogonality_error = stats[3];
    s.conserves_linear_momentum = stats[4] != 0, s.conserves_angular_momentum = stats[5] != 0;
    s.min_gap = stats[6], s.min_gap_reach = stats[7], s.min_distance = stats[8], s.t_of_min_distance = stats[9];
    s.frames = static_cast<std::size_t>(stats[10]);
    s.interpolated_frames = static_cast<std::int64_t>(stats[11]);
    m.observer->set_scales(stats[12], stats[13]);
    s.min_gap_pair = saved.min_gap_pair;
    s.stop_reason = saved.stop_reason;
  }
  const std::vector<double>& work = saved.work;
  m.t_origin = saved.t_origin;
  m.steps_before = static_cast<std::int64_t>(saved.steps_before);
  m.base_work = WorkCounters{static_cast<std::int64_t>(work[0]),
                             static_cast<std::int64_t>(work[1]) - m.integrator->work().potential_evaluations,
                             static_cast<std::int64_t>(work[2]), static_cast<std::int64_t>(work[3])};
  m.wall_seconds = saved.wall;
  // The integrator continues from its own variables where it has any, else from the state.
  if (saved.integrator.size() != m.integrator->checkpoint().size())
    throw OutputError(path.string() + ": its integrator checkpoint does not fit the scene's integrator");
  m.integrator->restore(m.state, saved.integrator);
  m.integrator_at_state = true;
  return sim;
}
}  // namespace noether
