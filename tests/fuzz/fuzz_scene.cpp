// libFuzzer target for the scene parser and validator (tools/fuzz.sh; docs/reliability.md).
// An input is a scene's YAML text. Every input must end in a parsed scene or a noether::Error
// (the user errors the CLI reports with exit 2); any other exception, a crash, a sanitizer
// report, a leak or a hang is a finding. A scene that parses is taken one step further: its
// potential and integrator are built by the bundled plugins, whose parameter validation is
// part of what a user's scene meets.
#include <noether/error.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace {

noether::PluginRegistry& registry() {
  static noether::PluginRegistry plugins({NOETHER_FUZZ_PLUGIN_DIR});
  return plugins;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return -1;  // scenes are small; larger inputs only slow the search
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Named as if it sat in examples/, so the examples' relative mesh paths resolve.
    const noether::Scene scene = noether::parse_scene(text, NOETHER_FUZZ_SCENE_NAME);
    std::shared_ptr<const noether::Potential> potential;
    for (const auto& p : scene.potentials) potential = registry().make_potential(p.plugin, scene.system, p.params);
    if (potential)
      registry().make_integrator(scene.integrator.plugin, scene.system, potential, scene.integrator.params);
  } catch (const noether::Error&) {
    // a user error, reported as such
  }
  return 0;
}
