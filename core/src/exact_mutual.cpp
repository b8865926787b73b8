#include <noether/error.hpp>
#include <noether/exact_mutual.hpp>
#include <noether/solid_harmonics.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace noether {

namespace {

// The change from `a` to `b` relative to b: of U, of ∂U/∂R, and of the torques against |R||∂U/∂R|.
double relative_change(const MutualTerms& a, const MutualTerms& b, const Vec3& R) {
  const double F = std::max(b.dU_dR.norm(), 1e-300);
  const double T = F * R.norm();
  return std::max({std::abs(a.U - b.U) / std::abs(b.U), (a.dU_dR - b.dU_dR).norm() / F,
                   (a.torque_A - b.torque_A).norm() / T, (a.torque_B - b.torque_B).norm() / T});
}

}  // namespace

// What the expansion (§37) keeps between evaluations: the surface body's moments and the
// sphere rules of the degrees used (neither changes a result).
struct ExactMutual::Expansion {
  SolidHarmonicMoments moments;
  std::map<int, SphereProjection> projections;
};

// One body in one of the two roles: its field, or its surface at each quadrature level.
struct ExactMutual::Side {
  std::shared_ptr<const Solid> solid;  // null: a point mass
  double mass = 0.0;
  double G = 0.0;
  std::unique_ptr<PolyhedronField> polyhedron;
  std::unique_ptr<EllipsoidField> ellipsoid;
  std::map<int, SurfaceRule> rules;

  FieldValue field(const Vec3& y, bool with_gradient = false) const {
    if (polyhedron) return (*polyhedron)(y, with_gradient);
    if (ellipsoid) return (*ellipsoid)(y, with_gradient);
    FieldValue v;  // a point mass
    const double r = y.norm();
    v.phi = -G * mass / r;
    v.g = (-G * mass / (r * r * r)) * y;
    if (with_gradient) v.dg = (-G * mass / (r * r * r)) * (Mat3::Identity() - (3.0 / (r * r)) * y * y.transpose());
    v.inside = !(r > 0.0);
    return v;
  }
  // Polyhedra: n × n points a face; ellipsoids: n × 2n points (14.7).
  int points_a_side(int level) const {
    static const int points[] = {2, 3, 4, 6, 8, 12, 16, 24, 32, 48};
    return solid->kind == Solid::Kind::Polyhedron ? points[std::min(level, 9)] : 12 * (level + 1);
  }
  std::size_t rule_size(int level) const {
    const auto n = static_cast<std::size_t>(points_a_side(level));
    return solid->kind == Solid::Kind::Polyhedron ? solid->mesh.faces.size() * n * n : 2 * n * n;
  }
  const SurfaceRule& rule(int level) {
    auto it = rules.find(level);
    if (it != rules.end()) return it->second;
    const int n = points_a_side(level);
    SurfaceRule r = solid->kind == Solid::Kind::Polyhedron ? polyhedron_surface_rule(solid->mesh, n)
                                                           : ellipsoid_surface_rule(solid->semi_axes, n, 2 * n);
    return rules.emplace(level, std::move(r)).first->second;
  }
};

ExactMutual::~ExactMutual() = default;
ExactMutual::ExactMutual(ExactMutual&&) noexcept = default;

ExactMutual::ExactMutual(double G, std::shared_ptr<const Solid> A, double mass_A,
                         std::shared_ptr<const Solid> B, double mass_B, ExactMutualOptions options)
    : options_(options) {
  // The field is the cheaper one to evaluate: an ellipsoid's (a few elliptic integrals) or a
  // point mass's over a polyhedron's (a sum over all its edges and faces); between two
  // polyhedra, the surface of the one with fewer faces. A point mass is always the surface
  // (a single point) unless both are.
  auto cost = [](const std::shared_ptr<const Solid>& s) {
    if (!s) return 0.0;
    if (s->kind == Solid::Kind::Ellipsoid) return 1.0;
    return 2.0 + static_cast<double>(s->mesh.faces.size());
  };
  switch (options.surface) {
    case ExactMutualOptions::Surface::A: surface_is_A_ = true; break;
    case ExactMutualOptions::Surface::B: surface_is_A_ = false; break;
    default:
      if (!A) surface_is_A_ = true;
      else if (!B) surface_is_A_ = false;
      else if (cost(A) == 1.0 || cost(B) == 1.0) surface_is_A_ = cost(B) == 1.0;  // ellipsoid field
      else surface_is_A_ = cost(A) <= cost(B);
  }
  auto make_side = [&](std::shared_ptr<const Solid> s, double m, bool as_field) {
    auto side = std::make_unique<Side>();
    side->solid = s;
    side->mass = m;
    side->G = G;
    if (as_field && s) {
      if (s->kind == Solid::Kind::Polyhedron) side->polyhedron = std::make_unique<PolyhedronField>(s->mesh, G * s->density);
      else side->ellipsoid = std::make_unique<EllipsoidField>(s->semi_axes, G * s->density);
    }
    return side;
  };
  surface_ = make_side(surface_is_A_ ? A : B, surface_is_A_ ? mass_A : mass_B, false);
  field_ = make_side(surface_is_A_ ? B : A, surface_is_A_ ? mass_B : mass_A, true);
  expansion_ = std::make_unique<Expansion>();
}

// In the surface body's frame: R_s the field body's centre, C_s its frame → surface frame. With
// J, also the derivatives with respect to R_s and a turn φ of the field body in the surface
// body's axes (26.3–26.5); J's "A" is the surface body, its "B" the field body.
MutualTerms ExactMutual::evaluate_level(int level, const Vec3& R_s, const Mat3& C_s, MutualJacobian* J) {
  MutualTerms t;
  if (!surface_->solid) {  // a point mass: U = m Φ_F(y₀), y₀ = C_sᵀ(−R_s)
    const FieldValue v = field_->field(C_s.transpose() * (-R_s), J != nullptr);
    if (v.inside) throw Error("the point mass lies inside the other body");
    t.U = surface_->mass * v.phi;
    t.dU_dR = surface_->mass * (C_s * v.g);
    t.torque_B = R_s.cross(t.dU_dR);
    if (J) {  // (26.5)
      J->g_R = -surface_->mass * (C_s * v.dg * C_s.transpose());
      J->g_phi = J->g_R * hat(R_s) - hat(t.dU_dR);
      J->tauA_R.setZero(), J->tauA_phi.setZero();
      J->tauB_R = hat(R_s) * J->g_R - hat(t.dU_dR);
      J->tauB_phi = hat(R_s) * J->g_phi;
    }
    return t;
  }
  const SurfaceRule& rule = surface_->rule(level);
  const double rho = surface_->solid->density;
  const Mat3 Ct = C_s.transpose();
  // Partial sums over fixed chunks of points, added in chunk order afterwards: the result
  // does not depend on the number of threads (OpenMP, when the build has it).
  constexpr std::size_t kChunk = 256;
  const std::size_t chunks = (rule.points.size() + kChunk - 1) / kChunk;
  struct Partial {
    double U = 0.0;
    Vec3 flux = Vec3::Zero(), moment = Vec3::Zero();
    Mat3 flux_R = Mat3::Zero(), flux_phi = Mat3::Zero(), moment_R = Mat3::Zero(), moment_phi = Mat3::Zero();
    bool overlap = false;
  };
  std::vector<Partial> partial(chunks);
  const Side& field = *field_;
#pragma omp parallel for schedule(dynamic)
  for (std::size_t c = 0; c < chunks; ++c) {
    Partial& p = partial[c];
    for (std::size_t k = c * kChunk; k < std::min(rule.points.size(), (c + 1) * kChunk); ++k) {
      const Vec3& x = rule.points[k];
      const Vec3& w = rule.areas[k];
      const FieldValue v = field.field(Ct * (x - R_s));
      p.overlap = p.overlap || v.inside;
      const Vec3 g = C_s * v.g;
      // ∇·(xΦ + ½|x|² g) = 3Φ where ∇²Φ = 0 (docs/equations.md (14.1))
      p.U += (x * v.phi + 0.5 * x.squaredNorm() * g).dot(w);
      const Vec3 xw = x.cross(w);
      p.flux += v.phi * w;
      p.moment += v.phi * xw;
      if (J) {  // (26.3): ∂Φ/∂R_s = gᵀ, ∂Φ/∂φ = ((x − R_s) × g)ᵀ
        const Vec3 g_phi = (x - R_s).cross(g);
        p.flux_R += w * g.transpose();
        p.flux_phi += w * g_phi.transpose();
        p.moment_R += xw * g.transpose();
        p.moment_phi += xw * g_phi.transpose();
      }
    }
  }
  double U = 0.0;
  Vec3 flux = Vec3::Zero(), moment = Vec3::Zero();
  Mat3 flux_R = Mat3::Zero(), flux_phi = Mat3::Zero(), moment_R = Mat3::Zero(), moment_phi = Mat3::Zero();
  for (const Partial& p : partial) {
    if (p.overlap) throw Error("the bodies overlap: a point of one surface lies inside the other body");
    U += p.U;
    flux += p.flux;
    moment += p.moment;
    if (J) flux_R += p.flux_R, flux_phi += p.flux_phi, moment_R += p.moment_R, moment_phi += p.moment_phi;
  }
  t.U = rho / 3.0 * U;
  t.dU_dR = -rho * flux;            // (14.2)
  t.torque_A = -rho * moment;       // (14.3), on the surface body
  t.torque_B = R_s.cross(t.dU_dR) - t.torque_A;
  if (J) {  // (26.4)
    J->g_R = -rho * flux_R, J->g_phi = -rho * flux_phi;
    J->tauA_R = -rho * moment_R, J->tauA_phi = -rho * moment_phi;
    J->tauB_R = hat(R_s) * J->g_R - hat(t.dU_dR) - J->tauA_R;
    J->tauB_phi = hat(R_s) * J->g_phi - J->tauA_phi;
  }
  return t;
}

MutualTerms ExactMutual::refine(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J) {
  if (!surface_->solid) {
    last_error_ = 0.0;
    return evaluate_level(0, R_s, C_s, J);
  }
  // With J, each level's derivatives come with its terms (a few products per point beside the
  // field's evaluation there); those of the level that meets the tolerance are kept. Every
  // evaluation starts from level 0, so its result is a function of the configuration alone (a
  // continued run is the uninterrupted one bit for bit).
  int level = 0;
  MutualTerms coarse = evaluate_level(level, R_s, C_s, J);
  for (;;) {
    if (level + 1 > options_.max_level) {
      std::ostringstream msg;
      msg << "mutual-exact: the surface quadrature did not reach the tolerance "
          << options_.tolerance << " (reached " << last_error_ << " at level " << level
          << "); the bodies are too close for the quadrature: raise max_level or the tolerance";
      throw Error(msg.str());
    }
    MutualTerms fine = evaluate_level(level + 1, R_s, C_s, J);
    last_error_ = relative_change(coarse, fine, R_s);
    if (last_error_ <= options_.tolerance) {
      level_ = level + 1;
      return fine;
    }
    coarse = fine;
    ++level;
  }
}

// (37.3)–(37.5): Φ_B and its derivatives sampled on the sphere of radius a (A's circumscribed
// sphere) about A's centre of mass, projected on the solid harmonics of degree ≤ N and
// contracted with A's moments; N raised until the sums to N − 2 and to N agree. False where it
// cannot converge by degree 40 or — method automatic — would not be the faster.
bool ExactMutual::expand(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J, MutualTerms& out) {
  const Solid& body = *surface_->solid;
  const double a = body.radius;
  const double d = R_s.norm() - (field_->solid ? field_->solid->radius : 0.0);  // ≤ distance to B
  if (!(d > a)) return false;
  const double q = a / d;
  constexpr int kMaxDegree = harmonic::kMaxDegree;
  // Degree n adds about qⁿ (37.5): the first guess, raised by 2 until the sums to N − 2 and to
  // N agree. From the configuration alone, as the quadrature's levels.
  const double guess = std::ceil(std::log(options_.tolerance) / std::log(q));
  if (!(guess <= kMaxDegree)) return false;
  if (options_.method == ExactMutualOptions::Method::Automatic) {
    // Where it pays: a polyhedron's field (a sum over all its faces and edges; an ellipsoid's or a
    // point mass's is cheap enough for the quadrature), sampled at fewer points than the
    // quadrature's first two levels hold.
    const int n = static_cast<int>(guess);
    const std::size_t nodes = static_cast<std::size_t>((n + 2) * (2 * n + 2));
    if (!field_->polyhedron || nodes >= surface_->rule_size(1) + surface_->rule_size(2)) return false;
  }
  const Side& field = *field_;
  const Mat3 Ct = C_s.transpose();
  for (int N = std::max(4, static_cast<int>(guess)); N <= kMaxDegree; N += 2) {
    // A sphere's projection holds (N+1)² × (N+2)(2N+2) numbers (46 MB at N = 40): a few kept.
    if (expansion_->projections.size() >= 3 && !expansion_->projections.count(N)) expansion_->projections.clear();
    const SphereProjection& sphere = expansion_->projections.try_emplace(N, N).first->second;
    SolidHarmonicMoments& moments = expansion_->moments;
    if (moments.degree < N) moments = solid_harmonic_moments(body.integrals(N), a, solid_harmonic_polynomials(N));
    // Φ at the nodes; with J also ∂Φ/∂R_s = gᵀ and ∂Φ/∂φ = ((y − R_s) × g)ᵀ (26.3).
    const auto K = static_cast<Eigen::Index>(sphere.nodes().size());
    Eigen::MatrixXd samples(K, J ? 7 : 1);
    bool inside = false;
#pragma omp parallel for schedule(dynamic, 8) reduction(|| : inside)
    for (Eigen::Index k = 0; k < K; ++k) {
      const Vec3 y = a * sphere.nodes()[static_cast<std::size_t>(k)];
      const FieldValue v = field.field(Ct * (y - R_s));
      inside = inside || v.inside;
      samples(k, 0) = v.phi;
      if (J) {
        const Vec3 g = C_s * v.g;
        samples.block<1, 3>(k, 1) = g.transpose();
        samples.block<1, 3>(k, 4) = (y - R_s).cross(g).transpose();
      }
    }
    if (inside) return false;
    const Eigen::MatrixXd c = sphere.project(samples);  // one row per harmonic
    auto terms = [&](int degree) {
      const Eigen::Index n = harmonic::count(degree);
      MutualTerms t;
      t.U = c.col(0).head(n).dot(moments.mass.head(n));
      t.dU_dR = -(moments.gradient.leftCols(n) * c.col(0).head(n));
      t.torque_A = -(moments.moment.leftCols(n) * c.col(0).head(n));
      t.torque_B = R_s.cross(t.dU_dR) - t.torque_A;
      return t;
    };
    const MutualTerms fine = terms(N);
    last_error_ = relative_change(terms(N - 2), fine, R_s);
    if (last_error_ > options_.tolerance) continue;
    if (J) {  // the same contractions of the derivatives' coefficients, then (26.4)
      const Eigen::Index n = harmonic::count(N);
      J->g_R = -(moments.gradient.leftCols(n) * c.block(0, 1, n, 3));
      J->g_phi = -(moments.gradient.leftCols(n) * c.block(0, 4, n, 3));
      J->tauA_R = -(moments.moment.leftCols(n) * c.block(0, 1, n, 3));
      J->tauA_phi = -(moments.moment.leftCols(n) * c.block(0, 4, n, 3));
      J->tauB_R = hat(R_s) * J->g_R - hat(fine.dU_dR) - J->tauA_R;
      J->tauB_phi = hat(R_s) * J->g_phi - J->tauA_phi;
    }
    last_degree_ = N;
    out = fine;
    return true;
  }
  return false;
}

MutualTerms ExactMutual::evaluate_in_surface_frame(const Vec3& R_s, const Mat3& C_s, MutualJacobian* J) {
  last_degree_ = -1;
  if (surface_->solid && options_.method != ExactMutualOptions::Method::Quadrature) {
    MutualTerms t;
    if (expand(R_s, C_s, J, t)) return t;
    if (options_.method == ExactMutualOptions::Method::Expansion) {
      std::ostringstream msg;
      msg << "the expansion does not reach the tolerance " << options_.tolerance
          << " by degree " << harmonic::kMaxDegree << ": the surface body's circumscribed sphere (radius "
          << surface_->solid->radius << ") is too close to the other body (centres " << R_s.norm()
          << " apart); use method: quadrature";
      throw Error(msg.str());
    }
  }
  return refine(R_s, C_s, J);
}

MutualTerms ExactMutual::evaluate(const Vec3& R, const Mat3& C) {
  // Into the surface body's frame, and back: R_s = −Cᵀ R ⇒ ∂U/∂R = −C ∂U/∂R_s, roles swapped.
  const Vec3 R_s = surface_is_A_ ? R : Vec3(-(C.transpose() * R));
  const Mat3 C_s = surface_is_A_ ? C : Mat3(C.transpose());
  const MutualTerms s = evaluate_in_surface_frame(R_s, C_s, nullptr);
  if (surface_is_A_) return s;
  MutualTerms t;
  t.U = s.U;
  t.dU_dR = -(C * s.dU_dR);
  t.torque_A = C * s.torque_B;
  t.torque_B = C * s.torque_A;
  return t;
}

MutualTerms ExactMutual::jacobian(const Vec3& R, const Mat3& C, MutualJacobian& J) {
  const Vec3 R_s = surface_is_A_ ? R : Vec3(-(C.transpose() * R));
  const Mat3 C_s = surface_is_A_ ? C : Mat3(C.transpose());
  MutualJacobian Js;
  const MutualTerms s = evaluate_in_surface_frame(R_s, C_s, &Js);
  if (surface_is_A_) {
    J = Js;
    return s;
  }
  // (26.6): B is the surface. δR_s = −Cᵀ δR − Cᵀ S(R) φ and φ_s = −Cᵀ φ; each output is C times
  // (or −C times) a surface-frame one, which φ turns as well.
  const Mat3 Ct = C.transpose();
  MutualTerms t;
  t.U = s.U;
  t.dU_dR = -(C * s.dU_dR);
  t.torque_A = C * s.torque_B;
  t.torque_B = C * s.torque_A;
  auto by_R = [&](const Mat3& Q_R) -> Mat3 { return C * Q_R * Ct; };
  auto by_phi = [&](const Mat3& Q_R, const Mat3& Q_phi) -> Mat3 { return C * (Q_R * Ct * hat(R) + Q_phi * Ct); };
  J.g_R = by_R(Js.g_R);
  J.g_phi = by_phi(Js.g_R, Js.g_phi) - hat(t.dU_dR);
  J.tauA_R = -by_R(Js.tauB_R);
  J.tauA_phi = -by_phi(Js.tauB_R, Js.tauB_phi) - hat(t.torque_A);
  J.tauB_R = -by_R(Js.tauA_R);
  J.tauB_phi = -by_phi(Js.tauA_R, Js.tauA_phi) - hat(t.torque_B);
  return t;
}

}  // namespace noether
