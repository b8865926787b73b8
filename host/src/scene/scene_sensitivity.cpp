// ∂z(t0)/∂p, and the parameters of the dynamics, for the keys of run.sensitivities
// (scene_sensitivity.hpp).
#include "scene/scene_sensitivity.hpp"

#include "scene/scene_schema.hpp"

#include <noether/error.hpp>
#include <noether/lie.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

namespace noether {
namespace {

// Whether `key` is a row of the scene schema's section `path` of type `type`: a body's [x, y, z] keys (position, velocity, angular_velocity, angular_momentum) and an
// orbit's elements (a, e, i, Omega, omega, nu, M) are the schema's.
bool schema_has(const char* path, const std::string& key, detail::KeyType type) {
  const auto& keys = detail::scene_section(path).keys;
  return std::any_of(keys.begin(), keys.end(), [&](const detail::SceneKey& k) { return k.key == key && k.type == type; });
}

const std::string kSemiAxes = "shape.ellipsoid.semi_axes";
const std::string kScale = "shape.polyhedron.scale";  // [1, 1, 1] where the scene leaves it out

std::string accepted() {
  return "a body's position, velocity, angular_velocity, angular_momentum (each whole or one component: "
         "velocity.1), attitude (three right rotations about the body's axes, or attitude.x, .y, .z), "
         "orbit.a, .e, .i, .Omega, .omega, .nu, .M; and the parameters of the dynamics G, a body's mass or "
         "density, its inertia (three principal moments, or one: inertia.2), shape.ellipsoid.semi_axes "
         "and shape.polyhedron.scale (whole or one of them); a number of a force beyond the potential, "
         "forces.K.FIELD (forces.0.k2); and an impulse's impulses.K.delta_v (whole or one component) or "
         "impulses.K.time";
}

// impulses.K.delta_v[.a] or impulses.K.time: the impulse's index and component (−1: all three
// of Δv; 3: its time), or SceneError.
std::pair<std::size_t, int> parse_impulse_key(const Scene& scene, const std::string& text) {
  const std::string where = "run.sensitivities: '" + text + "': ";
  const std::string rest = text.substr(9);  // after "impulses."
  const std::size_t dot = rest.find('.');
  std::size_t index = 0;
  try {
    std::size_t used = 0;
    index = std::stoul(rest.substr(0, dot), &used);
    if (used != dot) throw std::invalid_argument("index");
  } catch (const std::exception&) {
    throw SceneError(where + "an impulse is named by its index in the scene's impulses: impulses.0.delta_v");
  }
  if (index >= scene.impulses.size())
    throw SceneError(where + "names no impulse (the scene has " + std::to_string(scene.impulses.size()) + ")");
  const std::string field = dot == std::string::npos ? "" : rest.substr(dot + 1);
  if (field == "delta_v") return {index, -1};
  if (field == "time") return {index, 3};
  if (field.size() == 9 && field.compare(0, 8, "delta_v.") == 0 && std::string("012xyz").find(field[8]) != std::string::npos)
    return {index, field[8] >= '0' && field[8] <= '2' ? field[8] - '0' : field[8] - 'x'};
  throw SceneError(where + "of an impulse, sensitivities are taken to its delta_v (whole or one component: "
                   "impulses.0.delta_v.1) or its time (impulses.0.time)");
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

struct Key {
  std::string text;      // as given
  std::string body_key;  // "bodies.<name or index>"; "" for G
  std::size_t body = 0;
  std::string field;     // "velocity", "attitude", "orbit.e", "mass", "shape.ellipsoid.semi_axes", "G"
  int component = -1;    // 0, 1, 2 for one component of a vector field; -1: all of it
  bool dynamics = false;  // a parameter of the dynamics (docs/equations.md §22), not of z(t0)
  std::string path() const { return body_key.empty() ? field : body_key + "." + field; }
};

Key parse_key(const Scene& scene, const std::string& text) {
  const std::string where = "run.sensitivities: '" + text + "': ";
  Key key;
  key.text = text;
  if (text == "G") {
    key.field = "G";
    key.dynamics = true;
    if (scene.units.declared)
      throw SceneError(where + "G follows from the scene's declared units (" + scene.units.describe() +
                       "), which fix it; a sensitivity to G needs a scene without units");
    return key;
  }
  std::size_t best = 0;
  for (std::size_t i = 0; i < scene.system.size(); ++i)
    for (const std::string& ref : {scene.system.body(i).name, std::to_string(i)}) {
      const std::string prefix = "bodies." + ref + ".";
      if (text.size() > prefix.size() && text.compare(0, prefix.size(), prefix) == 0 && prefix.size() > best) {
        best = prefix.size();
        key.body = i;
        key.body_key = "bodies." + ref;
      }
    }
  if (best == 0) {
    std::string names;
    for (std::size_t i = 0; i < scene.system.size(); ++i) names += (i ? ", " : "") + scene.system.body(i).name;
    if (text.compare(0, 7, "bodies.") == 0)
      throw SceneError(where + "names no body of the scene (" + names + ") followed by a field");
    throw SceneError(where + "is not a key sensitivities are available to: " + accepted() + " (e.g. bodies." +
                     scene.system.body(0).name + ".velocity, bodies." + scene.system.body(0).name + ".mass)");
  }
  std::string rest = text.substr(best);
  if (rest.size() >= 2 && rest[rest.size() - 2] == '.' && std::string("012xyz").find(rest.back()) != std::string::npos) {
    const char c = rest.back();
    key.component = c >= '0' && c <= '2' ? c - '0' : c - 'x';
    rest.resize(rest.size() - 2);
  }
  key.field = rest;
  const bool vector = schema_has("bodies[]", rest, detail::KeyType::vector);
  const bool element = rest.compare(0, 6, "orbit.") == 0 &&
                       schema_has("particles.orbits[]", rest.substr(6), detail::KeyType::number);
  key.dynamics = ((rest == "mass" || rest == "density") && key.component < 0) || rest == kSemiAxes || rest == kScale ||
                 rest == "inertia";
  if (!(vector || rest == "attitude" || (element && key.component < 0) || key.dynamics))
    throw SceneError(where + "'" + rest + "' is not a key sensitivities are available to" +
                     (rest == "shape" || rest.compare(0, 6, "shape.") == 0
                          ? " (of a shape: an ellipsoid's semi-axes, a polyhedron's scale)"
                          : "") +
                     "; they are: " + accepted());
  const Params& item = scene.root.at("bodies").items()[key.body];
  const bool rigid = scene.system.body(key.body).rigid;
  const std::string body = scene.system.body(key.body).name;
  if (rest == "mass" && !item.has("mass") && item.has("gravity"))
    throw SceneError(where + body + "'s mass is its field's GM / G: give " + key.body_key +
                     ".mass in the scene (it then replaces the file's GM) to take the sensitivity to it");
  if (rest == "mass" && !item.has("mass"))
    throw SceneError(where + body + "'s mass follows from its density and shape: take " + key.body_key + ".density");
  if (rest == "density" && !item.has("density"))
    throw SceneError(where + body + " gives its mass, not a density: take " + key.body_key + ".mass");
  if (rest == kSemiAxes && !(item.has("shape") && item.at("shape").has("ellipsoid")))
    throw SceneError(where + body + " has no ellipsoid shape");
  if (rest == kScale && !(item.has("shape") && item.at("shape").has("polyhedron")))
    throw SceneError(where + body + " has no polyhedron shape");
  if (rest == "inertia" && !item.has("inertia"))
    throw SceneError(where + body + (rigid ? "'s inertia follows from its shape" : " is a point mass: it has no inertia"));
  if (rest == "inertia" && !(item.at("inertia").is_sequence() && item.at("inertia").size() == 3 &&
                             item.at("inertia").items()[0].is_scalar()))
    throw SceneError(where + body + "'s inertia is a 3×3 matrix; sensitivities are taken to three principal "
                     "moments [J1, J2, J3]");
  if ((rest == "attitude" || rest.compare(0, 8, "angular_") == 0) && !rigid)
    throw SceneError(where + body + " is a point mass: it has no " + rest);
  if (element && !item.has("orbit"))
    throw SceneError(where + body + "'s initial state is given by position and velocity, not orbit");
  if ((rest == "position" || rest == "velocity") && item.has("orbit"))
    throw SceneError(where + body + "'s initial state is given by orbit: take the sensitivity to " + key.body_key +
                     ".orbit.a, .e, .i, .Omega, .omega, .nu or .M");
  if (element && (rest == "orbit.nu" || rest == "orbit.M")) {
    const std::string other = rest == "orbit.nu" ? "M" : "nu";
    if (item.at("orbit").has(other))
      throw SceneError(where + body + "'s orbit gives its anomaly as " + other + ": take " + key.body_key +
                       ".orbit." + other);
  }
  const std::string other = rest == "angular_velocity" ? "angular_momentum" : "angular_velocity";
  if (rest.compare(0, 8, "angular_") == 0 && item.has(other))
    throw SceneError(where + body + "'s spin is given as " + other + ": take " + key.body_key + "." + other);
  return key;
}

// A parameter of the forces beyond the potential (docs/equations.md eq. 33.9): "forces.K.FIELD"
// for the K-th of a list of forces (FIELD a number the force's plugin reads: "forces.0.k2",
// "forces.1.time_lag"; dotted into a mapping: "forces.0.orbit.a"), or "forces.FIELD" when the
// scene gives one mapping. The number as the scene writes it, or SceneError naming the key.
double force_key_value(const Scene& scene, const std::string& text) {
  const std::string where = "run.sensitivities: '" + text + "': ";
  if (!scene.root.has("forces") || scene.forces.empty())
    throw SceneError(where + "the scene has no forces beyond the potential (forces:)");
  const Params& forces = scene.root.at("forces");
  std::string rest = text.substr(7);  // after "forces."
  const Params* node = &forces;
  if (forces.is_sequence()) {
    const std::size_t dot = rest.find('.');
    std::size_t index = 0;
    try {
      std::size_t used = 0;
      index = std::stoul(rest.substr(0, dot), &used);
      if (used != dot || dot == std::string::npos) throw std::invalid_argument("index");
    } catch (const std::exception&) {
      throw SceneError(where + "a force is named by its index in the scene's forces and one of its numbers: "
                       "forces.0.k2");
    }
    if (index >= forces.items().size())
      throw SceneError(where + "names no force (the scene has " + std::to_string(forces.items().size()) + ")");
    node = &forces.items()[index];
    rest = rest.substr(dot + 1);
  }
  for (std::size_t start = 0;;) {
    const std::size_t dot = rest.find('.', start);
    const std::string name = rest.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (name.empty() || !node->is_map() || !node->has(name))
      throw SceneError(where + "the force gives no '" + rest.substr(0, dot) +
                       "'; sensitivities are taken to a number the scene writes for it (forces.0.k2)");
    node = &node->at(name);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (!node->is_scalar() || rest == "plugin")
    throw SceneError(where + "is not a number of the force; sensitivities are taken to one (forces.0.k2)");
  try {
    return node->as_double();
  } catch (const SceneError&) {
    throw SceneError(where + "is not a number of the force; sensitivities are taken to one (forces.0.k2)");
  }
}

// The key's value in the scene (a vector field's three numbers; 0 where the scene leaves it out).
std::vector<double> value_of(const Scene& scene, const Key& key) {
  if (key.field == "G") return {scene.system.G()};
  const Params& item = scene.root.at("bodies").items()[key.body];
  if (key.field == "mass" || key.field == "density") return {item.at(key.field).as_double()};
  if (key.field == "inertia") return item.at("inertia").as_doubles();
  if (key.field == kSemiAxes) return item.at("shape").at("ellipsoid").at("semi_axes").as_doubles();
  if (key.field == kScale) {
    const Params& polyhedron = item.at("shape").at("polyhedron");
    return polyhedron.has("scale") ? polyhedron.at("scale").as_doubles() : std::vector<double>{1.0, 1.0, 1.0};
  }
  if (key.field.compare(0, 6, "orbit.") == 0) {
    const Params& orbit = item.at("orbit");
    const std::string name = key.field.substr(6);
    return {orbit.has(name) ? orbit.at(name).as_double() : 0.0};
  }
  if (!item.has(key.field)) return {0.0, 0.0, 0.0};
  std::vector<double> v = item.at(key.field).as_doubles();
  if (v.size() != 3) throw SceneError(item.at(key.field).here() + key.field + " must be three numbers");
  return v;
}

}  // namespace

double sensitivity_key_value(const Scene& scene, const std::string& column) {
  if (column.compare(0, 7, "forces.") == 0) return force_key_value(scene, column);
  if (column.compare(0, 9, "impulses.") == 0) {
    const auto [index, component] = parse_impulse_key(scene, column);
    if (component < 0)
      throw SceneError("'" + column + "': give one component of the impulse's delta_v (" + column + ".0, .1 or .2)");
    const Params& impulse = scene.root.at("impulses").items()[index];
    return component == 3 ? impulse.at("time").as_double()
                          : impulse.at("delta_v").as_doubles().at(static_cast<std::size_t>(component));
  }
  const Key key = parse_key(scene, column);
  if (key.field == "attitude")
    throw SceneError("'" + column + "' is a rotation of the body's attitude, not a value the scene writes");
  const std::vector<double> values = value_of(scene, key);
  if (values.size() > 1 && key.component < 0)
    throw SceneError("'" + column + "' has " + std::to_string(values.size()) + " components: give one (" + column + ".0, …)");
  return values.at(key.component < 0 ? 0 : static_cast<std::size_t>(key.component));
}

namespace {

// The scene with one more `--set` assignment ("bodies.beta.mass=…"), or nothing if the scene
// refuses that value (a bound).
std::optional<Scene> scene_with(const Scene& scene, const std::string& assignment) {
  std::vector<std::string> overrides = scene.overrides;
  overrides.push_back(assignment);
  try {
    return parse_scene(scene.text, scene.file, overrides);
  } catch (const SceneError&) {
    return std::nullopt;
  }
}

// The pair models (what a tolerance chose at the scene's initial state) of a model and of a
// scene's forces, for comparison with a perturbed scene's.
std::vector<std::string> choices(const Potential& potential, const Forcing* forcing) {
  std::vector<std::string> out;
  for (const PairModel& pair : potential.pair_models(*potential.make_workspace()))
    out.push_back(pair.body_a + "–" + pair.body_b + ": " + pair.model);
  if (forcing)
    for (const ForceTerm& term : *forcing)
      for (const PairModel& pair : term.model->pair_models())
        out.push_back(pair.body_a + "–" + term.name + ": " + pair.model);
  return out;
}

}  // namespace

SceneSensitivity scene_sensitivity(const Scene& scene, const std::vector<std::string>& keys, const Potential& model,
                                   const PotentialMaker& make_potential, const ForcingMaker& make_forcing) {
  const System& system = scene.system;
  const Eigen::Index rows = State::tangent_rows(system);
  const Eigen::Index n = static_cast<Eigen::Index>(system.size());
  SceneSensitivity out;
  std::vector<Eigen::VectorXd> columns;                     // keys of the initial state
  std::vector<std::string> parameter_names;                 // parameters of the dynamics, after them
  std::vector<Eigen::VectorXd> parameter_columns;
  auto parameters = std::make_shared<ParameterDerivatives>();
  std::optional<std::vector<std::string>> base_choices;  // the run's model's choices, once needed
  // A parameter of the dynamics (§22): the start, masses, inertias, model and forces, each by
  // the fourth-order central stencil (f(p−2d) − 8f(p−d) + 8f(p+d) − f(p+2d)) / 12d, d = 1e-4
  // |p|: exact for polynomials of degree 4 (a series' inertia integrals in a semi-axis up to
  // order 4), and the larger step keeps the round-off of a weak dependence (the orbit's speed on
  // a light moon's mass, ∝ m/M) below 1e-9 (22.1). `moved(offset)`: the scene with p moved by
  // offset, or nothing where it refuses that value; `potential_moves`: false for a parameter of
  // the forces alone (a tide's k2), whose models would all be the run's.
  auto add_parameter = [&](const std::string& name, double value, double scale,
                           const std::function<std::optional<Scene>(double)>& moved, bool potential_moves) {
    const double d = 1e-4 * scale;
    DynamicsParameter p;
    p.name = name;
    p.mass = Eigen::VectorXd::Zero(n);
    p.inertia.assign(system.rigid_count(), Mat3::Zero());
    Eigen::VectorXd col = Eigen::VectorXd::Zero(rows);
    for (const auto& [offset, weight] : {std::pair{-2.0, 1.0}, {-1.0, -8.0}, {1.0, 8.0}, {2.0, -1.0}}) {
      const auto other = moved(offset * d);
      if (!other)
        throw SceneError("run.sensitivities: '" + name + "': the scene refuses the key moved by " + number(offset * d) +
                         " from " + number(value) + ", so its derivative cannot be taken there");
      const double w = weight / (12.0 * d);
      col += w * State::difference(scene.initial, other->initial);
      for (std::size_t i = 0; i < system.size(); ++i) p.mass(static_cast<Eigen::Index>(i)) += w * other->system.body(i).mass;
      for (std::size_t r = 0; r < system.rigid_count(); ++r)
        p.inertia[r] += w * other->system.body(system.body_of_rigid(r)).inertia;
      p.weights.push_back(w);
      if (!scene.forces.empty()) {  // the forces at p_s, for the systems at p_s           (33.9)
        p.forcings.push_back(make_forcing(*other));
        p.systems.push_back(other->system);
      }
      // The stencil's models must be the run's: the same orders chosen where a tolerance chooses.
      if (!base_choices) base_choices = choices(model, scene.forces.empty() ? nullptr : make_forcing(scene).get());
      const std::shared_ptr<const Potential> moved_model = potential_moves ? make_potential(*other) : nullptr;
      if (moved_model) p.models.push_back(moved_model);
      if (choices(moved_model ? *moved_model : model, p.forcings.empty() ? nullptr : p.forcings.back().get()) !=
          *base_choices) {
        std::string was;
        for (const std::string& c : *base_choices) was += (was.empty() ? "" : "; ") + c;
        throw SceneError("run.sensitivities: '" + name + "': the model's choices (" + was +
                         ") change when the key moves by " + number(offset * d) +
                         ": fix the model's order instead of a tolerance for this run");
      }
    }
    if (!col.allFinite())
      throw SceneError("run.sensitivities: '" + name + "': the initial state's derivative is not finite");
    parameters->parameters.push_back(std::move(p));
    parameter_columns.push_back(col);
    parameter_names.push_back(name);
  };
  for (const std::string& text : keys) {
    if (text.compare(0, 7, "forces.") == 0) {  // a parameter of the forces alone            (33.9)
      const double value = force_key_value(scene, text);
      if (!(std::abs(value) > 0.0))
        throw SceneError("run.sensitivities: '" + text + "' is 0 in the scene: no scale to difference it on");
      add_parameter(text, value, std::abs(value),
                    [&](double offset) { return scene_with(scene, text + "=" + number(value + offset)); }, false);
      continue;
    }
    if (text.compare(0, 9, "impulses.") == 0) {  // 0 at t0: the run adds m e_a at the impulse (24.2)
      const auto [index, component] = parse_impulse_key(scene, text);
      if (component == 3) {  // the time: the run adds the jump of the vector field there (24.7)
        columns.push_back(Eigen::VectorXd::Zero(rows));
        out.names.push_back("impulses." + std::to_string(index) + ".time");
        continue;
      }
      for (int a = 0; a < 3; ++a) {
        if (component >= 0 && a != component) continue;
        columns.push_back(Eigen::VectorXd::Zero(rows));
        out.names.push_back("impulses." + std::to_string(index) + ".delta_v." + std::to_string(a));
      }
      continue;
    }
    const Key key = parse_key(scene, text);
    if (key.field == "attitude") {  // exact: the columns are the attitude's own coordinates θ
      const Eigen::Index r = system.rigid_index(key.body);
      for (int a = 0; a < 3; ++a) {
        if (key.component >= 0 && a != key.component) continue;
        Eigen::VectorXd col = Eigen::VectorXd::Zero(rows);
        col(3 * n + 3 * r + a) = 1.0;
        columns.push_back(col);
        out.names.push_back(key.body_key + ".attitude." + "xyz"[a]);
      }
      continue;
    }
    const std::vector<double> base = value_of(scene, key);
    double scale = key.dynamics ? 0.0 : 1.0;  // a parameter's own scale (a mass of 1e11 kg, G = 6.7e-11)
    for (double v : base) scale = std::max(scale, std::abs(v));
    if (base.size() == 3) scale = std::max(scale, std::hypot(base[0], base[1], base[2]));
    if (!(scale > 0.0)) throw SceneError("run.sensitivities: '" + text + "' is 0 in the scene: no scale to difference it on");
    const double delta = 1e-6 * scale;
    for (std::size_t a = 0; a < base.size(); ++a) {
      if (key.component >= 0 && static_cast<int>(a) != key.component) continue;
      const std::string name = base.size() == 3 ? key.path() + "." + std::to_string(a) : key.path();
      // The scene with the key moved by `offset`, or nothing if the scene refuses that value (a bound).
      auto moved = [&](double offset) -> std::optional<Scene> {
        std::vector<double> v = base;
        v[a] += offset;
        std::string assignment = key.path() + "=";
        if (v.size() == 3)
          assignment += "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
        else
          assignment += number(v[0]);
        std::optional<Scene> other = scene_with(scene, assignment);
        if (!other) return other;
        if (other->system.size() != system.size() || other->system.rigid_count() != system.rigid_count())
          throw SceneError("run.sensitivities: '" + text + "' changes which bodies the scene has");
        for (std::size_t i = 0; i < system.size() && !key.dynamics; ++i)
          if (other->system.body(i).mass != system.body(i).mass || other->system.body(i).inertia != system.body(i).inertia)
            throw SceneError("run.sensitivities: '" + text + "' changes the dynamics, not only the initial state");
        return other;
      };
      if (!key.dynamics) {
        Eigen::VectorXd col;
        const auto plus = moved(delta), minus = moved(-delta);
        if (plus && minus) {  // central: error O(δ²)
          col = State::difference(minus->initial, plus->initial) / (2.0 * delta);
        } else {  // one-sided, second order: (−3 z(0) + 4 z(±δ) − z(±2δ)) / (±2δ)
          const double s = plus ? 1.0 : -1.0;
          const auto one = plus ? plus : minus, two = moved(2.0 * s * delta);
          if (!one || !two)
            throw SceneError("run.sensitivities: '" + name + "': the scene refuses the key moved by ±" + number(delta) +
                             " from " + number(base[a]) + " either way, so its derivative cannot be taken there");
          col = (4.0 * State::difference(scene.initial, one->initial) - State::difference(scene.initial, two->initial)) /
                (2.0 * s * delta);
        }
        if (!col.allFinite())
          throw SceneError("run.sensitivities: '" + name + "': the initial state's derivative is not finite");
        columns.push_back(col);
        out.names.push_back(name);
        continue;
      }
      add_parameter(name, base[a], scale, moved, true);
    }
  }
  out.names.insert(out.names.end(), parameter_names.begin(), parameter_names.end());
  columns.insert(columns.end(), parameter_columns.begin(), parameter_columns.end());
  for (std::size_t c = 0; c < out.names.size(); ++c)
    if (std::find(out.names.begin(), out.names.begin() + static_cast<std::ptrdiff_t>(c), out.names[c]) !=
        out.names.begin() + static_cast<std::ptrdiff_t>(c))
      throw SceneError("run.sensitivities: " + out.names[c] + " is asked for twice");
  out.columns.resize(rows, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) out.columns.col(static_cast<Eigen::Index>(c)) = columns[c];
  if (parameters->size() > 0) out.parameters = parameters;
  return out;
}

}  // namespace noether
