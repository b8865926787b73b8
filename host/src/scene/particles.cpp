// The scene's massless particles: their initial states from a list, a file, orbits or ejecta
// clouds, and how they are carried (scene_sections.hpp; docs/user-guide.md "Particles").
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include <noether/ejecta.hpp>
#include <noether/error.hpp>
#include <noether/inertia_integrals.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace noether::detail {

namespace {

// particles.ejecta: {body, site: [latitude, longitude], count, speed: [min, max], exponent, cone,
// height, seed} (ejecta.hpp; docs/equations.md §39). `index`: the cloud's place in the list, whose
// default seed is index + 1, so that clouds without a seed draw different speeds and azimuths.
EjectaSettings parse_ejecta(const Params& e, const System& sys, std::size_t index) {
  const SceneSection& keys = scene_section("particles.ejecta");
  keys.check(e, "'particles.ejecta'");
  EjectaSettings out;
  out.body = body_named(e.at("body"), sys);
  const std::vector<double> site = e.at("site").as_doubles();
  if (site.size() != 2 || !(std::abs(site[0]) <= 90.0) || !std::isfinite(site[1]))
    throw SceneError(e.at("site").here() + "'particles.ejecta.site' is [latitude, longitude] in degrees, in the body "
                     "frame, latitude in [-90, 90]");
  out.latitude = site[0];
  out.longitude = site[1];
  const long count = e.at("count").as_int();
  if (count < 1 || count > 10000000L)  // 10^7 particles hold ~0.5 GB of states
    throw SceneError(e.at("count").here() + "'particles.ejecta.count' must be 1..10^7");
  out.count = static_cast<std::size_t>(count);
  const std::vector<double> speed = e.at("speed").as_doubles();
  if (speed.size() != 2 || !(speed[0] > 0.0) || !(speed[1] >= speed[0]) || !std::isfinite(speed[1]))
    throw SceneError(e.at("speed").here() + "'particles.ejecta.speed' is [min, max], 0 < min <= max: launch speeds "
                     "relative to the surface");
  out.speed_min = speed[0];
  out.speed_max = speed[1];
  out.exponent = keys.number(e, "exponent");
  if (!(out.exponent > 0.0) || !std::isfinite(out.exponent))
    throw SceneError(e.at("exponent").here() + "'particles.ejecta.exponent' (gamma of N(>v) ∝ v^-gamma) must be > 0");
  out.cone = keys.number(e, "cone");
  if (!(out.cone >= 0.0 && out.cone < 90.0))
    throw SceneError(e.at("cone").here() + "'particles.ejecta.cone' (degrees from the surface's normal) must be in "
                     "[0, 90)");
  out.height = keys.number(e, "height");
  if (!(out.height >= 0.0) || !std::isfinite(out.height))
    throw SceneError(e.at("height").here() + "'particles.ejecta.height' must be a distance ≥ 0");
  const long seed = e.has("seed") ? e.at("seed").as_int() : static_cast<long>(index) + 1;
  if (seed < 0) throw SceneError(e.at("seed").here() + "'particles.ejecta.seed' must be ≥ 0");
  out.seed = static_cast<std::uint64_t>(seed);
  return out;
}

}  // namespace

// particles: {around, states | file | orbits | ejecta, step, degree, tolerance, escape, record, check}
// (docs/user-guide.md, "Particles"): each source adds particles, in the order states, file, orbits,
// ejecta.
ParticleSettings parse_particles(const Params& p, const System& sys, const State& initial,
                                 const std::filesystem::path& folder) {
  const SceneSection& keys = scene_section("particles");
  keys.check(p, "'particles'");
  ParticleSettings out;
  Vec3 x0 = Vec3::Zero(), v0 = Vec3::Zero();
  if (p.has("around")) {
    const std::size_t c = body_named(p.at("around"), sys);
    out.around = c;
    x0 = initial.x.col(static_cast<Eigen::Index>(c));
    v0 = initial.p.col(static_cast<Eigen::Index>(c)) / sys.body(c).mass;
  }
  auto add = [&](const std::vector<double>& z, const std::string& where) {
    if (z.size() != 6 || !std::all_of(z.begin(), z.end(), [](double u) { return std::isfinite(u); }))
      throw SceneError(where + "a particle's state is six finite numbers: x, y, z, vx, vy, vz");
    out.position.push_back(x0 + Vec3(z[0], z[1], z[2]));
    out.velocity.push_back(v0 + Vec3(z[3], z[4], z[5]));
  };
  if (p.has("states")) {
    const Params& list = p.at("states");
    if (!list.is_sequence()) throw SceneError(list.here() + "'particles.states' must be a list of [x, y, z, vx, vy, vz]");
    for (const Params& z : list.items()) add(z.as_doubles(), z.here());
  }
  if (p.has("file")) {  // six numbers a line (commas or blanks); '#' starts a comment
    const std::filesystem::path path = scene_file(p.at("file"), folder, "'particles'", "file of particle states");
    std::ifstream in(path);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream fields(line);
      std::vector<double> z;
      std::string word;
      const std::string where = path.string() + ":" + std::to_string(number) + ": ";
      while (fields >> word) {
        char* end = nullptr;
        const double u = std::strtod(word.c_str(), &end);
        if (*end != '\0') throw SceneError(where + "'" + word + "' is not a number");
        z.push_back(u);
      }
      if (!z.empty()) add(z, where);
    }
  }
  if (p.has("orbits")) {  // osculating elements about `around` (17.2)–(17.4), angles in degrees
    if (!out.around) throw SceneError(p.at("orbits").here() + "'particles.orbits' needs 'particles.around': the body they orbit");
    const double mu = sys.G() * sys.body(*out.around).mass;
    for (const Params& o : p.at("orbits").items()) {
      scene_section("particles.orbits[]").check(o, "a particle's orbit");
      const RelativeState rel = state_from_elements(orbit_elements(o, "particle " + std::to_string(out.position.size())), mu);
      add({rel.r.x(), rel.r.y(), rel.r.z(), rel.v.x(), rel.v.y(), rel.v.z()}, o.here());
    }
  }
  if (p.has("ejecta")) {  // a cloud thrown from a surface, or a list of them (39.1)–(39.2)
    const Params& list = p.at("ejecta");
    const auto clouds = list.is_sequence() ? list.items() : std::vector<Params>{list};
    for (std::size_t k = 0; k < clouds.size(); ++k) {
      const EjectaSettings cloud = parse_ejecta(clouds[k], sys, k);
      try {
        launch_ejecta(cloud, sys, initial, out.position, out.velocity);
      } catch (const SceneError& error) {  // a body without a surface, named with the scene's line
        throw SceneError(clouds[k].at("body").here() + error.what());
      }
    }
  }
  if (out.empty())
    throw SceneError(p.here() + "'particles' gives no particle: list 'states', a 'file', 'orbits' or 'ejecta'");
  out.step = keys.number(p, "step");
  out.degree = static_cast<int>(keys.integer(p, "degree"));
  out.tolerance = keys.number(p, "tolerance");
  out.escape = keys.number(p, "escape");
  const long record = keys.integer(p, "record");
  if (record < 0) throw SceneError(p.at("record").here() + "'particles.record' must be a count ≥ 0");
  out.record = std::min(static_cast<std::size_t>(record), out.position.size());
  const long check = keys.integer(p, "check");
  if (check < 0) throw SceneError(p.at("check").here() + "'particles.check' must be a count ≥ 0 (0: no check)");
  out.check = std::min(static_cast<std::size_t>(check), out.position.size());
  if (!(out.step > 0.0 && std::isfinite(out.step)) && p.has("step"))
    throw SceneError(p.at("step").here() + "'particles.step' must be a positive time (the particles' longest Verlet step)");
  if (out.degree < 0 || out.degree > multi_index::kMaxDegree)
    throw SceneError(p.at("degree").here() + "'particles.degree' must be 0.." + std::to_string(multi_index::kMaxDegree));
  if (!(out.tolerance > 0.0 && out.tolerance < 1.0))
    throw SceneError(p.at("tolerance").here() + "'particles.tolerance' must be in (0, 1)");
  if (!(out.escape >= 0.0) || !std::isfinite(out.escape))
    throw SceneError(p.at("escape").here() + "'particles.escape' must be a distance ≥ 0 (0: never)");
  return out;
}

}  // namespace noether::detail
