#include <noether/error.hpp>
#include <noether/registry.hpp>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <spdlog/spdlog.h>

#include <elf.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <cstdlib>
#include <sstream>
#include <system_error>


namespace fs = std::filesystem;

namespace noether {

const char* to_string(PluginKind kind) {
  switch (kind) {
    case PluginKind::Potential: return "potential";
    case PluginKind::Integrator: return "integrator";
    case PluginKind::Force: return "force";
  }
  return "unknown";
}

std::string plugin_name_from_file(const fs::path& file) {
  const std::string f = file.filename().string();
  const std::string prefix = "noether-", suffix = ".so";
  if (f.size() <= prefix.size() + suffix.size()) return {};
  if (f.compare(0, prefix.size(), prefix) != 0) return {};
  if (f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0) return {};
  return f.substr(prefix.size(), f.size() - prefix.size() - suffix.size());
}

std::vector<fs::path> PluginRegistry::default_search_path() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("NOETHER_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string dir;
    while (std::getline(ss, dir, ':'))
      if (!dir.empty()) dirs.emplace_back(dir);
  }
  // The bundled plugins sit in <folder of libnoether>/noether/plugins, both in the build tree
  // (build/lib) and under an install prefix (<prefix>/lib), wherever that prefix is.
  std::error_code ec;
  const fs::path core = boost::dll::this_line_location(ec);
  if (!ec && !core.empty())
    dirs.push_back(fs::weakly_canonical(core.parent_path() / "noether" / "plugins", ec));
  return dirs;
}

PluginRegistry::PluginRegistry(std::vector<fs::path> search_path)
    : search_path_(std::move(search_path)) {
  for (const auto& dir : search_path_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      const std::string name = plugin_name_from_file(file);
      if (!name.empty()) files_.emplace(name, file);  // first in search order wins
    }
  }
}

std::vector<std::string> PluginRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, file] : files_) out.push_back(name);
  return out;
}

namespace {

// Before dlopen: the file must be a complete 64-bit ELF shared object (its program and section
// header tables inside the file; dlopen maps a truncated file and dies of SIGBUS), and neither
// it nor its folder writable by others (anyone could then run code in noether). Returns an
// empty string when it is fine, else what is wrong.
std::string unsafe_plugin_file(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::string("cannot read it: ") + std::strerror(errno);
  if (st.st_mode & S_IWOTH) return "it is writable by every user; chmod o-w it";
  struct stat dir {};
  if (::stat(path.parent_path().c_str(), &dir) == 0 && (dir.st_mode & S_IWOTH) && !(dir.st_mode & S_ISVTX))
    return "its folder " + path.parent_path().string() + " is writable by every user; chmod o-w it";
  Elf64_Ehdr h{};
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.e_ident, ELFMAG, SELFMAG) != 0)
    return "it is not an ELF shared library";
  if (h.e_ident[EI_CLASS] != ELFCLASS64 || h.e_type != ET_DYN) return "it is not a 64-bit ELF shared library";
  const auto size = static_cast<std::uint64_t>(st.st_size);
  const std::uint64_t programs = h.e_phoff + std::uint64_t{h.e_phnum} * h.e_phentsize;
  const std::uint64_t sections = h.e_shoff + std::uint64_t{h.e_shnum} * h.e_shentsize;
  if (programs > size || sections > size)
    return "it is truncated (" + std::to_string(size) + " bytes; its headers reach byte " +
           std::to_string(std::max(programs, sections)) + "): rebuild or reinstall it";
  return "";
}

}  // namespace

const PluginRegistry::Loaded& PluginRegistry::load(const std::string& name) {
  if (auto it = loaded_.find(name); it != loaded_.end()) return it->second;
  auto file = files_.find(name);
  if (file == files_.end()) {
    std::ostringstream msg;
    msg << "unknown plugin '" << name << "'";
    const std::string guess = closest_match(name, names());
    if (!guess.empty()) msg << " (did you mean '" << guess << "'?)";
    msg << "; plugins found:";
    if (files_.empty()) msg << " none";
    for (const auto& [n, f] : files_) msg << ' ' << n;
    msg << ". Searched:";
    for (const auto& d : search_path_) msg << ' ' << d.string();
    msg << " (add folders with NOETHER_PLUGIN_PATH)";
    throw PluginError(msg.str());
  }
  const fs::path& path = file->second;
  if (const std::string wrong = unsafe_plugin_file(path); !wrong.empty())
    throw PluginError("plugin '" + name + "' (" + path.string() + ") is not loaded: " + wrong);
  auto library = std::make_shared<boost::dll::shared_library>();
  try {
    library->load(path, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw PluginError("plugin '" + name + "' (" + path.string() +
                      ") could not be loaded: " + e.what());
  }
  if (!library->has(NOETHER_PLUGIN_SYMBOL))
    throw PluginError("plugin '" + name + "' (" + path.string() + ") has no symbol '" +
                      NOETHER_PLUGIN_SYMBOL +
                      "': it is not a noether plugin, or was not built with "
                      "noether_add_plugin() and NOETHER_PLUGIN_DESCRIPTOR");
  const auto& d = library->get<const PluginDescriptor>(NOETHER_PLUGIN_SYMBOL);
  if (d.api_version != NOETHER_PLUGIN_API_VERSION) {
    std::ostringstream msg;
    msg << "plugin '" << name << "' (" << path.string() << ") was built for plugin API version "
        << d.api_version << ", but this noether uses plugin API version "
        << NOETHER_PLUGIN_API_VERSION << "; rebuild the plugin against this noether";
    throw PluginError(msg.str());
  }
  const bool potential_ok = d.kind == PluginKind::Potential && d.make_potential;
  const bool integrator_ok = d.kind == PluginKind::Integrator && d.make_integrator;
  const bool force_ok = d.kind == PluginKind::Force && d.make_force;
  if (!potential_ok && !integrator_ok && !force_ok)
    throw PluginError("plugin '" + name + "' (" + path.string() +
                      ") has an invalid descriptor: unknown kind or no factory");
  if (!d.name || name != d.name)
    throw PluginError("plugin file " + path.string() + " describes itself as '" +
                      (d.name ? d.name : "") + "'; the file name says '" + name + "'");
  Loaded loaded;
  loaded.descriptor = &d;
  loaded.info = {name, d.kind, d.description ? d.description : "",
                 std::vector<ParamDoc>(d.params, d.params + d.param_count), path};
  loaded.library = library;
  spdlog::debug("loaded plugin '{}' from {}", name, path.string());
  return loaded_.emplace(name, std::move(loaded)).first->second;
}

const PluginInfo& PluginRegistry::info(const std::string& name) { return load(name).info; }

std::vector<PluginInfo> PluginRegistry::load_all(std::vector<std::string>& failures) {
  std::vector<PluginInfo> out;
  for (const auto& name : names()) {
    try {
      out.push_back(load(name).info);
    } catch (const PluginError& e) {
      failures.emplace_back(e.what());
    }
  }
  return out;
}

const PluginRegistry::Loaded& PluginRegistry::load_kind(const std::string& name,
                                                        PluginKind kind) {
  const Loaded& l = load(name);
  if (l.info.kind != kind) {
    // Alternatives from what is already loaded and from file names: loading every library on
    // the path to learn its kind would run the code of each (constructors included).
    std::vector<std::string> same_kind, unloaded;
    for (const auto& n : names()) {
      if (auto it = loaded_.find(n); it != loaded_.end()) {
        if (it->second.info.kind == kind) same_kind.push_back(n);
      } else {
        unloaded.push_back(n);
      }
    }
    std::ostringstream msg;
    msg << "plugin '" << name << "' is " << (l.info.kind == PluginKind::Integrator ? "an " : "a ")
        << to_string(l.info.kind) << ", not " << (kind == PluginKind::Integrator ? "an " : "a ")
        << to_string(kind);
    if (!same_kind.empty()) {
      msg << "; " << to_string(kind) << " plugins loaded:";
      for (const auto& n : same_kind) msg << ' ' << n;
    }
    if (!unloaded.empty()) {
      msg << "; other plugins found:";
      for (const auto& n : unloaded) msg << ' ' << n;
      msg << " (`noether plugins` shows the kind of each)";
    }
    throw PluginError(msg.str());
  }
  return l;
}

namespace {

// A documented default the host fills in (ParamDoc::default_value; "(...)" describes one the
// plugin works out itself).
bool literal_default(const ParamDoc& doc) { return doc.default_value && doc.default_value[0] != '('; }

// The scene's parameters with every documented default the scene omits filled in (where():
// kPluginDefault), so that a plugin reads each documented key with at().
Params with_defaults(const PluginInfo& info, const Params& given_params) {
  Params params = given_params.is_null() ? Params::map({}, given_params.where()) : given_params;
  for (const auto& doc : info.params) {
    if (!literal_default(doc) || params.has(doc.name)) continue;
    const std::string text = doc.default_value;
    if (std::string(doc.type) == "list") {  // "[a, b, c]"
      std::vector<Params> items;
      std::stringstream in(text.substr(1, text.size() - 2));
      for (std::string item; std::getline(in, item, ',');) {
        const auto b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
        items.push_back(Params::scalar(item.substr(b, e - b + 1), kPluginDefault));
      }
      params.set(doc.name, Params::sequence(std::move(items), kPluginDefault));
    } else {
      params.set(doc.name, Params::scalar(text, kPluginDefault));
    }
  }
  return params;
}

void check_params(const PluginInfo& info, const Params& params) {
  if (params.is_null()) return;
  const std::string what = std::string(to_string(info.kind)) + " plugin '" + info.name + "'";
  std::vector<std::string> allowed{"plugin"};
  for (const auto& p : info.params) allowed.emplace_back(p.name);
  params.check_keys(allowed, what);
  for (const auto& p : info.params)
    if (!p.default_value && !params.has(p.name))
      throw SceneError(params.here() + what + " needs '" + p.name + "': " + p.description);
}

// Every potential a plugin makes is wrapped so that a non-finite energy, force or moment stops
// the run with the plugin's name instead of propagating NaN silently (an O(n) check against an
// evaluation that is at least O(n)).
class FiniteChecked final : public Potential {
 public:
  FiniteChecked(std::shared_ptr<const Potential> inner, std::string plugin, const System& system)
      : inner_(std::move(inner)), plugin_(std::move(plugin)) {
    for (const auto& b : system.bodies()) names_.push_back(b.name);
    for (std::size_t k = 0; k < system.rigid_count(); ++k) rigid_.push_back(system.body_of_rigid(k));
  }
  std::unique_ptr<Workspace> make_workspace() const override {
    auto workspace = inner_->make_workspace();
    if (!workspace) throw PluginError("potential plugin '" + plugin_ + "' made no workspace");
    return workspace;
  }
  void evaluate(const State& state, Forces& forces, Workspace& workspace) const override {
    inner_->evaluate(state, forces, workspace);
    if (std::isfinite(forces.U) && forces.f.allFinite() && forces.M.allFinite()) return;
    std::string what = "the energy U";
    for (Eigen::Index i = 0; i < forces.f.cols(); ++i)
      if (!forces.f.col(i).allFinite()) what = "the force on body '" + names_[static_cast<std::size_t>(i)] + "'";
    for (Eigen::Index k = 0; k < forces.M.cols(); ++k)
      if (!forces.M.col(k).allFinite())
        what = "the moment on body '" + names_[rigid_[static_cast<std::size_t>(k)]] + "'";
    std::ostringstream msg;
    msg << "potential plugin '" << plugin_ << "' returned a non-finite value for " << what
        << " at t = " << state.t;
    throw IntegrationError(msg.str(), state.t);
  }
  std::vector<PairModel> pair_models(const Workspace& workspace) const override {
    return inner_->pair_models(workspace);
  }
  bool force_jacobian(const State& state, Eigen::MatrixXd& K, Workspace& workspace) const override {
    const auto rows = K.rows(), cols = K.cols();
    if (!inner_->force_jacobian(state, K, workspace)) return false;
    if (K.rows() != rows || K.cols() != cols)
      throw IntegrationError("potential plugin '" + plugin_ + "' resized the force Jacobian to " +
                             std::to_string(K.rows()) + " × " + std::to_string(K.cols()) + " (expected " +
                             std::to_string(rows) + " × " + std::to_string(cols) + ")", state.t);
    if (!K.allFinite())
      throw IntegrationError("potential plugin '" + plugin_ + "' returned a non-finite force Jacobian at t = " +
                             std::to_string(state.t), state.t);
    return true;
  }

 private:
  std::shared_ptr<const Potential> inner_;
  std::string plugin_;
  std::vector<std::string> names_;
  std::vector<std::size_t> rigid_;
};

// Calls a plugin's factory: noether errors (bad parameters) pass through, anything else is
// reported with the plugin's name.
template <class Make>
auto construct(const PluginInfo& info, Make&& make) {
  try {
    auto object = make();
    if (!object)
      throw PluginError(std::string(to_string(info.kind)) + " plugin '" + info.name +
                        "' returned no object");
    return object;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw PluginError(std::string(to_string(info.kind)) + " plugin '" + info.name +
                      "' failed to construct: " + e.what());
  } catch (...) {
    throw PluginError(std::string(to_string(info.kind)) + " plugin '" + info.name +
                      "' failed to construct (unknown exception)");
  }
}

// Wraps an object so that its plugin library outlives it.
template <class T>
std::shared_ptr<T> keep_library_alive(std::unique_ptr<T> object, std::shared_ptr<void> library) {
  return std::shared_ptr<T>(object.release(), [library](T* p) { delete p; });
}

}  // namespace

std::shared_ptr<const Potential> PluginRegistry::make_potential(const std::string& name,
                                                                const System& system,
                                                                const Params& params, const State* initial) {
  const Loaded& l = load_kind(name, PluginKind::Potential);
  check_params(l.info, params);
  const Params filled = with_defaults(l.info, params);
  auto object = construct(l.info, [&] { return l.descriptor->make_potential(system, filled); });
  if (initial) object->choose_models(*initial);
  return std::make_shared<FiniteChecked>(
      keep_library_alive<Potential>(std::move(object), l.library), name, system);
}

std::shared_ptr<Integrator> PluginRegistry::make_integrator(
    const std::string& name, const System& system, std::shared_ptr<const Potential> potential,
    const Params& params) {
  const Loaded& l = load_kind(name, PluginKind::Integrator);
  check_params(l.info, params);
  const Params filled = with_defaults(l.info, params);
  auto object =
      construct(l.info, [&] { return l.descriptor->make_integrator(system, potential, filled); });
  return keep_library_alive<Integrator>(std::move(object), l.library);
}

std::shared_ptr<const ForceModel> PluginRegistry::make_force(const std::string& name, const System& system,
                                                             const Params& params, const State* initial) {
  const Loaded& l = load_kind(name, PluginKind::Force);
  check_params(l.info, params);
  const Params filled = with_defaults(l.info, params);
  auto object = construct(l.info, [&] { return l.descriptor->make_force(system, filled); });
  if (initial) object->choose_models(*initial);
  return keep_library_alive<ForceModel>(std::move(object), l.library);
}

}  // namespace noether
