// A swarm's checkpoint (ParticleSwarm::checkpoint, ::restore): every particle and the check's
// at half the step as rows of numbers, from which a continued or loaded run carries them on
// (docs/user-guide.md, "Continuing a run"; H5Writer::write_particle_checkpoint writes them).
#include <noether/error.hpp>
#include <noether/particles.hpp>

#include <sstream>
#include <string>

namespace noether {

namespace {

// A checkpoint's row (ParticleCheckpoint): x, v, a, fate, t, body, point, velocity.
void pack_row(double* r, const Vec3& x, const Vec3& v, const Vec3& a, const ParticleOutcome& o) {
  for (int k = 0; k < 3; ++k) r[k] = x[k], r[3 + k] = v[k], r[6 + k] = a[k], r[12 + k] = o.point[k], r[15 + k] = o.velocity[k];
  r[9] = static_cast<double>(o.fate), r[10] = o.t, r[11] = o.body;
}
void unpack_row(const double* r, Vec3& x, Vec3& v, Vec3& a, ParticleOutcome& o) {
  for (int k = 0; k < 3; ++k) x[k] = r[k], v[k] = r[3 + k], a[k] = r[6 + k], o.point[k] = r[12 + k], o.velocity[k] = r[15 + k];
  o.fate = static_cast<ParticleFate>(static_cast<int>(r[9]));
  o.t = r[10];
  o.body = static_cast<int>(r[11]);
}

}  // namespace

ParticleCheckpoint ParticleSwarm::checkpoint() const {
  ParticleCheckpoint c;
  c.t = t_;
  c.particle_steps = static_cast<double>(particle_steps_);
  c.check_steps = static_cast<double>(check_steps_);
  c.seconds = seconds_;
  constexpr std::size_t w = ParticleCheckpoint::kColumns;
  c.rows.resize((outcomes_.size() + checked_.size()) * w);
  for (std::size_t i = 0; i < outcomes_.size(); ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    pack_row(&c.rows[i * w], x_.col(j), v_.col(j), a_.col(j), outcomes_[i]);
  }
  for (std::size_t k = 0; k < checked_.size(); ++k) {
    const auto j = static_cast<Eigen::Index>(k);
    pack_row(&c.rows[(outcomes_.size() + k) * w], x_half_.col(j), v_half_.col(j), a_half_.col(j), outcomes_half_[k]);
  }
  return c;
}

void ParticleSwarm::restore(const ParticleCheckpoint& from, double t_bodies) {
  constexpr std::size_t w = ParticleCheckpoint::kColumns;
  const std::size_t rows = outcomes_.size() + checked_.size();
  if (from.rows.size() != rows * w)
    throw Error("particles: the checkpoint holds " + std::to_string(from.rows.size() / w) + " particles (with the check's), the scene " +
                std::to_string(rows) + " (" + std::to_string(outcomes_.size()) + " and " + std::to_string(checked_.size()) +
                " checked): it was saved from another scene");
  if (from.t != t_bodies) {
    std::ostringstream why;
    why.precision(17);
    why << "particles: the checkpoint has them at t = " << from.t << ", the bodies at " << t_bodies;
    throw Error(why.str());
  }
  const int surfaces = static_cast<int>(surfaces_.size());
  auto take = [&](std::size_t row, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& a, Eigen::Index j,
                  ParticleOutcome& o) {
    Vec3 xi, vi, ai;
    unpack_row(&from.rows[row * w], xi, vi, ai, o);
    if (static_cast<int>(o.fate) < 0 || static_cast<int>(o.fate) > 2 || o.body < -1 || o.body >= surfaces)
      throw Error("particles: the checkpoint's row " + std::to_string(row) + " is not a particle's (fate " +
                  std::to_string(static_cast<int>(o.fate)) + ", body " + std::to_string(o.body) + ")");
    x.col(j) = xi, v.col(j) = vi, a.col(j) = ai;
  };
  for (std::size_t i = 0; i < outcomes_.size(); ++i) take(i, x_, v_, a_, static_cast<Eigen::Index>(i), outcomes_[i]);
  for (std::size_t k = 0; k < checked_.size(); ++k)
    take(outcomes_.size() + k, x_half_, v_half_, a_half_, static_cast<Eigen::Index>(k), outcomes_half_[k]);
  t_ = from.t;
  particle_steps_ = static_cast<std::int64_t>(from.particle_steps);
  check_steps_ = static_cast<std::int64_t>(from.check_steps);
  seconds_ = from.seconds;
  x_before_.resize(3, 0);  // no step taken since: the recorded positions are where they stand
  v_before_.resize(3, 0);
}

}  // namespace noether
