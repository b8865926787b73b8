#pragma once
// Solid: a homogeneous body of a given shape — a triaxial ellipsoid or a closed polyhedron —
// in its body frame: origin at its centre of mass and, unless asked otherwise, axes along
// its principal axes (docs/equations.md §11).
#include <noether/inertia_integrals.hpp>
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <memory>
#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct Solid {
  enum class Kind { Ellipsoid, Polyhedron };
  Kind kind = Kind::Ellipsoid;
  double density = 0.0;
  double volume = 0.0;
  double mass = 0.0;
  Mat3 inertia = Mat3::Zero();    // about the centre of mass, body frame
  double radius = 0.0;            // largest distance of the surface from the centre of mass
  Vec3 semi_axes = Vec3::Zero();  // ellipsoid: along body x, y, z
  Mesh mesh;                      // polyhedron: vertices in the body frame
  // Placement of a mesh: x_file = offset + rotation · diag(stretch)⁻¹ · x_body (identity for an
  // ellipsoid; stretch: the factors a scene's `scale` stretched the mesh by along the body axes).
  Vec3 offset = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  Vec3 stretch = Vec3::Ones();

  // T^{lmn} to total degree `order` (ellipsoid closed form; polyhedron exact).
  InertiaIntegrals integrals(int order) const;
  std::string describe() const;  // "ellipsoid 400 × 395 × 340" or "polyhedron (1148 vertices, 2292 faces)"
};

std::shared_ptr<const Solid> make_ellipsoid(const Vec3& semi_axes, double density);

// A polyhedron stretched by the factors `scale` along its body axes, about its centre of mass:
// the same axes (principal axes stay principal), the mass properties of the stretched mesh, the
// placement in the file kept (`stretch` records the factors).
std::shared_ptr<const Solid> stretched_polyhedron(const Solid& polyhedron, const Vec3& scale);

// Validates the mesh, moves it to its centre of mass and — if `principal_axes` — rotates it
// onto its principal axes (taken in the order and sense closest to the file's axes; left
// alone when the file's products of inertia already vanish to 1e-12).
std::shared_ptr<const Solid> make_polyhedron(Mesh mesh, double density, bool principal_axes);

}  // namespace noether

#pragma GCC visibility pop
