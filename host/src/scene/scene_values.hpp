#pragma once
// The value readers every section of a scene shares: vectors and matrices, a body's inertia, a
// file the scene names, a body named by a key. Each throws SceneError with the value's file:line.
#include <noether/params.hpp>
#include <noether/system.hpp>

#include <filesystem>
#include <string>

namespace noether::detail {

Vec3 vec3(const Params& p);
// A 3×3 matrix from [[a,b,c],[d,e,f],[g,h,i]].
Mat3 mat3(const Params& p);
// Principal moments [J1, J2, J3] or a 3×3 matrix.
Mat3 inertia(const Params& p);
// A file a scene names (`f`): relative to the scene file's folder, not to the working directory,
// so that a copied scene without its files is told where they were looked for.
std::filesystem::path scene_file(const Params& f, const std::filesystem::path& folder, const std::string& who,
                                 const std::string& what);
// The index of the body a key names, or SceneError naming the key (and the closest name).
std::size_t body_named(const Params& key, const System& system);
// The heaviest body other than `body` (the first of equals).
std::size_t heaviest_other(const System& system, std::size_t body);

}  // namespace noether::detail
