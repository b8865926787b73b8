// sphere-cluster: every rigid body is a set of point masses ρ fixed in its body frame (docs/equations.md
// §2); point masses are a single point at their centre. For two dumbbells this is the
// potential of Lee, Leok & McClamroch 2007 §5.1:  U = −Σ_{p,q} G (m1/2)(m2/2) / ‖x1 + R1ρ1p − x2 − R2ρ2q‖.
//
// Forces f_i = Σ_ρ F_ρ, moments M_i = Σ_ρ ρ × (R_iᵀ F_ρ) (docs/equations.md §2, from (24)).
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/plugin.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace {

using noether::Forces;
using noether::Params;
using noether::SceneError;
using noether::State;
using noether::System;
using Vec3 = Eigen::Vector3d;

struct Cluster {
  std::vector<double> mass;  // m_p
  std::vector<Vec3> rho;     // ρ_p, body frame
};

// A body's cluster from its `shape`: {dumbbell: {length: l}} or
// {spheres: [{mass: m_p, position: [ρx, ρy, ρz]}, ...]}.
Cluster cluster_of(const noether::Body& body) {
  Cluster c;
  const std::string who = "sphere-cluster: body '" + body.name + "'";
  if (!body.rigid) {
    if (!body.shape.is_null())
      throw SceneError(body.shape.here() + who +
                       " is a point mass (no 'inertia') and cannot have a 'shape'");
    c.mass.push_back(body.mass);
    c.rho.push_back(Vec3::Zero());
    return c;
  }
  const Params& shape = body.shape;
  if (shape.is_null())
    throw SceneError(who + " is rigid but has no 'shape'; give shape: {dumbbell: {length: L}} "
                           "or shape: {spheres: [{mass: m, position: [x, y, z]}, ...]}, or "
                           "use the point-mass potential");
  if (body.solid)
    throw SceneError(shape.here() + who + " is a " + body.solid->describe() +
                     "; sphere-cluster models point clusters only: use the mutual-series or "
                     "mutual-exact potential for solid shapes");
  shape.check_keys({"dumbbell", "spheres"}, "the shape of body '" + body.name + "'");
  if (shape.size() != 1)
    throw SceneError(shape.here() + who + ": give exactly one of 'dumbbell' or 'spheres'");
  if (shape.has("dumbbell")) {
    const Params& d = shape.at("dumbbell");
    d.check_keys({"length"}, "dumbbell of body '" + body.name + "'");
    const double l = d.at("length").as_double();
    if (l <= 0.0) throw SceneError(d.at("length").here() + who + ": dumbbell length must be positive");
    // Two equal spheres of mass m/2 at ±(l/2) e1 (Lee, Leok & McClamroch 2007 §5.1).
    c.mass = {0.5 * body.mass, 0.5 * body.mass};
    c.rho = {Vec3(0.5 * l, 0, 0), Vec3(-0.5 * l, 0, 0)};
    return c;
  }
  double total = 0.0;
  Vec3 moment = Vec3::Zero();
  double extent = 0.0;
  for (const auto& s : shape.at("spheres").items()) {
    s.check_keys({"mass", "position"}, "a sphere of body '" + body.name + "'");
    const double m = s.at("mass").as_double();
    const auto p = s.at("position").as_doubles();
    if (m <= 0.0) throw SceneError(s.here() + who + ": sphere masses must be positive");
    if (p.size() != 3) throw SceneError(s.here() + who + ": sphere position needs 3 numbers");
    c.mass.push_back(m);
    c.rho.emplace_back(p[0], p[1], p[2]);
    total += m;
    moment += m * c.rho.back();
    extent = std::max(extent, c.rho.back().norm());
  }
  if (c.mass.empty()) throw SceneError(shape.here() + who + ": 'spheres' is empty");
  if (std::abs(total - body.mass) > 1e-12 * body.mass) {
    std::ostringstream msg;
    msg << shape.here() << who << ": sphere masses sum to " << total << ", the body's mass is "
        << body.mass;
    throw SceneError(msg.str());
  }
  if ((moment / total).norm() > 1e-12 * std::max(extent, 1e-300)) {
    std::ostringstream msg;
    msg << shape.here() << who << ": the spheres' centre of mass is at "
        << (moment / total).transpose()
        << " in the body frame; it must be at the origin (the body's position is its centre "
           "of mass)";
    throw SceneError(msg.str());
  }
  return c;
}

constexpr std::size_t kPairsPerTask = 16;  // pairs a thread takes at a time (then 16 such tasks a chunk)

class SphereCluster final : public noether::Potential {
 public:
  explicit SphereCluster(const System& system) : G_(system.G()) {
    for (std::size_t i = 0; i < system.size(); ++i) {
      clusters_.push_back(cluster_of(system.body(i)));
      rigid_.push_back(system.rigid_index(i));
      name_.push_back(system.body(i).name);
    }
    for (std::size_t i = 0; i < clusters_.size(); ++i)
      for (std::size_t j = i + 1; j < clusters_.size(); ++j) pairs_.emplace_back(i, j);
  }

  // Scratch: the inertial positions of every point, and each pair's share of the forces.
  struct Share {
    double U = 0.0;
    Vec3 f = Vec3::Zero(), ti = Vec3::Zero(), tj = Vec3::Zero();  // on i; the torques inertial
  };
  struct Points final : noether::Workspace {
    std::vector<std::vector<Vec3>> of_body;
    std::vector<Share> shares;
  };
  std::unique_ptr<noether::Workspace> make_workspace() const override { return std::make_unique<Points>(); }

  // Each pair's share on some thread (`noether run --threads`), then the shares added in pair
  // order: the same bit for bit for any number of threads.
  void evaluate(const State& s, Forces& out, noether::Workspace& workspace) const override {
    auto& w = noether::workspace_as<Points>(workspace, "sphere-cluster");
    auto& points = w.of_body;
    out.set_zero();
    const std::size_t n = clusters_.size();
    // Inertial positions of every point: x_i + R_i ρ_p.
    points.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& c = clusters_[i];
      points[i].resize(c.rho.size());
      for (std::size_t p = 0; p < c.rho.size(); ++p)
        points[i][p] = rigid_[i] >= 0
                            ? Vec3(s.x.col(static_cast<Eigen::Index>(i)) +
                                   s.R[static_cast<std::size_t>(rigid_[i])] * c.rho[p])
                            : Vec3(s.x.col(static_cast<Eigen::Index>(i)));
    }
    // Pair k's share added to the forces; in pair order, whichever thread computed it.
    auto add = [&](std::size_t k, const Share& share) {
      const auto [i, j] = pairs_[k];
      out.U += share.U;
      out.f.col(static_cast<Eigen::Index>(i)) += share.f;
      out.f.col(static_cast<Eigen::Index>(j)) -= share.f;
      // ρ × (Rᵀ F) = Rᵀ ((Rρ) × F): the body-frame moment (docs/equations.md §2).
      if (rigid_[i] >= 0) out.M.col(rigid_[i]) += s.R[static_cast<std::size_t>(rigid_[i])].transpose() * share.ti;
      if (rigid_[j] >= 0) out.M.col(rigid_[j]) += s.R[static_cast<std::size_t>(rigid_[j])].transpose() * share.tj;
    };
    // Tasks of kPairsPerTask pairs (a pair of dumbbells is ~50 ns of work), from 4 tasks on: below
    // that (8 dumbbells, 28 pairs: 1.5 µs) waking the threads costs more than it saves.
    const int threads = pairs_.size() >= 4 * kPairsPerTask ? noether::evaluation_threads() : 1;
    if (threads > 1) {
      w.shares.resize(pairs_.size());
      const std::size_t tasks = (pairs_.size() + kPairsPerTask - 1) / kPairsPerTask;
      noether::parallel_for_each(tasks, threads, [&](std::size_t task, int) {
        for (std::size_t k = task * kPairsPerTask; k < std::min(pairs_.size(), (task + 1) * kPairsPerTask); ++k)
          w.shares[k] = share_of(k, s, points);
      });
      for (std::size_t k = 0; k < pairs_.size(); ++k) add(k, w.shares[k]);
    } else {  // the same sums, each share added as it is made
      for (std::size_t k = 0; k < pairs_.size(); ++k) add(k, share_of(k, s, points));
    }
  }

  // The force Jacobian (docs/equations.md §20, eq. 20.2). For points y_p = x_i + R_i ρ_p and
  // y_q = x_j + R_j ρ_q, d = y_p − y_q, F = −G m_p m_q d/r³ on p and B = G m_p m_q (I − 3 d̂d̂ᵀ)/r³,
  // so δF = −B δd. With A_p = R_i S(ρ_p), δy_p = δx_i − A_p δθ_i; f_i = Σ F, M_i = −Σ A_pᵀ F and
  // δ(R_iᵀ) F = S(R_iᵀ F) δθ_i give every block; body j is the same with −F.
  bool force_jacobian(const State& s, Eigen::MatrixXd& K, noether::Workspace&) const override {
    const std::size_t n = clusters_.size();
    const Eigen::Index N = 3 * static_cast<Eigen::Index>(n);
    auto X = [](std::size_t i) { return 3 * static_cast<Eigen::Index>(i); };   // x_i's index
    auto T = [&](int k) { return N + 3 * static_cast<Eigen::Index>(k); };      // θ_k's index
    // Every point y_p = x_i + R_i ρ_p and its arm A_p = R_i S(ρ_p) (zero for a point mass), once.
    std::vector<std::vector<Vec3>> points(n);
    std::vector<std::vector<Eigen::Matrix3d>> arms(n);
    for (std::size_t i = 0; i < n; ++i)
      for (const Vec3& rho : clusters_[i].rho) {
        const Vec3 x = s.x.col(static_cast<Eigen::Index>(i));
        if (rigid_[i] < 0) {
          points[i].push_back(x);
          arms[i].push_back(Eigen::Matrix3d::Zero());
        } else {
          const Eigen::Matrix3d& R = s.R[static_cast<std::size_t>(rigid_[i])];
          points[i].push_back(x + R * rho);
          arms[i].push_back(R * noether::hat(rho));
        }
      }
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const auto &ci = clusters_[i], &cj = clusters_[j];
        const int ki = rigid_[i], kj = rigid_[j];
        for (std::size_t p = 0; p < ci.rho.size(); ++p)
          for (std::size_t q = 0; q < cj.rho.size(); ++q) {
            const auto [d, r2, r, Gmm] = point_pair(i, j, p, q, points, s.t);
            const Vec3 F = (-Gmm / (r2 * r)) * d;
            const Eigen::Matrix3d B = Gmm / (r2 * r) * (Eigen::Matrix3d::Identity() - 3.0 * d * d.transpose() / r2);
            const Eigen::Matrix3d &Ap = arms[i][p], &Aq = arms[j][q];
            // δF = −B δx_i + B A_p δθ_i + B δx_j − B A_q δθ_j; f_i += F, f_j −= F.
            K.block<3, 3>(X(i), X(i)) -= B;
            K.block<3, 3>(X(i), X(j)) += B;
            K.block<3, 3>(X(j), X(i)) += B;
            K.block<3, 3>(X(j), X(j)) -= B;
            if (ki >= 0) {
              K.block<3, 3>(X(i), T(ki)) += B * Ap;
              K.block<3, 3>(X(j), T(ki)) -= B * Ap;
              // M_i = −Σ A_pᵀ F: −A_pᵀ δF, and ρ̂_p δ(R_iᵀ) F = S(ρ_p) S(R_iᵀ F) δθ_i.
              const Vec3 F_body = s.R[static_cast<std::size_t>(ki)].transpose() * F;
              K.block<3, 3>(T(ki), X(i)) += Ap.transpose() * B;
              K.block<3, 3>(T(ki), X(j)) -= Ap.transpose() * B;
              K.block<3, 3>(T(ki), T(ki)) += -Ap.transpose() * B * Ap + noether::hat(ci.rho[p]) * noether::hat(F_body);
              if (kj >= 0) K.block<3, 3>(T(ki), T(kj)) += Ap.transpose() * B * Aq;
            }
            if (kj >= 0) {
              K.block<3, 3>(X(i), T(kj)) -= B * Aq;
              K.block<3, 3>(X(j), T(kj)) += B * Aq;
              // M_j = Σ A_qᵀ F (the force on q is −F): A_qᵀ δF, and S(ρ_q) S(−R_jᵀ F) δθ_j.
              const Vec3 F_body = s.R[static_cast<std::size_t>(kj)].transpose() * F;
              K.block<3, 3>(T(kj), X(i)) -= Aq.transpose() * B;
              K.block<3, 3>(T(kj), X(j)) += Aq.transpose() * B;
              K.block<3, 3>(T(kj), T(kj)) += -Aq.transpose() * B * Aq - noether::hat(cj.rho[q]) * noether::hat(F_body);
              if (ki >= 0) K.block<3, 3>(T(kj), T(ki)) += Aq.transpose() * B * Ap;
            }
          }
      }
    return true;
  }

 private:
  // The point masses p of body i and q of body j: d = y_p − y_q, r², r and G m_p m_q (a collision
  // when they coincide).
  struct PointPair {
    Vec3 d;
    double r2, r, Gmm;
  };
  PointPair point_pair(std::size_t i, std::size_t j, std::size_t p, std::size_t q,
                       const std::vector<std::vector<Vec3>>& points, double t) const {
    const Vec3 d = points[i][p] - points[j][q];
    const double r2 = d.squaredNorm();
    if (!(r2 > 0.0)) collision(i, j, t);
    return {d, r2, std::sqrt(r2), G_ * clusters_[i].mass[p] * clusters_[j].mass[q]};
  }

  // Pair k's share: Σ over its points' pairs of the point masses' U, the force on i and both
  // bodies' inertial torques.
  Share share_of(std::size_t k, const State& s, const std::vector<std::vector<Vec3>>& points) const {
    const auto [i, j] = pairs_[k];
    const auto &ci = clusters_[i], &cj = clusters_[j];
    const Vec3 xi = s.x.col(static_cast<Eigen::Index>(i)), xj = s.x.col(static_cast<Eigen::Index>(j));
    Share share;
    for (std::size_t p = 0; p < ci.rho.size(); ++p) {
      for (std::size_t q = 0; q < cj.rho.size(); ++q) {
        const auto [d, r2, r, Gmm] = point_pair(i, j, p, q, points, s.t);
        share.U -= Gmm / r;
        const Vec3 F = (-Gmm / (r2 * r)) * d;  // inertial force on point p of body i
        share.f += F;
        // Moment arms in the inertial frame: R ρ; rotated back to the body in evaluate().
        if (rigid_[i] >= 0) share.ti += (points[i][p] - xi).cross(F);
        if (rigid_[j] >= 0) share.tj -= (points[j][q] - xj).cross(F);
      }
    }
    return share;
  }

  [[noreturn]] void collision(std::size_t i, std::size_t j, double t) const {
    std::ostringstream msg;
    msg << "sphere-cluster: a sphere of body '" << name_[i] << "' and one of body '" << name_[j]
        << "' are at the same position at t = " << t << " (a collision)";
    throw noether::IntegrationError(msg.str(), t);
  }

  double G_;
  std::vector<Cluster> clusters_;
  std::vector<int> rigid_;
  std::vector<std::string> name_;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;  // (i, j), i < j, in the order their shares are added
};

std::unique_ptr<noether::Potential> make(const System& system, const Params&) {
  return std::make_unique<SphereCluster>(system);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Potential,
    "sphere-cluster",
    "rigid bodies as point masses fixed in their body frames (dumbbells, sphere clusters)",
    nullptr,
    0,
    &make,
    nullptr};
