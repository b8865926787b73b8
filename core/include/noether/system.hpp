#pragma once
// System: the constants of a scene (docs/equations.md §1). Bodies with an inertia are rigid bodies on
// SE(3); bodies without one are point masses and carry no attitude at all.
#include <noether/lie.hpp>
#include <noether/params.hpp>
#include <noether/solid.hpp>
#include <noether/stokes_coefficients.hpp>

#include <memory>

#include <string>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct Body {
  std::string name;
  double mass = 0.0;
  bool rigid = false;
  Mat3 inertia = Mat3::Zero();              // J, standard inertia, body frame (rigid only)
  Mat3 inertia_inverse = Mat3::Zero();      // J⁻¹
  Mat3 inertia_nonstandard = Mat3::Zero();  // Jd = ½ tr(J) I − J
  Params shape;                             // the scene's `shape` mapping, as given
  // The homogeneous solid (ellipsoid or polyhedron) when the shape is one; its mass and
  // inertia are the body's. Null for point masses and point clusters.
  std::shared_ptr<const Solid> solid;
  // A body given by its gravity field (the scene's `gravity:`): its Stokes coefficients about its
  // centre of mass in its body frame, mass = the body's. Its inertia integrals to the field's
  // degree are field_integrals(*field, ½ tr J) (docs/equations.md (31.3)–(31.4)). Null otherwise.
  std::shared_ptr<const StokesCoefficients> field;
  // The radius of a sphere about the centre of mass that holds the body: the solid's, or the
  // scene's `radius`; 0 when unknown. Collision events use it (docs/equations.md §16).
  double radius = 0.0;
};

class System {
 public:
  System() = default;
  // Validates the physics (positive masses, symmetric positive-definite inertia that satisfies
  // the triangle inequality, unique names) and fills the derived inertia matrices.
  // Throws SceneError with `where` prefixed when given.
  System(double G, std::vector<Body> bodies);

  double G() const { return G_; }
  const std::vector<Body>& bodies() const { return bodies_; }
  const Body& body(std::size_t i) const { return bodies_[i]; }
  std::size_t size() const { return bodies_.size(); }
  std::size_t rigid_count() const { return body_of_rigid_.size(); }
  // Index into the rigid-body arrays of State, or -1 for a point mass.
  int rigid_index(std::size_t body) const { return rigid_of_body_[body]; }
  std::size_t body_of_rigid(std::size_t k) const { return body_of_rigid_[k]; }
  // Why `name` cannot name a body ("" when it can): names become HDF5 group names and --set
  // path components, so no '/' and no control characters.
  static std::string name_problem(const std::string& name);
  int index_of(const std::string& name) const;  // -1 if absent

 private:
  double G_ = 1.0;
  std::vector<Body> bodies_;
  std::vector<int> rigid_of_body_;
  std::vector<std::size_t> body_of_rigid_;
};

// Checks that J is symmetric positive definite and satisfies the triangle inequality of
// principal moments (J1 + J2 ≥ J3 and permutations). Throws SceneError with `context`.
void validate_inertia(const Mat3& J, const std::string& context);

}  // namespace noether

#pragma GCC visibility pop
