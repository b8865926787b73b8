// The run's settings: its length and frames, the events that stop it, the verdict's thresholds
// and the derivatives it carries (scene_sections.hpp; docs/user-guide.md "Scenes", "Verdict").
#include "scene/scene_schema.hpp"
#include "scene/scene_sections.hpp"
#include "scene/scene_values.hpp"

#include "scene/start_apart.hpp"
#include "run/event_watch.hpp"

#include <noether/error.hpp>

#include <cmath>
#include <sstream>
#include <utility>

namespace noether::detail {

namespace {

// run.trust: the verdict's thresholds, each positive; absent ones (or all, without run.trust)
// the schema's defaults.
TrustThresholds parse_trust(const Params& trust) {
  const SceneSection& keys = scene_section("run.trust");
  keys.check(trust, "'run.trust'");
  TrustThresholds t;
  for (auto [key, value] : {std::pair<const char*, double*>{"energy", &t.energy}, {"momentum", &t.momentum},
                            {"orthogonality", &t.orthogonality}, {"position", &t.position},
                            {"particle_fates", &t.particle_fates}, {"period", &t.period},
                            {"period_change", &t.period_change}, {"libration", &t.libration},
                            {"closest_approach", &t.closest_approach}, {"event_time", &t.event_time}}) {
    *value = keys.number(trust, key);
    if (!(*value > 0.0))
      throw SceneError(trust.at(key).here() + "'run.trust." + key + "' must be a positive number");
  }
  return t;
}

// run.escape: {body, about, distance, unbound}; body defaults to the lightest body, about to
// the heaviest other one.
Escape parse_escape(const Params& e, const System& system) {
  if (!e.is_map()) throw SceneError(e.here() + "'run.escape' must be a mapping: {body: NAME, about: NAME, distance: D, unbound: true}");
  const SceneSection& keys = scene_section("run.escape");
  keys.check(e, "'run.escape'");
  if (system.size() < 2) throw SceneError(e.here() + "'run.escape' needs two bodies");
  std::size_t lightest = 0;
  for (std::size_t i = 1; i < system.size(); ++i)
    if (system.body(i).mass < system.body(lightest).mass) lightest = i;
  Escape out;
  out.body = e.has("body") ? body_named(e.at("body"), system) : lightest;
  out.about = e.has("about") ? body_named(e.at("about"), system) : heaviest_other(system, out.body);
  if (out.about == out.body)
    throw SceneError(e.here() + "'run.escape': body and about are both '" + system.body(out.body).name + "'");
  out.distance = keys.number(e, "distance");
  out.unbound = keys.flag(e, "unbound");
  if (!std::isfinite(out.distance) || out.distance < 0.0)
    throw SceneError(e.at("distance").here() + "'run.escape.distance' must be a positive distance");
  if (!(out.distance > 0) && !out.unbound)
    throw SceneError(e.here() + "'run.escape' needs a distance (stop beyond it) or unbound: true (stop when the "
                     "two-body energy turns positive), or both");
  return out;
}

}  // namespace

RunSettings parse_run(const Params& run, const System& sys, const State& initial, const Params& bodies) {
  const SceneSection& keys = scene_section("run");
  keys.check(run, "'run'");
  RunSettings out;
  if (run.has("escape")) out.escape = parse_escape(run.at("escape"), sys);
  out.trust = parse_trust(run.has("trust") ? run.at("trust") : Params::map({}));
  out.close_approach = keys.number(run, "close_approach");
  out.rerun_seconds = keys.number(run, "rerun_seconds");
  if (!(out.rerun_seconds >= 0.0))
    throw SceneError(run.at("rerun_seconds").here() + "'run.rerun_seconds' must be 0 (never repeat the run) or a "
                     "positive wall time in seconds");
  out.collisions = keys.flag(run, "collisions");
  out.stm = keys.flag(run, "stm");
  out.chaos = keys.flag(run, "chaos");
  if (run.has("sensitivities")) {  // keys, checked against the bodies where the run starts
    const Params& listed = run.at("sensitivities");
    if (listed.is_scalar() && !listed.as_string().empty()) {
      out.sensitivities.push_back(listed.as_string());
    } else if (listed.is_sequence()) {
      for (const Params& key : listed.items()) {
        if (!key.is_scalar() || key.as_string().empty())
          throw SceneError(key.here() + "'run.sensitivities' must list keys such as bodies.moon.velocity");
        out.sensitivities.push_back(key.as_string());
      }
    } else if (!listed.is_scalar()) {
      throw SceneError(listed.here() + "'run.sensitivities' must list keys such as bodies.moon.velocity");
    }
  }
  if (!std::isfinite(out.close_approach) || out.close_approach < 0.0)
    throw SceneError(run.at("close_approach").here() + "'run.close_approach' must be non-negative");
  out.t_end = run.at("t_end").as_double();
  out.output_every = run.at("output_every").as_double();
  if (out.t_end <= 0.0)
    throw SceneError(run.at("t_end").here() + "'run.t_end' must be positive");
  if (out.output_every <= 0.0 || out.output_every > out.t_end)
    throw SceneError(run.at("output_every").here() +
                     "'run.output_every' must be positive and at most run.t_end");
  if (const auto conflict = start_conflict(sys, initial, out.collisions))
    throw SceneError(bodies.items()[conflict->body].here() + conflict->what);
  return out;
}

}  // namespace noether::detail
