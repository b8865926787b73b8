// Ensembles (docs/ensembles.md): samples drawn from (seed, index), run on a pool of threads, each
// result written at its index by the main thread.
#include <noether/ensemble.hpp>
#include <noether/error.hpp>
#include <noether/orbital_elements.hpp>
#include <noether/simulation.hpp>

#include "h5_helpers.hpp"
#include "io/file_access.hpp"
#include "io/safe_publish.hpp"

#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fcntl.h>
#include <mutex>
#include <sstream>
#include <sys/file.h>
#include <thread>
#include <unistd.h>

namespace noether {

namespace {

using Clock = std::chrono::steady_clock;
using namespace noether::h5;

double number(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  while (used < text.size() && std::isspace(static_cast<unsigned char>(text[used]))) ++used;
  if (used != text.size() || text.empty() || !std::isfinite(v))
    throw SceneError(where + ": '" + text + "' is not a finite number");
  return v;
}

// splitmix64: a stateless, portable hash of (seed, index, k) to 64 random bits.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
// A uniform double in (0, 1) from (seed, index, stream): 53 bits, never 0.
double uniform01(std::uint64_t seed, std::uint64_t index, std::uint64_t stream) {
  const std::uint64_t bits = mix(mix(mix(seed) ^ index) ^ (stream * 0x632be59bd9b4e019ULL));
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1p-53;
}

}  // namespace

Variation parse_variation(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--vary '" + text + "': expected KEY=DISTRIBUTION, e.g. bodies.beta.mass=normal(1, 0.01)");
  Variation v;
  v.key = text.substr(0, eq);
  v.text = text;
  const std::string spec = text.substr(eq + 1);
  const auto open = spec.find('('), close = spec.rfind(')');
  const std::string where = "--vary " + v.key;
  if (open == std::string::npos || close == std::string::npos || close < open || close + 1 != spec.size())
    throw SceneError(where + ": '" + spec +
                     "' is not a distribution: normal(mean, sd), uniform(a, b), log-uniform(a, b), list(v1, ...), "
                     "grid(a, b, n)");
  const std::string name = spec.substr(0, open);
  std::vector<std::string> parts;
  {
    std::stringstream ss(spec.substr(open + 1, close - open - 1));
    for (std::string part; std::getline(ss, part, ',');) {
      const auto a = part.find_first_not_of(" \t"), b = part.find_last_not_of(" \t");
      parts.push_back(a == std::string::npos ? std::string() : part.substr(a, b - a + 1));
    }
  }
  for (const auto& p : parts) v.args.push_back(number(p, where));
  auto need = [&](std::size_t n, const char* form) {
    if (v.args.size() != n) throw SceneError(where + ": " + name + " takes " + form + ", not '" + spec + "'");
  };
  if (name == "normal") {
    v.kind = Variation::Kind::Normal;
    need(2, "(mean, sd)");
    if (!(v.args[1] >= 0)) throw SceneError(where + ": normal's standard deviation must be ≥ 0");
  } else if (name == "uniform") {
    v.kind = Variation::Kind::Uniform;
    need(2, "(a, b)");
    if (!(v.args[0] < v.args[1])) throw SceneError(where + ": uniform(a, b) needs a < b");
  } else if (name == "log-uniform") {
    v.kind = Variation::Kind::LogUniform;
    need(2, "(a, b)");
    if (!(v.args[0] > 0 && v.args[0] < v.args[1])) throw SceneError(where + ": log-uniform(a, b) needs 0 < a < b");
  } else if (name == "list") {
    v.kind = Variation::Kind::List;
    if (v.args.empty()) throw SceneError(where + ": list() needs at least one value");
  } else if (name == "grid") {
    v.kind = Variation::Kind::Grid;
    need(3, "(a, b, n)");
    if (!(v.args[2] >= 1 && v.args[2] == std::floor(v.args[2]) && v.args[2] <= 1e9))
      throw SceneError(where + ": grid(a, b, n) needs a whole n ≥ 1");
    if (v.args[2] > 1 && !(v.args[0] < v.args[1])) throw SceneError(where + ": grid(a, b, n) needs a < b");
  } else {
    throw SceneError(where + ": unknown distribution '" + name +
                     "' (normal, uniform, log-uniform, list, grid)");
  }
  return v;
}

std::size_t grid_size(const std::vector<Variation>& vary) {
  std::size_t n = 1;
  for (const auto& v : vary)
    if (v.kind == Variation::Kind::Grid) n *= static_cast<std::size_t>(v.args[2]);
  return n;
}

std::vector<double> sample_values(const std::vector<Variation>& vary, std::uint64_t seed, std::size_t index) {
  std::vector<double> out;
  // Grids: the index in mixed radix, the first grid the slowest digit.
  std::size_t stride = grid_size(vary);
  for (std::size_t k = 0; k < vary.size(); ++k) {
    const Variation& v = vary[k];
    const double u1 = uniform01(seed, index, 2 * k), u2 = uniform01(seed, index, 2 * k + 1);
    switch (v.kind) {
      case Variation::Kind::Normal:  // Box–Muller
        out.push_back(v.args[0] + v.args[1] * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
        break;
      case Variation::Kind::Uniform:
        out.push_back(v.args[0] + (v.args[1] - v.args[0]) * u1);
        break;
      case Variation::Kind::LogUniform:
        out.push_back(std::exp(std::log(v.args[0]) + (std::log(v.args[1]) - std::log(v.args[0])) * u1));
        break;
      case Variation::Kind::List:
        out.push_back(v.args[std::min(v.args.size() - 1, static_cast<std::size_t>(u1 * static_cast<double>(v.args.size())))]);
        break;
      case Variation::Kind::Grid: {
        const auto n = static_cast<std::size_t>(v.args[2]);
        stride /= n;
        const std::size_t digit = (index / stride) % n;
        out.push_back(n == 1 ? v.args[0] : v.args[0] + (v.args[1] - v.args[0]) * static_cast<double>(digit) /
                                                           static_cast<double>(n - 1));
        break;
      }
    }
  }
  return out;
}

namespace {

std::string override_of(const Variation& v, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  return v.key + "=" + buf;
}

const char* const kSummary[] = {"final_time",   "max_abs_energy_error", "max_rel_energy_error",
                                "max_rel_angular_momentum_error", "min_distance", "steps",
                                "potential_evaluations"};
constexpr std::size_t kSummaryCount = sizeof kSummary / sizeof kSummary[0];
constexpr std::size_t kMessageBytes = 512;

// The ensemble file: fixed-size datasets allocated up front (a kill changes raw data only), one
// row per sample, /outcome written after the row (−1: not run).
class EnsembleFile {
 public:
  EnsembleFile(const std::filesystem::path& path, const Scene& scene, const std::string& scene_text,
               const std::vector<std::string>& overrides, const EnsembleOptions& options, std::size_t samples,
               std::size_t pair_a, std::size_t pair_b)
      : samples_(samples), nb_(scene.system.size()), nr_(scene.system.rigid_count()) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
    std::error_code ec;
    const bool exists = std::filesystem::exists(path, ec);
    std::string recorded;
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
      file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      if (file_ < 0) throw OutputError("cannot open " + path.string() + " to resume it" + system_reason());
      recorded = read_string(file_, "identity", false);
      if (recorded != identity_) {
        H5Fclose(file_);
        throw OutputError(path.string() + " holds another ensemble (scene, overrides, --vary, --seed, --samples or "
                                          "--pair differ); resume it with the command that made it");
      }
      outcome_ = H5Dopen2(file_, "outcome", H5P_DEFAULT);
      done_.assign(samples, -1);
      H5Dread(outcome_, H5T_NATIVE_INT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, done_.data());
      return;
    }
    // Built under a hidden name and renamed into place once its layout is complete, so the path
    // holds either nothing (or the file --force replaces) or a whole layout, whenever a kill comes.
    // (io/safe_publish.hpp: a link, or another process writing the path, is refused.)
    const int claimed = io::claim_output(path, true);
    const std::filesystem::path partial = io::partial_name(path);
    try {
      lock_ = io::create_partial(partial, path);
    } catch (...) {
      if (claimed >= 0) ::close(claimed);
      throw;
    }
    file_ = H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, io::file_access(64 * 1024));
    if (file_ < 0) {
      if (claimed >= 0) ::close(claimed);
      ::close(lock_);
      lock_ = -1;
      std::filesystem::remove(partial, ec);
      throw OutputError("cannot create " + path.string() + system_reason());
    }
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
    hid_t inputs = make_group(file_, "inputs");
    for (const auto& v : options.vary) {
      hid_t d = create(inputs, v.key.c_str(), H5T_NATIVE_DOUBLE, {});
      string_attribute(d, "distribution", v.text);
      H5Dclose(d);
    }
    H5Gclose(inputs);
    outcome_ = create(file_, "outcome", H5T_NATIVE_INT8, {});
    string_attribute(outcome_, "description", "-1 not run, 0 completed, 1 stopped by an event, 2 failed");
    hid_t message_type = H5Tcopy(H5T_C_S1);
    H5Tset_size(message_type, kMessageBytes);
    H5Dclose(create(file_, "message", message_type, {}));
    H5Tclose(message_type);
    hid_t summary = make_group(file_, "summary");
    for (const char* name : kSummary) H5Dclose(create(summary, name, H5T_NATIVE_DOUBLE, {}));
    H5Gclose(summary);
    hid_t fin = make_group(file_, "final");
    H5Dclose(create(fin, "positions", H5T_NATIVE_DOUBLE, {nb_, 3}));
    H5Dclose(create(fin, "momenta", H5T_NATIVE_DOUBLE, {nb_, 3}));
    if (nr_ > 0) {
      H5Dclose(create(fin, "attitudes", H5T_NATIVE_DOUBLE, {nr_, 3, 3}));
      H5Dclose(create(fin, "angular_momenta", H5T_NATIVE_DOUBLE, {nr_, 3}));
    }
    H5Gclose(fin);
    hid_t orbit = make_group(file_, "orbit");
    string_attribute(orbit, "description",
                     "the pair's osculating mutual orbit at the end: semi-major axis, eccentricity, period "
                     "(NaN when unbound)");
    for (const char* name : {"a", "e", "period"}) H5Dclose(create(orbit, name, H5T_NATIVE_DOUBLE, {}));
    H5Gclose(orbit);
    hid_t timing = make_group(file_, "timing");
    string_attribute(timing, "description", "wall times: not results, they differ from run to run");
    H5Dclose(create(timing, "wall_seconds", H5T_NATIVE_DOUBLE, {}));
    H5Dclose(create(timing, "setup_seconds", H5T_NATIVE_DOUBLE, {}));
    hid_t trust = create(file_, "trustworthy", H5T_NATIVE_INT8, {});
    string_attribute(trust, "description", "the run's verdict against run.trust: 1 trustworthy, 0 not (why: message), "
                                           "-1 not run or failed");
    H5Dclose(trust);
    H5Gclose(timing);
    check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing the ensemble file");
    try {
      io::publish_file(partial, path, claimed >= 0);
    } catch (...) {
      H5Fclose(file_);
      file_ = -1;
      std::filesystem::remove(partial, ec);
      if (claimed >= 0) ::close(claimed);
      throw;
    }
    if (claimed >= 0) ::close(claimed);
    done_.assign(samples, -1);
  }
  ~EnsembleFile() {
    if (outcome_ >= 0) H5Dclose(outcome_);
    if (file_ >= 0) H5Fclose(file_);
    if (lock_ >= 0) ::close(lock_);
  }
  bool done(std::size_t i) const { return done_[i] >= 0; }

  // The row of sample i, then (after a flush) its outcome.
  void write(std::size_t i, const std::vector<double>& inputs, const std::vector<Variation>& vary,
             const SampleResult& r) {
    for (std::size_t k = 0; k < vary.size(); ++k) put(("inputs/" + vary[k].key).c_str(), i, &inputs[k], 1);
    char message[kMessageBytes] = {};
    std::strncpy(message, r.message.c_str(), kMessageBytes - 1);
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, kMessageBytes);
    put("message", i, message, 1, type);
    H5Tclose(type);
    for (std::size_t k = 0; k < kSummaryCount; ++k)
      put((std::string("summary/") + kSummary[k]).c_str(), i, &r.summary[k], 1);
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
    check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing the ensemble file");
    for (const auto& [i, outcome] : pending_) {
      put_id(outcome_, i, &outcome, 1, H5T_NATIVE_INT8);
      done_[i] = outcome;
    }
    pending_.clear();
    check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing the ensemble file");
  }

 private:
  hid_t create(hid_t parent, const char* name, hid_t type, std::vector<hsize_t> shape) {
    std::vector<hsize_t> dims{samples_};
    dims.insert(dims.end(), shape.begin(), shape.end());
    hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_time(plist, H5D_FILL_TIME_ALLOC);
    if (H5Tequal(type, H5T_NATIVE_DOUBLE) > 0) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      H5Pset_fill_value(plist, type, &nan);
    } else if (H5Tequal(type, H5T_NATIVE_INT8) > 0) {
      const std::int8_t none = -1;
      H5Pset_fill_value(plist, type, &none);
    }
    hid_t d = check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT), name);
    H5Pclose(plist);
    H5Sclose(space);
    return d;
  }
  void put(const char* path, std::size_t i, const void* data, std::size_t count, hid_t type = H5T_NATIVE_DOUBLE) {
    hid_t d = check_id(H5Dopen2(file_, path, H5P_DEFAULT), path);
    put_id(d, i, data, count, type);
    H5Dclose(d);
  }
  void put_id(hid_t d, std::size_t i, const void* data, std::size_t count, hid_t type) {
    hid_t space = H5Dget_space(d);
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), start(dims.size(), 0);
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    start[0] = i;
    dims[0] = 1;
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr);
    const hsize_t n = count;
    hid_t mem = H5Screate_simple(1, &n, nullptr);
    check(H5Dwrite(d, type, mem, space, H5P_DEFAULT, data), "writing a sample");
    H5Sclose(mem);
    H5Sclose(space);
  }

  hid_t file_ = -1, outcome_ = -1;
  int lock_ = -1;  // the new file's lock (io::create_partial), held while it is written
  hsize_t samples_;
  hsize_t nb_, nr_;
  std::string identity_;
  std::vector<std::int8_t> done_;
  std::vector<std::pair<std::size_t, std::int8_t>> pending_;
};

}  // namespace

EnsemblePlan::EnsemblePlan(const std::filesystem::path& scene_file, std::vector<std::string> overrides_given,
                           EnsembleOptions options_given)
    : overrides(std::move(overrides_given)), options(std::move(options_given)) {
  if (options.vary.empty()) throw SceneError("ensemble: nothing varies; give at least one --vary KEY=DISTRIBUTION");
  const std::size_t grid = grid_size(options.vary);
  samples = options.samples;
  const bool has_grid = std::any_of(options.vary.begin(), options.vary.end(),
                                    [](const Variation& v) { return v.kind == Variation::Kind::Grid; });
  if (samples == 0) {
    if (!has_grid) throw SceneError("ensemble: --samples N is needed (only grids give their own number of samples)");
    samples = grid;
  }
  if (has_grid && samples % grid != 0)
    throw SceneError("ensemble: --samples " + std::to_string(samples) + " is not a multiple of the grids' " +
                     std::to_string(grid) + " points");
  // The scene and every key checked before anything runs: sample 0's scene is built.
  base = load_scene(scene_file, overrides);
  (void)parse_scene(base.text, base.file, sample_overrides(0));
  if (!options.pair.empty()) {
    const auto comma = options.pair.find(',');
    if (comma == std::string::npos) throw SceneError("--pair '" + options.pair + "': expected two body names, a,b");
    auto find = [&](const std::string& name) {
      for (std::size_t i = 0; i < base.system.size(); ++i)
        if (base.system.body(i).name == name) return i;
      throw SceneError("--pair: the scene has no body '" + name + "'");
    };
    pair_a = find(options.pair.substr(0, comma));
    pair_b = find(options.pair.substr(comma + 1));
  } else if (base.system.size() < 2) {
    pair_b = 0;
  }
}

std::vector<std::string> EnsemblePlan::sample_overrides(std::size_t i) const {
  std::vector<std::string> out = overrides;
  const auto values = sample_values(options.vary, options.seed, i);
  for (std::size_t k = 0; k < options.vary.size(); ++k) out.push_back(override_of(options.vary[k], values[k]));
  return out;
}

SampleResult EnsemblePlan::run(std::size_t i, PluginRegistry& registry, const std::filesystem::path& output) const {
  SampleResult r;
  r.summary.assign(kSummaryCount, NAN);
  const auto t0 = Clock::now();
  try {
    RunOptions run;
    if (i < options.trajectories) {
      run.output = output.parent_path() / (output.stem().string() + "-sample-" + std::to_string(i) + ".h5");
      run.overwrite = true;
    }
    Simulation sim(parse_scene(base.text, base.file, sample_overrides(i)), registry, run);
    r.setup = std::chrono::duration<double>(Clock::now() - t0).count();
    try {
      sim.integrate(sim.scene().run.t_end);
    } catch (const IntegrationError& e) {
      r.outcome = 2;
      r.message = e.what();
    }
    const RunSummary s = sim.finish();
    if (r.outcome < 0) {
      r.outcome = s.stop_reason.empty() ? 0 : 1;
      r.message = s.stop_reason;
    }
    // A sample that finished but cannot be trusted (run.trust) says so, as `noether run` does.
    r.trustworthy = r.outcome == 2 ? -1 : s.verdict.trustworthy ? 1 : 0;
    if (r.trustworthy == 0) {
      std::string reasons;
      for (const auto& why : s.verdict.reasons) reasons += (reasons.empty() ? "" : "; ") + why;
      r.message += (r.message.empty() ? "" : "; ") + ("untrustworthy: " + reasons);
    }
    r.summary = {s.final_state.t, s.max_abs_energy_error, s.max_rel_energy_error, s.max_rel_angular_momentum_error,
                 s.min_distance, static_cast<double>(s.work.steps), static_cast<double>(s.work.potential_evaluations)};
    r.final_state = s.final_state;
    if (pair_a != pair_b) {
      const System& sys = sim.scene().system;
      const auto A = static_cast<Eigen::Index>(pair_a), B = static_cast<Eigen::Index>(pair_b);
      const double ma = sys.body(pair_a).mass, mb = sys.body(pair_b).mass, mu = sys.G() * (ma + mb);
      const RelativeState rel{s.final_state.x.col(B) - s.final_state.x.col(A),
                              s.final_state.p.col(B) / mb - s.final_state.p.col(A) / ma};
      try {
        const OrbitalElements el = elements_from_state(rel, mu);
        r.a = el.a, r.e = el.e, r.period = 2 * M_PI * std::sqrt(el.a * el.a * el.a / mu);
      } catch (const std::domain_error&) {  // unbound: NaN
      }
    }
  } catch (const Error& e) {  // a sample's scene or plugin refused: recorded, the rest go on
    r.outcome = 2;
    r.message = e.what();
  } catch (const std::exception& e) {
    r.outcome = 2;
    r.message = std::string("unexpected error: ") + e.what();
  }
  r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

std::vector<double> SampleResult::pack() const {
  std::vector<double> out{static_cast<double>(outcome), static_cast<double>(trustworthy), a, e, period, wall, setup};
  out.insert(out.end(), summary.begin(), summary.end());
  out.push_back(static_cast<double>(final_state.x.cols()));
  out.push_back(static_cast<double>(final_state.R.size()));
  out.push_back(final_state.t);
  out.insert(out.end(), final_state.x.data(), final_state.x.data() + final_state.x.size());
  out.insert(out.end(), final_state.p.data(), final_state.p.data() + final_state.p.size());
  for (const auto& R : final_state.R) out.insert(out.end(), R.data(), R.data() + 9);
  out.insert(out.end(), final_state.Pi.data(), final_state.Pi.data() + final_state.Pi.size());
  return out;
}

SampleResult SampleResult::unpack(const std::vector<double>& in, std::string message) {
  SampleResult r;
  std::size_t k = 0;
  auto next = [&] {
    if (k >= in.size()) throw Error("ensemble: a sample's result arrived truncated");
    return in[k++];
  };
  r.outcome = static_cast<std::int8_t>(next());
  r.trustworthy = static_cast<std::int8_t>(next());
  r.a = next(), r.e = next(), r.period = next(), r.wall = next(), r.setup = next();
  for (std::size_t j = 0; j < kSummaryCount; ++j) r.summary.push_back(next());
  const auto nb = static_cast<Eigen::Index>(next()), nr = static_cast<Eigen::Index>(next());
  r.final_state.t = next();
  r.final_state.x.resize(3, nb);
  r.final_state.p.resize(3, nb);
  r.final_state.Pi.resize(3, nr);
  for (Eigen::Index j = 0; j < 3 * nb; ++j) r.final_state.x.data()[j] = next();
  for (Eigen::Index j = 0; j < 3 * nb; ++j) r.final_state.p.data()[j] = next();
  r.final_state.R.resize(static_cast<std::size_t>(nr));
  for (auto& R : r.final_state.R)
    for (int j = 0; j < 9; ++j) R.data()[j] = next();
  for (Eigen::Index j = 0; j < 3 * nr; ++j) r.final_state.Pi.data()[j] = next();
  r.message = std::move(message);
  return r;
}

EnsembleReport run_ensemble(const std::filesystem::path& scene_file, const std::vector<std::string>& overrides,
                            const EnsembleOptions& options, const std::filesystem::path& output,
                            const std::function<void(std::size_t, std::size_t)>& progress, RemoteWorkers* remote) {
  const auto start = Clock::now();
  const EnsemblePlan plan(scene_file, overrides, options);
  const std::size_t samples = plan.samples;
  EnsembleFile file(output, plan.base, plan.base.text, overrides, options, samples, plan.pair_a, plan.pair_b);

  EnsembleReport report;
  report.samples = samples;
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < samples; ++i)
    if (!file.done(i)) todo.push_back(i);
  report.skipped = samples - todo.size();
  unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, todo.size())));
  report.threads = threads;
  report.ranks = remote ? remote->count() + 1 : 1;

  // One dispenser of sample indices for the local threads and the remote workers alike (dynamic
  // distribution: runs may differ in length by orders of magnitude).
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<std::pair<std::size_t, SampleResult>> finished;
  std::atomic<unsigned> running{threads};
  auto worker = [&] {
    PluginRegistry registry;  // one per thread: nothing shared but the immutable plugin code
    for (;;) {
      const std::size_t t = next.fetch_add(1);
      if (t >= todo.size()) break;
      const std::size_t i = todo[t];
      SampleResult r = plan.run(i, registry, output);
      {
        std::lock_guard<std::mutex> lock(mutex);
        finished.emplace_back(i, std::move(r));
      }
      ready.notify_one();
    }
    running.fetch_sub(1);
    ready.notify_one();
  };
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k) pool.emplace_back(worker);

  // The main thread writes: each result at its index, committed every 50 ms at most (two
  // flushes: a few milliseconds), so a kill loses at most that much work. It also serves the
  // remote workers.
  auto last_commit = Clock::now();
  std::size_t written = 0, remote_busy = 0, remote_stopped = 0;
  const std::size_t remotes = remote ? remote->count() : 0;
  std::vector<std::pair<std::size_t, SampleResult>> arrived;
  std::vector<int> idle;
  for (;;) {
    std::deque<std::pair<std::size_t, SampleResult>> batch;
    {
      std::unique_lock<std::mutex> lock(mutex);
      ready.wait_for(lock, std::chrono::milliseconds(remote ? 1 : 200),
                     [&] { return !finished.empty() || running.load() == 0; });
      batch.swap(finished);
    }
    if (remote) {
      arrived.clear();
      idle.clear();
      remote->poll(arrived, idle);
      for (auto& item : arrived) {
        batch.push_back(std::move(item));
        --remote_busy;
      }
      for (int w : idle) {
        const std::size_t t = next.fetch_add(1);
        if (t < todo.size()) {
          remote->assign(w, todo[t]);
          ++remote_busy;
        } else {
          remote->assign(w, RemoteWorkers::kNone);
          ++remote_stopped;
        }
      }
    }
    for (auto& [i, r] : batch) {
      file.write(i, sample_values(options.vary, options.seed, i), options.vary, r);
      ++written;
      (r.outcome == 0 ? report.completed : r.outcome == 1 ? report.stopped : report.failed) += 1;
      if (r.trustworthy == 0) ++report.untrustworthy;
      report.sample_seconds += r.wall;
      report.setup_seconds += r.setup;
    }
    if (!batch.empty() && std::chrono::duration<double>(Clock::now() - last_commit).count() >= 0.05) {
      file.commit();
      last_commit = Clock::now();
      if (progress) progress(report.skipped + written, samples);
    }
    if (running.load() == 0 && remote_busy == 0 && remote_stopped == remotes) {
      std::lock_guard<std::mutex> lock(mutex);
      if (finished.empty()) break;
    }
  }
  for (auto& t : pool) t.join();
  file.commit();
  report.run = written;
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

}  // namespace noether
