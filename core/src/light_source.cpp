// Where a radiation force's light comes from (light_source.hpp).
#include <noether/error.hpp>
#include <noether/light_source.hpp>

namespace noether {

LightSource::LightSource(const System& system, const Params& p, const std::string& plugin) {
  if (p.has("sun")) {
    for (const char* key : {"position", "velocity", "mu", "epoch", "center"})
      if (given(p, key))
        throw SceneError(p.at(key).here() + plugin + ": give the Sun either as a scene body ('sun') or by its conic "
                                                     "('position', 'velocity', 'mu'), not both");
    const std::string sun = p.at("sun").as_string();
    body_ = system.index_of(sun);
    if (body_ < 0) throw SceneError(p.at("sun").here() + plugin + ": no body named '" + sun + "' to be the Sun");
    return;
  }
  if (!p.has("position") || !p.has("velocity"))
    throw SceneError(p.here() + plugin + ": give the Sun: 'sun', a scene body, or its conic 'position', 'velocity' "
                                         "and 'mu' relative to 'center'");
  conic_.emplace(system, p, 0.0, plugin);
}

}  // namespace noether
