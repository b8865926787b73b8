#pragma once
// The exact mutual potential of two homogeneous bodies (docs/equations.md §14): one body's
// exact exterior field integrated over the other's surface, refined until two successive
// quadrature levels agree to a tolerance; or, when the surface body's circumscribed sphere is
// far enough from the field body, the exact field sampled on that sphere, expanded in solid
// harmonics and integrated through the surface body's moments, its degree raised until two
// agree (§37). Same frames and outputs as MutualSeries.
#include <noether/gravity_field.hpp>
#include <noether/mutual_series.hpp>
#include <noether/solid.hpp>

#include <memory>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct ExactMutualOptions {
  double tolerance = 1e-12;  // relative change of U, ∂U/∂R and torques between two levels
  int max_level = 7;         // polyhedra: 2, 3, 4, 6, 8, 12, 16, 24 points a side
  enum class Surface { Automatic, A, B } surface = Surface::Automatic;  // whose surface
  // Automatic: the expansion (§37) where the field is a polyhedron's and the expansion converges
  // by degree 40 at fewer field evaluations than the quadrature's first two levels, else the
  // quadrature; Expansion: wherever it converges by degree 40, an error elsewhere.
  enum class Method { Automatic, Quadrature, Expansion } method = Method::Automatic;
};

class ExactMutual {
 public:
  // A null solid is a point mass of the given mass.
  ExactMutual(double G, std::shared_ptr<const Solid> A, double mass_A,
              std::shared_ptr<const Solid> B, double mass_B, ExactMutualOptions options = {});
  ~ExactMutual();
  ExactMutual(ExactMutual&&) noexcept;

  // R: B's centre of mass minus A's, in A's frame; C: B's frame → A's frame. Throws Error if
  // the bodies overlap or the quadrature does not reach the tolerance.
  MutualTerms evaluate(const Vec3& R, const Mat3& C);
  // The terms and their derivatives J (MutualJacobian's frames; docs/equations.md §26), from the
  // same quadrature, at the level at which the terms meet the tolerance.
  MutualTerms jacobian(const Vec3& R, const Mat3& C, MutualJacobian& J);
  double last_error_estimate() const { return last_error_; }
  int last_level() const { return level_; }  // the quadrature's
  int last_degree() const { return last_degree_; }  // the expansion's; −1: the quadrature was used
  bool surface_is_A() const { return surface_is_A_; }

 private:
  struct Side;
  MutualTerms evaluate_level(int level, const Vec3& R_s, const Mat3& C_s, MutualJacobian* J = nullptr);
  // Levels from 0 until two agree to the tolerance, in the surface's frame.
  MutualTerms refine(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J);
  // The expansion (§37), or false where it does not converge to the tolerance by degree 40.
  bool expand(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J, MutualTerms& out);
  MutualTerms evaluate_in_surface_frame(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J);
  struct Expansion;
  std::unique_ptr<Side> surface_, field_;
  std::unique_ptr<Expansion> expansion_;
  int last_degree_ = -1;
  bool surface_is_A_ = true;
  ExactMutualOptions options_;
  int level_ = 0;
  double last_error_ = 0.0;
};

}  // namespace noether

#pragma GCC visibility pop
