// parse_scene: the scene's tree (scene_yaml.cpp) checked against the schema (scene_schema.cpp)
// and built section by section (scene_sections.hpp) into bodies, shapes, initial states, plugins
// and run settings (docs/user-guide.md, "Scenes").
#include <noether/error.hpp>
#include <noether/force_model.hpp>
#include <noether/scene.hpp>

#include "scene/input_warnings.hpp"
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_yaml.hpp"

#include <filesystem>

namespace noether {

namespace {

PluginConfig plugin_config(const Params& p, const std::string& what) {
  if (!p.is_map() || !p.has("plugin"))
    throw SceneError(p.here() + "'" + p.path() + "' must be a mapping naming a plugin, e.g. " +
                     what + ": {plugin: NAME}");
  return {p.at("plugin").as_string(), p};
}

// `potential:` or `forces:`: one plugin's mapping, or a list of them.
std::vector<PluginConfig> plugin_list(const Params& node, const std::string& what) {
  std::vector<PluginConfig> out;
  if (!node.is_sequence()) return {plugin_config(node, what)};
  for (const auto& item : node.items()) out.push_back(plugin_config(item, what));
  return out;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::string>& overrides) {
  using namespace detail;
  Scene scene;
  scene.file = file;
  scene.text = text;
  scene.overrides = overrides;
  Params root = parse_yaml(text, file);
  if (!root.is_map()) throw SceneError(file + ": a scene must be a YAML mapping (G, bodies, ...)");
  for (const auto& o : overrides) apply_override(root, o);
  root.set_path("");
  const SceneSection& keys = scene_section("");
  keys.check(root, "the scene");
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();

  // Bodies: constants into System, initial values into State.
  if (root.has("units")) scene.units = parse_units(root.at("units"));
  std::vector<std::string> notes;  // the bodies' field files' defects and overrides (warnings, first)
  scene.system = parse_bodies(root, scene.units, scene_gravitational_constant(root, scene.units), folder, notes);
  scene.initial = initial_state(root.at("bodies"), scene.system, keys.flag(root, "barycentric"));

  // Models, integrator, run.
  scene.potentials = plugin_list(root.at("potential"), "potential");
  if (scene.potentials.empty()) throw SceneError(root.at("potential").here() + "'potential' must name at least one plugin");
  if (root.has("forces")) scene.forces = plugin_list(root.at("forces"), "forces");
  if (!scene.forces.empty())  // what the forces put in since t0 (docs/equations.md eq. 33.3)
    scene.initial.force_balance = Eigen::MatrixXd::Zero(kBalanceRows, static_cast<Eigen::Index>(scene.forces.size()));
  scene.integrator = plugin_config(root.at("integrator"), "integrator");
  if (root.has("impulses")) scene.impulses = parse_impulses(root.at("impulses"), scene.system, scene.initial.t);
  if (root.has("particles")) scene.particles = parse_particles(root.at("particles"), scene.system, scene.initial, folder);
  scene.run = parse_run(root.at("run"), scene.system, scene.initial, root.at("bodies"));
  scene.root = std::move(root);
  scene.warnings = input_warnings(scene);
  scene.warnings.insert(scene.warnings.begin(), notes.begin(), notes.end());
  return scene;
}

}  // namespace noether
