#pragma once
// PluginRegistry: finds plugins by name on the search path ($NOETHER_PLUGIN_PATH, then the
// folder of bundled plugins next to libnoether: build/lib/noether/plugins in the build tree,
// <prefix>/lib/noether/plugins when installed) and loads them on demand with Boost.DLL. Every
// object a plugin makes keeps its library loaded for as long as the object lives.
#include <noether/integrator.hpp>
#include <noether/params.hpp>
#include <noether/plugin.hpp>
#include <noether/potential.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace noether {

struct PluginInfo {
  std::string name;
  PluginKind kind = PluginKind::Potential;
  std::string description;
  std::vector<ParamDoc> params;
  std::filesystem::path file;
};

class PluginRegistry {
 public:
  explicit PluginRegistry(std::vector<std::filesystem::path> search_path = default_search_path());

  // $NOETHER_PLUGIN_PATH (colon-separated), then <folder of libnoether>/noether/plugins.
  static std::vector<std::filesystem::path> default_search_path();

  const std::vector<std::filesystem::path>& search_path() const { return search_path_; }
  // Names of every plugin library found (noether-<name>.so), without loading them.
  std::vector<std::string> names() const;

  // Loads (once) and describes a plugin. Throws PluginError: unknown name (listing the names
  // found), load error, missing descriptor symbol, API version mismatch.
  const PluginInfo& info(const std::string& name);

  // Loads every plugin found; failures are returned as messages instead of thrown.
  std::vector<PluginInfo> load_all(std::vector<std::string>& failures);

  // Makes a model or an integrator; `params` is checked against the plugin's ParamDoc list
  // (unknown keys, missing required keys) before the factory sees it. `params` may contain the
  // key "plugin", which is ignored. With `initial` (the scene's initial state) a model makes its
  // choices there before it is shared (Potential::choose_models): what a scene's run does.
  std::shared_ptr<const Potential> make_potential(const std::string& name, const System& system,
                                                  const Params& params, const State* initial = nullptr);
  std::shared_ptr<Integrator> make_integrator(const std::string& name, const System& system,
                                              std::shared_ptr<const Potential> potential,
                                              const Params& params);
  std::shared_ptr<const ForceModel> make_force(const std::string& name, const System& system, const Params& params,
                                               const State* initial = nullptr);

 private:
  struct Loaded {
    std::shared_ptr<void> library;  // boost::dll::shared_library, kept alive by every object
    const PluginDescriptor* descriptor = nullptr;
    PluginInfo info;
  };
  const Loaded& load(const std::string& name);
  const Loaded& load_kind(const std::string& name, PluginKind kind);

  std::vector<std::filesystem::path> search_path_;
  std::map<std::string, std::filesystem::path> files_;  // first file per name, search order
  std::map<std::string, Loaded> loaded_;
};

// "noether-<name>.so" → "<name>", or "" if the file is not named like a plugin.
std::string plugin_name_from_file(const std::filesystem::path& file);

}  // namespace noether
