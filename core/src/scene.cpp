#include <noether/error.hpp>
#include <noether/scene.hpp>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace noether {

namespace {

// YAML → Params, keeping "file:line" of every node.
Params to_params(const YAML::Node& node, const std::string& file) {
  const std::string where =
      node.Mark().line >= 0 ? file + ":" + std::to_string(node.Mark().line + 1) : file;
  switch (node.Type()) {
    case YAML::NodeType::Scalar: return Params::scalar(node.Scalar(), where);
    case YAML::NodeType::Sequence: {
      std::vector<Params> items;
      for (const auto& item : node) items.push_back(to_params(item, file));
      return Params::sequence(std::move(items), where);
    }
    case YAML::NodeType::Map: {
      std::vector<std::pair<std::string, Params>> entries;
      for (const auto& kv : node) {
        const std::string key = kv.first.as<std::string>();
        for (const auto& e : entries)
          if (e.first == key)
            throw SceneError(file + ":" + std::to_string(kv.first.Mark().line + 1) +
                             ": key '" + key + "' appears twice");
        entries.emplace_back(key, to_params(kv.second, file));
      }
      return Params::map(std::move(entries), where);
    }
    default: return Params::scalar("", where);  // an empty value
  }
}

Params parse_yaml(const std::string& text, const std::string& file) {
  try {
    return to_params(YAML::Load(text), file);
  } catch (const YAML::ParserException& e) {
    std::ostringstream msg;
    msg << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
        << ": malformed YAML: " << e.msg;
    throw SceneError(msg.str());
  }
}

// "--set a.b.c=value": edits the tree in place.
void apply_override(Params& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--set '" + assignment + "': expected key=value, e.g. integrator.step=1e-3");
  const std::string key = assignment.substr(0, eq);
  const std::string where = "--set " + key;
  Params value = parse_yaml(assignment.substr(eq + 1), where);
  if (value.is_null()) value = Params::scalar("", where);

  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  Params* node = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& part = parts[i];
    Params* next = nullptr;
    if (node->is_map()) {
      next = node->find(part);
    } else if (node->is_sequence()) {
      auto& items = node->mutable_items();
      bool numeric = !part.empty() && part.find_first_not_of("0123456789") == std::string::npos;
      if (numeric && std::stoul(part) < items.size()) next = &items[std::stoul(part)];
      for (auto& item : items)  // bodies by name
        if (!next && item.is_map() && item.has("name") && item.at("name").is_scalar() &&
            item.at("name").as_string() == part)
          next = &item;
    }
    if (!next)
      throw SceneError("--set " + key + ": the scene has no '" + part + "' at '" +
                       (node->path().empty() ? std::string("top level") : node->path()) + "'");
    node = next;
  }
  if (!node->is_map() && !node->is_null())
    throw SceneError("--set " + key + ": '" + node->path() + "' is not a mapping");
  node->set(parts.back(), std::move(value));
}

Vec3 vec3(const Params& p) {
  const auto v = p.as_doubles();
  if (v.size() != 3)
    throw SceneError(p.here() + "'" + p.path() + "' must have 3 components, not " +
                     std::to_string(v.size()));
  return Vec3(v[0], v[1], v[2]);
}

// A 3×3 matrix from [[a,b,c],[d,e,f],[g,h,i]].
Mat3 mat3(const Params& p) {
  if (!p.is_sequence() || p.size() != 3)
    throw SceneError(p.here() + "'" + p.path() + "' must be a 3×3 matrix: three rows of three");
  Mat3 m;
  for (int r = 0; r < 3; ++r) m.row(r) = vec3(p.items()[static_cast<std::size_t>(r)]).transpose();
  return m;
}

Mat3 inertia(const Params& p) {
  if (p.is_sequence() && p.size() == 3 && p.items()[0].is_scalar())
    return vec3(p).asDiagonal();  // principal moments
  if (p.is_sequence() && p.size() == 3) return mat3(p);
  throw SceneError(p.here() + "'" + p.path() +
                   "' must be three principal moments [J1, J2, J3] or a 3×3 matrix");
}

Mat3 attitude(const Params& p, const std::string& body) {
  Mat3 R;
  if (p.is_map()) {
    p.check_keys({"quaternion", "matrix"}, "attitude of body '" + body + "'");
    if (p.has("matrix")) return attitude(p.at("matrix"), body);
    const auto q = p.at("quaternion").as_doubles();
    if (q.size() != 4)
      throw SceneError(p.here() + "quaternion of body '" + body + "' needs 4 numbers [w, x, y, z]");
    const Vec4 qv(q[0], q[1], q[2], q[3]);
    if (std::abs(qv.norm() - 1.0) > 1e-9) {
      std::ostringstream msg;
      msg << p.here() << "quaternion of body '" << body << "' has norm " << qv.norm()
          << "; a rotation needs a unit quaternion (scalar first)";
      throw SceneError(msg.str());
    }
    R = rotation_from_quaternion(qv);
  } else {
    R = mat3(p);
  }
  const double err = orthogonality_error(R);
  if (err > 1e-10 || R.determinant() <= 0.0) {
    std::ostringstream msg;
    msg << p.here() << "attitude of body '" << body
        << "' is not a rotation matrix: ‖I − RᵀR‖ = " << err << ", det R = " << R.determinant()
        << " (needs ‖I − RᵀR‖ ≤ 1e-10 and det R = +1)";
    throw SceneError(msg.str());
  }
  return R;
}

PluginConfig plugin_config(const Params& p, const std::string& what) {
  if (!p.is_map() || !p.has("plugin"))
    throw SceneError(p.here() + "'" + p.path() + "' must be a mapping naming a plugin, e.g. " +
                     what + ": {plugin: NAME}");
  return {p.at("plugin").as_string(), p};
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::string>& overrides) {
  Scene scene;
  scene.file = file;
  scene.text = text;
  scene.overrides = overrides;
  Params root = parse_yaml(text, file);
  if (!root.is_map()) throw SceneError(file + ": a scene must be a YAML mapping (G, bodies, ...)");
  for (const auto& o : overrides) apply_override(root, o);
  root.set_path("");
  root.check_keys({"description", "G", "bodies", "potential", "integrator", "run"}, "the scene");
  const double G = root.get("G", 1.0);

  // Bodies: constants into System, initial values into State.
  const Params& bodies = root.at("bodies");
  if (!bodies.is_sequence() || bodies.size() == 0)
    throw SceneError(bodies.here() + "'bodies' must be a non-empty list of bodies");
  std::vector<Body> list;
  for (const auto& b : bodies.items()) {
    if (!b.is_map()) throw SceneError(b.here() + "each body must be a mapping");
    b.check_keys({"name", "mass", "inertia", "position", "velocity", "attitude",
                  "angular_velocity", "angular_momentum", "shape"},
                 "body '" + b.get("name", std::string("?")) + "'");
    Body body;
    body.name = b.at("name").as_string();
    body.mass = b.at("mass").as_double();
    if (!std::isfinite(body.mass) || body.mass <= 0.0)
      throw SceneError(b.at("mass").here() + "body '" + body.name + "': mass must be positive, not " +
                       b.at("mass").as_string());
    body.rigid = b.has("inertia");
    if (body.rigid) {
      body.inertia = inertia(b.at("inertia"));
      validate_inertia(body.inertia, b.at("inertia").here() + "body '" + body.name + "'");
    }
    if (b.has("shape")) body.shape = b.at("shape");
    if (!body.rigid)
      for (const char* key : {"attitude", "angular_velocity", "angular_momentum"})
        if (b.has(key))
          throw SceneError(b.at(key).here() + "body '" + body.name + "' has no 'inertia', so it" +
                           " is a point mass and cannot have '" + key +
                           "'; add 'inertia' to make it a rigid body");
    if (b.has("angular_velocity") && b.has("angular_momentum"))
      throw SceneError(b.here() + "body '" + body.name +
                       "': give 'angular_velocity' or 'angular_momentum', not both");
    list.push_back(std::move(body));
  }
  try {
    scene.system = System(G, std::move(list));  // validates what is left: G, unique names
  } catch (const SceneError& e) {
    throw SceneError((root.has("G") ? root.at("G").here() : bodies.here()) + e.what());
  }

  const System& sys = scene.system;
  State s = State::zeros(sys);
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Params& b = bodies.items()[i];
    const Body& body = sys.body(i);
    const auto col = static_cast<Eigen::Index>(i);
    s.x.col(col) = vec3(b.at("position"));
    if (b.has("velocity")) s.p.col(col) = body.mass * vec3(b.at("velocity"));
    if (const int k = sys.rigid_index(i); k >= 0) {
      if (b.has("attitude")) s.R[static_cast<std::size_t>(k)] = attitude(b.at("attitude"), body.name);
      if (b.has("angular_velocity"))
        s.Pi.col(k) = body.inertia * vec3(b.at("angular_velocity"));  // Π = J Ω
      if (b.has("angular_momentum")) s.Pi.col(k) = vec3(b.at("angular_momentum"));
    }
  }
  for (std::size_t i = 0; i < sys.size(); ++i)
    for (std::size_t j = i + 1; j < sys.size(); ++j)
      if ((s.x.col(static_cast<Eigen::Index>(i)) - s.x.col(static_cast<Eigen::Index>(j)))
              .norm() == 0.0)
        throw SceneError(bodies.items()[j].here() + "bodies '" + sys.body(i).name + "' and '" +
                         sys.body(j).name + "' start at the same position");
  scene.initial = std::move(s);

  // Models, integrator, run.
  const Params& potential = root.at("potential");
  if (potential.is_sequence()) {
    for (const auto& item : potential.items())
      scene.potentials.push_back(plugin_config(item, "potential"));
    if (scene.potentials.empty())
      throw SceneError(potential.here() + "'potential' must name at least one plugin");
  } else {
    scene.potentials.push_back(plugin_config(potential, "potential"));
  }
  scene.integrator = plugin_config(root.at("integrator"), "integrator");
  const Params& run = root.at("run");
  run.check_keys({"t_end", "output_every"}, "'run'");
  scene.run.t_end = run.at("t_end").as_double();
  scene.run.output_every = run.at("output_every").as_double();
  if (scene.run.t_end <= 0.0)
    throw SceneError(run.at("t_end").here() + "'run.t_end' must be positive");
  if (scene.run.output_every <= 0.0 || scene.run.output_every > scene.run.t_end)
    throw SceneError(run.at("output_every").here() +
                     "'run.output_every' must be positive and at most run.t_end");
  scene.root = std::move(root);
  return scene;
}

namespace {
std::string read_file(const std::filesystem::path& file, const char* what) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the " + what);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}
}  // namespace

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  return parse_scene(read_file(file, "scene file"), file.string(), overrides);
}

Params parse_params(const std::string& text, const std::string& file) {
  Params p = parse_yaml(text, file);
  p.set_path("");
  return p;
}

Params load_params_file(const std::filesystem::path& file) {
  return parse_params(read_file(file, "file"), file.string());
}

}  // namespace noether
