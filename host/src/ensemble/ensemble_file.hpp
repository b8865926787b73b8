#pragma once
// EnsembleFile: the HDF5 file of `noether ensemble` (internal to libnoether; ensemble.cpp runs
// the samples and hands each result to it). docs/ensembles.md lists its layout.
#include <noether/ensemble.hpp>
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "io/h5.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/flush.hpp"
#include "io/h5.hpp"
#include "io/read_probe.hpp"
#include "io/safe_publish.hpp"
#include "run/summary_schema.hpp"

#include <spdlog/spdlog.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <csignal>

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

namespace noether::detail {

using namespace noether::io;

inline std::string override_of(const Variation& v, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  return v.key + "=" + buf;
}

// The /summary columns: the summary schema's ensemble rows (run/summary_schema.cpp), in order.
inline const std::vector<const SummaryRow*>& summary_columns() {
  static const std::vector<const SummaryRow*> rows = summary_rows_for(kEnsemble);
  return rows;
}

// The per-sample indicators of a scene's runs (/indicators/<name>), with their units, and their
// values from a run's summary in the same order (ensemble.cpp).
struct Indicator {
  std::string name, unit;
};
std::vector<Indicator> ensemble_indicators(const Scene& scene);
std::vector<double> indicator_values(const Scene& scene, const RunSummary& summary);
constexpr std::size_t kMessageBytes = 512;

// The ensemble file: fixed-size datasets allocated up front (a kill changes raw data only), one
// row per sample, /outcome written after the row (−1: not run).
class EnsembleFile {
 public:
  EnsembleFile(const std::filesystem::path& path, const Scene& scene, const std::string& scene_text,
               const std::vector<std::string>& overrides, const EnsembleOptions& options, std::size_t samples,
               std::size_t pair_a, std::size_t pair_b)
      : path_(path), samples_(samples), nb_(scene.system.size()), nr_(scene.system.rigid_count()),
        indicators_(ensemble_indicators(scene)) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
    std::error_code ec;
    const bool exists = std::filesystem::exists(path, ec);
    {
      std::ostringstream id;  // what makes two ensembles the same one
      id << scene_text << "\n--\n";
      for (const auto& o : overrides) id << o << "\n";
      for (const auto& v : options.vary) id << "vary " << v.text << "\n";
      id << "seed " << options.seed << "\nsamples " << samples << "\npair " << pair_a << "," << pair_b << "\n";
      identity_ = id.str();
    }
    if (exists && !options.resume && !options.overwrite)
      throw OutputError(path.string() + " exists: pass --resume to continue that ensemble, or --force to replace it");
    if (options.resume && exists) {
      // Every read made first in a child (io/read_probe.hpp): a damaged file must not crash or
      // hang this process; then the recorded outcomes, each verified against its checksum.
      io::read_probe(path, [&] { EnsembleFile::read_recorded(path, samples, identity_); },
                     io::read_probe_seconds(path));
      done_ = read_recorded(path, samples, identity_);
      file_ = io::H5Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, io::file_access(64 * 1024)));
      if (file_ < 0) throw OutputError("cannot open " + path.string() + " to resume it" + system_reason());
      lock_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);  // for io::flush_extended
      outcome_ = io::H5Handle(H5Dopen2(file_, "outcome", H5P_DEFAULT));
      checksum_ = io::H5Handle(H5Dopen2(file_, "outcome_checksum", H5P_DEFAULT));  // absent in an older noether's file
      for (const SummaryRow* column : summary_columns()) {  // a column renamed or added since the file was written
        std::string name = "summary/" + std::string(column->key);
        if (H5Lexists(file_, name.c_str(), H5P_DEFAULT) <= 0 && column->key == "closest_approach")
          name = "summary/min_distance";  // its name before the summary's schema (2026-11-28)
        if (H5Lexists(file_, name.c_str(), H5P_DEFAULT) <= 0)
          throw OutputError(path.string() + " was written by an older noether: its /summary has no " +
                            std::string(column->key) + " column; finish it with that version, or run it afresh with --force");
        summary_paths_.push_back(name);
      }
      return;
    }
    // Built under a hidden name and renamed into place once its layout is complete, so the path
    // holds either nothing (or the file --force replaces) or a whole layout, whenever a kill comes.
    // (io/safe_publish.hpp: a link, or another process writing the path, is refused.)
    const double needed = check_disk_space(path, options.vary.size());
    // SIGINT and SIGTERM wait while the layout is written (they end `noether ensemble` at once,
    // and a kill here would leave the hidden file, up to the size just checked, behind); they
    // are delivered once the file is published or removed, ending the process with a complete
    // layout that --resume continues.
    const SignalsHeld held;
    const int claimed = io::claim_output(path, true);
    const std::filesystem::path partial = io::partial_name(path);
    try {
      lock_ = io::create_partial(partial, path);
    } catch (...) {
      if (claimed >= 0) ::close(claimed);
      throw;
    }
    try {  // the file and its layout, published: on any failure (a full disk), the hidden file goes
      file_ = io::H5Handle(H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, io::file_creation(), io::file_access(64 * 1024)));
      if (file_ < 0) throw OutputError("cannot create " + path.string() + system_reason());
      // The space reserved first: a disk or a file-size limit too small for the layout fails
      // here, before HDF5 writes (HDF5 1.10 cannot close a file whose writes failed cleanly).
      if (const int err = ::posix_fallocate(lock_, 0, static_cast<off_t>(needed)))
        throw OutputError("cannot reserve " + std::to_string(static_cast<std::size_t>(needed)) +
                          " bytes for " + path.string() + ": " + std::strerror(err));
      string_attribute(file_, "identity", identity_);
      string_attribute(file_, "description",
                       "noether ensemble: one row per sample; outcome -1 not run, 0 completed, 1 stopped by an "
                       "event, 2 failed (message)");
      string_dataset(file_, "scene", scene_text, "the scene file's text");
      std::string joined;
      for (const auto& o : overrides) joined += (joined.empty() ? "" : "\n") + o;
      string_attribute(file_, "overrides", joined);
      numeric_attribute<std::uint64_t>(file_, "seed", H5T_NATIVE_UINT64, {options.seed});
      string_attribute(file_, "units", scene.units.describe());
      string_attribute(file_, "pair", scene.system.body(pair_a).name + "," + scene.system.body(pair_b).name);
      const io::H5Handle inputs(make_group(file_, "inputs"));
      for (const auto& v : options.vary) {
        const io::H5Handle d = create(inputs, v.key.c_str(), H5T_NATIVE_DOUBLE, {});
        string_attribute(d, "distribution", v.text);
      }
      outcome_ = create(file_, "outcome", H5T_NATIVE_INT8, {});
      string_attribute(outcome_, "description", "-1 not run, 0 completed, 1 stopped by an event, 2 failed");
      checksum_ = create(file_, "outcome_checksum", H5T_NATIVE_UINT64, {});
      string_attribute(checksum_, "description",
                       "checksum64 of each sample's outcome byte, seeded with its index (0: not written); "
                       "`noether ensemble --resume` verifies every outcome it reads");
      const io::H5Handle message_type(H5Tcopy(H5T_C_S1));
      H5Tset_size(message_type, kMessageBytes);
      create(file_, "message", message_type, {});
      // Each series with its unit, in the scene's units (as `noether run`'s output).
      const Units& u = scene.units;
      auto with_unit = [](io::H5Handle d, const std::string& unit) {
        string_attribute(d, "unit", unit);
        return d;
      };
      const io::H5Handle summary(make_group(file_, "summary"));
      for (const SummaryRow* column : summary_columns()) {
        with_unit(create(summary, std::string(column->key).c_str(), H5T_NATIVE_DOUBLE, {}), io::unit_of(column->dimension, u));
        summary_paths_.push_back("summary/" + std::string(column->key));
      }
      if (!indicators_.empty()) {
        const io::H5Handle group(make_group(file_, "indicators"));
        string_attribute(group, "description",
                         "each sample's indicators at its end: with run.chaos MEGNO <Y>, the FLI, ln|delta|/t "
                         "(docs/derivatives.md); for each rigid body its spin state, <body>.libration_amplitude, "
                         ".libration_period, .turns, .max_pitch, .max_roll (one of the binary), .max_nutation and "
                         ".spin_period (docs/user-guide.md, \"Spin state\")");
        for (const auto& indicator : indicators_)
          with_unit(create(group, indicator.name.c_str(), H5T_NATIVE_DOUBLE, {}), indicator.unit);
      }
      const io::H5Handle fin(make_group(file_, "final"));
      with_unit(create(fin, "positions", H5T_NATIVE_DOUBLE, {nb_, 3}), u.of_length());
      with_unit(create(fin, "momenta", H5T_NATIVE_DOUBLE, {nb_, 3}), u.of_momentum());
      if (nr_ > 0) {
        with_unit(create(fin, "attitudes", H5T_NATIVE_DOUBLE, {nr_, 3, 3}), "1");
        with_unit(create(fin, "angular_momenta", H5T_NATIVE_DOUBLE, {nr_, 3}), u.of_angular_momentum());
      }
      const io::H5Handle orbit(make_group(file_, "orbit"));
      string_attribute(orbit, "description",
                       "the pair's osculating mutual orbit at the end: semi-major axis, eccentricity, period "
                       "(NaN when unbound)");
      with_unit(create(orbit, "a", H5T_NATIVE_DOUBLE, {}), u.of_length());
      with_unit(create(orbit, "e", H5T_NATIVE_DOUBLE, {}), "1");
      with_unit(create(orbit, "period", H5T_NATIVE_DOUBLE, {}), u.of_time());
      const io::H5Handle timing(make_group(file_, "timing"));
      string_attribute(timing, "description", "wall times: not results, they differ from run to run");
      with_unit(create(timing, "wall_seconds", H5T_NATIVE_DOUBLE, {}), "s");
      with_unit(create(timing, "setup_seconds", H5T_NATIVE_DOUBLE, {}), "s");
      const io::H5Handle trust = create(file_, "trustworthy", H5T_NATIVE_INT8, {});
      string_attribute(trust, "description", "the run's verdict against run.trust: 1 trustworthy, 0 not (why: message), "
                                             "-1 not run or failed");
      io::flush_extended(file_, lock_, "flushing the ensemble file");
      io::publish_file(partial, path, claimed >= 0);
    } catch (...) {
      checksum_.reset();
      outcome_.reset();
      file_.reset();
      ::close(lock_);
      lock_ = -1;
      std::filesystem::remove(partial, ec);
      if (claimed >= 0) ::close(claimed);
      throw;
    }
    if (claimed >= 0) ::close(claimed);
    done_.assign(samples, -1);
  }
  ~EnsembleFile() {
    checksum_.reset();  // the datasets, then the file, then its lock
    outcome_.reset();
    file_.reset();
    if (lock_ >= 0) {
      io::trim_extension(path_, lock_);
      ::close(lock_);
    }
  }
  bool done(std::size_t i) const { return done_[i] >= 0; }

  // The row of sample i, then (after a flush) its outcome.
  void write(std::size_t i, const std::vector<double>& inputs, const std::vector<Variation>& vary,
             const SampleResult& r) {
    for (std::size_t k = 0; k < vary.size(); ++k) put(("inputs/" + vary[k].key).c_str(), i, &inputs[k], 1);
    char message[kMessageBytes] = {};
    std::strncpy(message, r.message.c_str(), kMessageBytes - 1);
    const io::H5Handle type(H5Tcopy(H5T_C_S1));
    H5Tset_size(type, kMessageBytes);
    put("message", i, message, 1, type);
    for (std::size_t k = 0; k < summary_paths_.size(); ++k) put(summary_paths_[k].c_str(), i, &r.summary[k], 1);
    if (r.final_state.x.cols() > 0) {
      put("final/positions", i, r.final_state.x.data(), 3 * nb_);
      put("final/momenta", i, r.final_state.p.data(), 3 * nb_);
      if (nr_ > 0) {
        std::vector<double> R;
        for (const auto& Rk : r.final_state.R)
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) R.push_back(Rk(a, b));
        put("final/attitudes", i, R.data(), 9 * nr_);
        put("final/angular_momenta", i, r.final_state.Pi.data(), 3 * nr_);
      }
    }
    for (std::size_t k = 0; k < indicators_.size() && k < r.indicators.size(); ++k)
      put(("indicators/" + indicators_[k].name).c_str(), i, &r.indicators[k], 1);
    put("orbit/a", i, &r.a, 1);
    put("orbit/e", i, &r.e, 1);
    put("orbit/period", i, &r.period, 1);
    put("trustworthy", i, &r.trustworthy, 1, H5T_NATIVE_INT8);
    put("timing/wall_seconds", i, &r.wall, 1);
    put("timing/setup_seconds", i, &r.setup, 1);
    pending_.push_back({i, r.outcome});
  }
  // Flushes the rows, then writes their outcomes and flushes again: a kill leaves every
  // sample with an outcome complete.
  void commit() {
    if (pending_.empty()) return;
    io::flush_extended(file_, lock_, "flushing the ensemble file");
    for (const auto& [i, outcome] : pending_) {
      put_id(outcome_, i, &outcome, 1, H5T_NATIVE_INT8);
      if (checksum_ >= 0) {
        const std::uint64_t sum = outcome_checksum(i, outcome);
        put_id(checksum_, i, &sum, 1, H5T_NATIVE_UINT64);
      }
      done_[i] = outcome;
    }
    pending_.clear();
    io::flush_extended(file_, lock_, "flushing the ensemble file");
  }

 private:
  // Blocks SIGINT and SIGTERM in this thread for its lifetime (pending ones arrive at the end).
  struct SignalsHeld {
    sigset_t old{};
    SignalsHeld() {
      sigset_t stop;
      sigemptyset(&stop);
      sigaddset(&stop, SIGINT);
      sigaddset(&stop, SIGTERM);
      pthread_sigmask(SIG_BLOCK, &stop, &old);
    }
    ~SignalsHeld() { pthread_sigmask(SIG_SETMASK, &old, nullptr); }
    SignalsHeld(const SignalsHeld&) = delete;
    SignalsHeld& operator=(const SignalsHeld&) = delete;
  };

  // The datasets are allocated whole when the file is created (one row per sample): refuse an
  // ensemble whose file would not fit on its disk, before writing anything.
  // Returns the bytes the datasets take.
  double check_disk_space(const std::filesystem::path& path, std::size_t varied) const {
    const double row = 1.0 + 8.0 + kMessageBytes + 8.0 * (static_cast<double>(summary_columns().size()) + indicators_.size() + 6.0 * nb_ + 12.0 * nr_ + 3 + 2 + varied) + 1.0;
    const double needed = row * static_cast<double>(samples_);
    std::filesystem::path folder = path.parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    const auto space = std::filesystem::space(folder, ec);
    if (ec) return needed;  // cannot tell: the reservation reports it
    if (needed > 0.98 * static_cast<double>(space.available)) {
      std::ostringstream msg;
      msg.precision(3);
      msg << "the ensemble file for " << samples_ << " samples needs " << needed / 1e9 << " GB ("
          << static_cast<std::size_t>(row) << " bytes per sample, allocated when it is created); "
          << folder.string() << " has " << static_cast<double>(space.available) / 1e9
          << " GB free: use fewer samples (--samples, or coarser grids) or another disk";
      throw OutputError(msg.str());
    }
    return needed;
  }

  static std::uint64_t outcome_checksum(std::size_t i, std::int8_t outcome) {
    return io::checksum64(&outcome, 1, i) | 1;  // never 0, the fill of a row not written
  }
  // The outcomes recorded in an ensemble file of this identity, verified: a row whose checksum
  // is 0 was not committed (a kill between the outcome and its checksum) and runs again; any
  // other mismatch is damage, refused by sample.
  static std::vector<std::int8_t> read_recorded(const std::filesystem::path& path, std::size_t samples,
                                                const std::string& identity) {
    const io::H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, io::file_access(0)));
    if (!file.valid()) throw OutputError("cannot open " + path.string() + " to resume it" + system_reason());
    if (read_string(file, "identity", false) != identity)
      throw OutputError(path.string() + " holds another ensemble (scene, overrides, --vary, --seed, --samples or "
                                        "--pair differ), or its identity is damaged; resume it with the command "
                                        "that made it");
    std::vector<std::int8_t> outcome(samples, -1);
    const io::H5Handle d = io::open_dataset(file, "/outcome");
    if (!d.valid() || H5Dread(d, H5T_NATIVE_INT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, outcome.data()) < 0)
      io::throw_damaged(path, "/outcome does not read");
    const io::H5Handle sums_dataset = io::open_dataset(file, "/outcome_checksum");
    if (!sums_dataset.valid()) {
      spdlog::warn("{} was written by a noether without checksums: its outcomes are read unverified", path.string());
      return outcome;
    }
    std::vector<std::uint64_t> sums(samples, 0);
    if (H5Dread(sums_dataset, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, sums.data()) < 0)
      io::throw_damaged(path, "/outcome_checksum does not read");
    for (std::size_t i = 0; i < samples; ++i) {
      if (sums[i] == 0) {  // never committed: run it (again)
        outcome[i] = -1;
        continue;
      }
      if (outcome[i] < 0 || outcome[i] > 2 || sums[i] != outcome_checksum(i, outcome[i]))
        io::throw_damaged(path, "the outcome of sample " + std::to_string(i) + " does not match its checksum");
    }
    return outcome;
  }

  io::H5Handle create(hid_t parent, const char* name, hid_t type, std::vector<hsize_t> shape) {
    std::vector<hsize_t> dims{samples_};
    dims.insert(dims.end(), shape.begin(), shape.end());
    const io::H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
    const io::H5Handle plist(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_time(plist, H5D_FILL_TIME_ALLOC);
    if (H5Tequal(type, H5T_NATIVE_DOUBLE) > 0) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      H5Pset_fill_value(plist, type, &nan);
    } else if (H5Tequal(type, H5T_NATIVE_INT8) > 0) {
      const std::int8_t none = -1;
      H5Pset_fill_value(plist, type, &none);
    }
    return io::H5Handle(check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT), name));
  }
  void put(const char* path, std::size_t i, const void* data, std::size_t count, hid_t type = H5T_NATIVE_DOUBLE) {
    const io::H5Handle d(check_id(H5Dopen2(file_, path, H5P_DEFAULT), path));
    put_id(d, i, data, count, type);
  }
  void put_id(hid_t d, std::size_t i, const void* data, std::size_t count, hid_t type) {
    const io::H5Handle space(H5Dget_space(d));
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), start(dims.size(), 0);
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    start[0] = i;
    dims[0] = 1;
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr);
    const hsize_t n = count;
    const io::H5Handle mem(H5Screate_simple(1, &n, nullptr));
    check(H5Dwrite(d, type, mem, space, H5P_DEFAULT, data), "writing a sample");
  }

  io::H5Handle file_, outcome_, checksum_;
  std::filesystem::path path_;
  int lock_ = -1;  // the new file's lock (io::create_partial), held while it is written
  hsize_t samples_;
  hsize_t nb_, nr_;
  std::string identity_;
  std::vector<std::string> summary_paths_;  // each summary column's dataset, in summary_columns()' order
  std::vector<std::int8_t> done_;
  std::vector<std::pair<std::size_t, std::int8_t>> pending_;
  std::vector<Indicator> indicators_;
};

}  // namespace noether::detail
