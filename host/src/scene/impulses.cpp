// The scene's impulses: a change of a body's velocity at a time during the run, in the inertial
// frame or the RTN frame of its orbit (scene_sections.hpp; docs/user-guide.md "Impulses").
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include <noether/error.hpp>

#include <cmath>

namespace noether::detail {

std::vector<Impulse> parse_impulses(const Params& list, const System& system, double t0) {
  const char* form = "'impulses' must be a list of {body: NAME, time: T, delta_v: [x, y, z]} (optionally "
                     "frame: rtn, around: NAME)";
  if (!list.is_sequence()) throw SceneError(list.here() + form);
  const SceneSection& keys = scene_section("impulses[]");
  std::vector<Impulse> out;
  for (const Params& item : list.items()) {
    if (!item.is_map()) throw SceneError(item.here() + form);
    keys.check(item, "'" + item.path() + "'");
    Impulse impulse;
    impulse.body = body_named(item.at("body"), system);
    impulse.time = item.at("time").as_double();
    if (!std::isfinite(impulse.time) || !(impulse.time > t0))
      throw SceneError(item.at("time").here() + "'" + item.at("time").path() + "' must be a time after the start (" +
                       std::to_string(t0) + "); a change of velocity at the start is the body's velocity");
    impulse.delta_v = vec3(item.at("delta_v"));
    if (!impulse.delta_v.allFinite())
      throw SceneError(item.at("delta_v").here() + "'" + item.at("delta_v").path() + "' must be finite");
    const std::string frame = keys.text(item, "frame");
    if (frame == "rtn") {
      impulse.frame = Impulse::Frame::rtn;
      if (system.size() < 2)
        throw SceneError(item.at("frame").here() + "'" + item.path() + ".frame: rtn' needs a second body to orbit");
      impulse.around = item.has("around") ? body_named(item.at("around"), system) : heaviest_other(system, impulse.body);
      if (impulse.around == impulse.body)
        throw SceneError(item.at("around").here() + "'" + item.at("around").path() + "': a body cannot orbit itself");
    } else if (frame != "inertial") {
      throw SceneError(item.at("frame").here() + "'" + item.at("frame").path() + "' is '" + frame +
                       "'; it must be inertial (the scene's axes, the default) or rtn (radial, along-track, normal "
                       "of the body's orbit about 'around' at the impulse's time)");
    } else if (item.has("around")) {
      throw SceneError(item.at("around").here() + "'" + item.at("around").path() +
                       "' is used only with frame: rtn (an inertial delta_v needs no orbit)");
    }
    out.push_back(impulse);
  }
  return out;
}

}  // namespace noether::detail
