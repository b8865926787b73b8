#pragma once
// Exact exterior gravity fields of homogeneous bodies, per unit mass: the potential Φ (< 0)
// and the acceleration g = −∇Φ (docs/equations.md §14), and quadrature rules over their
// surfaces. The fields are the oracle of the mutual potential (mutual-exact plugin, tests).
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct FieldValue {
  double phi = 0.0;      // Φ, potential per unit mass
  Vec3 g = Vec3::Zero(); // −∇Φ
  Mat3 dg = Mat3::Zero();  // ∂g/∂r = −∇∇Φ, when asked for (`with_gradient`); zero otherwise
  bool inside = false;   // the point lies inside the body (Φ is then not harmonic there)
};

// Werner & Scheeres 1997 Eq. 8, 15: sums over edges and faces of a closed polyhedron.
class PolyhedronField {
 public:
  PolyhedronField(const Mesh& mesh, double G_density);
  // With `with_gradient`, also ∂g/∂r = Gρ (Σ_e E_e L_e − Σ_f F_f ω_f) (26.2; Werner & Scheeres 1997 Eq. 16).
  FieldValue operator()(const Vec3& r, bool with_gradient = false) const;

 private:
  double Grho_;
  Eigen::Matrix3Xd vertices_;
  struct Face {
    std::array<int, 3> v;
    Mat3 F;  // n nᵀ
  };
  struct Edge {
    int i, j;
    double length;
    Mat3 E;  // n_A n_Aeᵀ + n_B n_Beᵀ
  };
  std::vector<Face> faces_;
  std::vector<Edge> edges_;
};

// MacMillan 1930: Φ = −πGρabc [I₀(λ) − Σ x_i² I_i(λ)], with Carlson's R_F and R_D.
class EllipsoidField {
 public:
  EllipsoidField(const Vec3& semi_axes, double G_density);
  // With `with_gradient`, also ∂g/∂r (docs/equations.md (26.1)).
  FieldValue operator()(const Vec3& r, bool with_gradient = false) const;

 private:
  Vec3 a2_;
  double k_;  // πGρabc
};

// Points x_k and vector areas w_k = n dS_k whose sums approximate ∮ f(x) n dS.
struct SurfaceRule {
  std::vector<Vec3> points;
  std::vector<Vec3> areas;
};

// Collapsed (Duffy) Gauss–Legendre with n × n points on every face.
SurfaceRule polyhedron_surface_rule(const Mesh& mesh, int n);
// Gauss–Legendre in cos θ (n_theta points) × trapezoid in φ (n_phi points): spectral.
SurfaceRule ellipsoid_surface_rule(const Vec3& semi_axes, int n_theta, int n_phi);

// Gauss–Legendre nodes and weights on [0, 1].
void gauss_legendre01(int n, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace noether

#pragma GCC visibility pop
