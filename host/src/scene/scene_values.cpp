// The value readers every section of a scene shares (scene_values.hpp).
#include "scene/scene_values.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <vector>

namespace noether::detail {

Vec3 vec3(const Params& p) {
  const auto v = p.as_doubles();
  if (v.size() != 3)
    throw SceneError(p.here() + "'" + p.path() + "' must have 3 components, not " +
                     std::to_string(v.size()));
  return Vec3(v[0], v[1], v[2]);
}

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

std::filesystem::path scene_file(const Params& f, const std::filesystem::path& folder, const std::string& who,
                                 const std::string& what) {
  const std::filesystem::path path(f.as_string());
  const std::filesystem::path resolved = path.is_absolute() ? path : folder / path;
  std::error_code ec;
  if (!std::filesystem::exists(resolved, ec)) {
    const std::filesystem::path shown = std::filesystem::absolute(resolved, ec).lexically_normal();
    throw SceneError(f.here() + who + ": " + what + " '" + f.as_string() + "' not found" +
                     (path.is_absolute() ? std::string() : " (relative to the scene's folder: " + shown.string() + ")"));
  }
  return resolved;
}

std::size_t body_named(const Params& key, const System& system) {
  std::vector<std::string> names;
  for (const auto& b : system.bodies()) names.push_back(b.name);
  const std::string name = key.as_string();
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end()) {
    const std::string near = closest_match(name, names);
    throw SceneError(key.here() + "'" + key.path() + "': no body '" + name + "'" +
                     (near.empty() ? std::string() : "; did you mean '" + near + "'?"));
  }
  return static_cast<std::size_t>(found - names.begin());
}

std::size_t heaviest_other(const System& system, std::size_t body) {
  std::size_t heaviest = body == 0 ? 1 : 0;
  for (std::size_t i = 0; i < system.size(); ++i)
    if (i != body && system.body(i).mass > system.body(heaviest).mass) heaviest = i;
  return heaviest;
}

}  // namespace noether::detail
