// Massless particles carried with a run's bodies (particles.hpp; docs/equations.md §38).
#include <noether/error.hpp>
#include <noether/evaluation_threads.hpp>
#include <noether/particles.hpp>
#include <noether/stepping.hpp>

#include "run/regula_falsi.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

namespace noether {

namespace {
constexpr double kMaxSubsteps = 1e7;  // particle steps in one step of the bodies
}  // namespace

struct ParticleSwarm::Placement {
  double t = 0.0;
  std::vector<Vec3> x;  // the bodies' centres
  std::vector<Mat3> R;  // their attitudes (identity for a point mass)
  std::vector<PointPull> pulls;  // the forces' point masses that pull the particles
};

struct ParticleSwarm::Scratch {
  std::vector<Placement> ends, halves;  // the bodies at the substeps' ends (and midpoints)
  State probe;
  std::vector<State> probes;            // one per thread
  std::vector<std::int64_t> steps;      // Verlet steps, per thread
};

ParticleSwarm::~ParticleSwarm() = default;

namespace {

// The bodies at `s` into `at`, reusing its memory (a run places them a few times each step).
void place_bodies(const System& system, const State& s, ParticleSwarm::Placement& at) {
  at.t = s.t;
  at.x.resize(system.size());
  at.R.resize(system.size());
  for (std::size_t b = 0; b < system.size(); ++b) {
    at.x[b] = s.x.col(static_cast<Eigen::Index>(b));
    const int k = system.rigid_index(b);
    at.R[b] = k >= 0 ? s.R[static_cast<std::size_t>(k)] : Mat3::Identity();
  }
}

// The cubic Hermite path of a particle over [0, h] from (xa, va) to (xb, vb), at s ∈ [0, 1]:
// its position and velocity.
void hermite_path(const Vec3& xa, const Vec3& va, const Vec3& xb, const Vec3& vb, double h, double s, Vec3& x,
                  Vec3& v) {
  const double s2 = s * s, s3 = s2 * s;
  x = (2 * s3 - 3 * s2 + 1) * xa + (s3 - 2 * s2 + s) * h * va + (-2 * s3 + 3 * s2) * xb + (s3 - s2) * h * vb;
  v = ((6 * s2 - 6 * s) * xa + (-6 * s2 + 6 * s) * xb) / h + (3 * s2 - 4 * s + 1) * va + (3 * s2 - 2 * s) * vb;
}

}  // namespace

ParticleSwarm::ParticleSwarm(const System& system, const ParticleSettings& settings, const State& bodies,
                             std::shared_ptr<const Forcing> forcing)
    : system_(system), settings_(settings), scratch_(std::make_unique<Scratch>()) {
  if (!(settings_.step >= 0.0)) throw SceneError("particles.step must be positive (0: the bodies' steps)");
  const auto n = static_cast<Eigen::Index>(settings_.position.size());
  x_.resize(3, n);
  v_.resize(3, n);
  a_.setZero(3, n);  // (made below, or restored)
  for (Eigen::Index i = 0; i < n; ++i) {
    x_.col(i) = settings_.position[static_cast<std::size_t>(i)];
    v_.col(i) = settings_.velocity[static_cast<std::size_t>(i)];
  }
  outcomes_.assign(static_cast<std::size_t>(n), {});
  t_ = bodies.t;
  fields_.emplace_back();
  for (const Body& b : system.bodies()) {
    fields_[0].emplace_back(b, system.G(), BodyFieldOptions{settings_.degree, settings_.tolerance});
    surfaces_.push_back(b.name);
  }
  if (forcing) {
    std::vector<PointPull> pulls;
    for (const ForceTerm& term : *forcing) {
      const std::size_t first = pulls.size();
      const bool pulls_particles = term.model->pull_particles(bodies, pulls);
      if (pulls_particles) pulling_.push_back(term.model);
      // A pull of negative G M is a push away from a point: the Sun's light (cannonball).
      bool pushes = false;
      for (std::size_t j = first; j < pulls.size(); ++j) pushes = pushes || pulls[j].mu < 0.0;
      force_fields_.push_back(term.name + (!pulls_particles ? ": not felt by the particles"
                                           : pushes         ? ": a push away from a point (the Sun's light)"
                                                            : ": point masses (its bodies' gravity)"));
      for (std::size_t j = first; j < pulls.size(); ++j) {
        surfaces_.push_back(pulls.size() - first > 1 ? term.name + " #" + std::to_string(j - first) : term.name);
        pull_radius_.push_back(pulls[j].radius);
      }
    }
  }
  // A particle that starts inside a body is refused (where it stands it would land at once).
  const Placement at = place(bodies);
  for (Eigen::Index i = 0; i < n && !settings_.restored; ++i) {
    if (!(x_.col(i).cwiseAbs().maxCoeff() <= kLargestCoordinate))  // (NaN too)
      throw SceneError("particle " + std::to_string(i) + " (from 0: particles.states, then file, orbits, ejecta) starts "
                       "beyond 1e150 or at a position that is not a number (a semi-major axis of 1e300?), where its "
                       "distances overflow a double; start it nearer");
    if (const std::string where = inside(x_.col(i), at); !where.empty())
      throw SceneError("particle " + std::to_string(i) + " (from 0: particles.states, then file, orbits, ejecta) starts "
                       "inside " + where + "; start it outside");
    a_.col(i) = acceleration(x_.col(i), at, fields_[0]);
    if (!a_.col(i).allFinite() || !v_.col(i).allFinite())
      throw SceneError("particle " + std::to_string(i) + " (from 0: particles.states, then file, orbits, ejecta) starts "
                       "where its state or the field is not finite (at the centre of a point mass?); start it elsewhere");
  }
  // The check's particles: k n / K for k < K, spread evenly through the list.
  const std::size_t K = std::min(settings_.check, outcomes_.size());
  for (std::size_t k = 0; k < K; ++k) checked_.push_back(k * outcomes_.size() / K);
  x_half_.resize(3, static_cast<Eigen::Index>(K));
  v_half_.resize(3, static_cast<Eigen::Index>(K));
  a_half_.resize(3, static_cast<Eigen::Index>(K));
  for (std::size_t k = 0; k < K; ++k) {
    const auto c = static_cast<Eigen::Index>(k), i = static_cast<Eigen::Index>(checked_[k]);
    x_half_.col(c) = x_.col(i);
    v_half_.col(c) = v_.col(i);
    a_half_.col(c) = a_.col(i);
  }
  outcomes_half_.assign(K, {});
  if (settings_.restored) restore(*settings_.restored, bodies.t);
}

void ParticleSwarm::recorded_positions(const State& bodies, Eigen::Matrix3Xd& out) const {
  const auto recorded = static_cast<Eigen::Index>(settings_.record);
  const double t = bodies.t;
  out = x_.leftCols(recorded);
  std::optional<Placement> at;  // where the pulling point masses are, for particles landed on them
  for (Eigen::Index i = 0; i < recorded; ++i) {
    const ParticleOutcome& o = outcomes_[static_cast<std::size_t>(i)];
    if (o.fate == ParticleFate::impact && o.t <= t) {  // on its body: x_b + R_b r
      const auto b = static_cast<std::size_t>(o.body);
      if (b >= system_.size()) {  // on a point mass's sphere: X + r
        if (!at) at = place(bodies);
        out.col(i) = at->pulls[b - system_.size()].position + o.point;
        continue;
      }
      const int k = system_.rigid_index(b);
      out.col(i) = bodies.x.col(static_cast<Eigen::Index>(b)) +
                   (k >= 0 ? bodies.R[static_cast<std::size_t>(k)] : Mat3::Identity()) * o.point;
      continue;
    }
    if (t >= t_ || x_before_.cols() != recorded) continue;  // at the last step's end (or t0)
    // The path from the step's start to where the particle stands: the step's end, or its
    // landing or escape within the step.
    const double end = o.fate != ParticleFate::in_flight && o.t <= t_ && o.t > t_before_ ? o.t : t_;
    if (t >= end) continue;
    Vec3 x, v;
    hermite_path(x_before_.col(i), v_before_.col(i), x_.col(i), v_.col(i), end - t_before_,
                 (t - t_before_) / (end - t_before_), x, v);
    out.col(i) = x;
  }
}

// What x is inside of at `at` — "body 'NAME' (its surface, eq. 16.5)", or a pulling point mass's
// sphere (within its radius, or at its centre) — or "" when it is outside everything.
std::string ParticleSwarm::inside(const Vec3& x, const Placement& at) const {
  for (std::size_t b = 0; b < system_.size(); ++b) {
    const BodyField& f = fields_[0][b];
    if (!f.has_surface()) continue;
    const Vec3 r = at.R[b].transpose() * (x - at.x[b]);
    if (r.norm() <= f.bounding_radius() && f.surface_gap(r) <= 0.0)
      return "body '" + system_.body(b).name + "' (its surface, eq. 16.5)";
  }
  for (std::size_t j = 0; j < at.pulls.size(); ++j)
    if (!((x - at.pulls[j].position).norm() > at.pulls[j].radius))
      return "'" + surfaces_[system_.size() + j] + "' (within its radius " + std::to_string(at.pulls[j].radius) +
             " of its centre)";
  return "";
}

void ParticleSwarm::set_bodies(const State& bodies) {
  if (bodies.t != t_) {
    std::ostringstream why;
    why.precision(17);
    why << "the particles stand at t = " << t_ << ", the new state of the bodies is at t = " << bodies.t
        << ": give the bodies a state at the particles' time (or make a Simulation for the new state)";
    throw Error(why.str());
  }
  const Placement at = place(bodies);
  // All checked before any is changed: a refusal leaves the swarm as it was.
  for (std::size_t i = 0; i < outcomes_.size(); ++i)
    if (outcomes_[i].fate == ParticleFate::in_flight)
      if (const std::string where = inside(x_.col(static_cast<Eigen::Index>(i)), at); !where.empty())
        throw Error("particle " + std::to_string(i) + " (from 0) would be inside " + where +
                    " in the new state of the bodies");
  auto refit = [&](const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& a, const std::vector<ParticleOutcome>& outcomes) {
    for (std::size_t k = 0; k < outcomes.size(); ++k)
      if (outcomes[k].fate == ParticleFate::in_flight)
        a.col(static_cast<Eigen::Index>(k)) = acceleration(x.col(static_cast<Eigen::Index>(k)), at, fields_[0]);
  };
  refit(x_, a_, outcomes_);
  refit(x_half_, a_half_, outcomes_half_);
}

std::vector<std::string> ParticleSwarm::fields() const {
  std::vector<std::string> out;
  for (const BodyField& f : fields_[0]) out.push_back(f.describe());
  out.insert(out.end(), force_fields_.begin(), force_fields_.end());
  return out;
}

ParticleSwarm::Placement ParticleSwarm::place(const State& bodies) const {
  Placement at;
  place(bodies, at);
  return at;
}

void ParticleSwarm::place(const State& bodies, Placement& at) const {
  place_bodies(system_, bodies, at);
  at.pulls.clear();
  for (const auto& force : pulling_) force->pull_particles(bodies, at.pulls);
}

// (38.1): Σ_b R_b g_b(R_bᵀ (x − x_b)), and μ d/|d|³ (d = X − x) of each point mass X that pulls.
Vec3 ParticleSwarm::acceleration(const Vec3& x, const Placement& at, std::vector<BodyField>& fields) const {
  Vec3 a = Vec3::Zero();
  for (std::size_t b = 0; b < fields.size(); ++b)
    a += at.R[b] * fields[b](at.R[b].transpose() * (x - at.x[b])).acceleration;
  for (const PointPull& pull : at.pulls) {
    const Vec3 d = pull.position - x;
    const double d2 = d.squaredNorm();
    a += (pull.mu / (d2 * std::sqrt(d2))) * d;
  }
  return a;
}

double ParticleSwarm::energy(std::size_t i, const State& bodies) {
  const Placement at = place(bodies);
  const Vec3 x = x_.col(static_cast<Eigen::Index>(i));
  double phi = 0.0;
  for (std::size_t b = 0; b < fields_[0].size(); ++b) phi += fields_[0][b](at.R[b].transpose() * (x - at.x[b])).potential;
  for (const PointPull& pull : at.pulls) phi -= pull.mu / (pull.position - x).norm();
  return 0.5 * v_.col(static_cast<Eigen::Index>(i)).squaredNorm() + phi;
}

void ParticleSwarm::advance(const State& from, const State& to, int threads) {
  const auto start = std::chrono::steady_clock::now();
  const auto recorded = static_cast<Eigen::Index>(settings_.record);
  x_before_ = x_.leftCols(recorded);
  v_before_ = v_.leftCols(recorded);
  t_before_ = t_;
  // Equal substeps no longer than particles.step (one: the bodies' step).
  const double span = to.t - from.t, substeps = settings_.step > 0.0 ? std::ceil(span / settings_.step - 1e-9) : 1.0;
  if (!(substeps <= kMaxSubsteps)) {
    std::ostringstream why;
    why << "particles: the bodies' step from t = " << from.t << " to " << to.t << " is " << substeps
        << " particle steps of " << settings_.step << " (at most " << kMaxSubsteps
        << "); raise particles.step or limit the integrator's step";
    throw IntegrationError(why.str(), from.t);
  }
  const int n = std::max(1, static_cast<int>(substeps));
  // The bodies at the substeps' ends: the step's own states at its ends, Hermite between (16.2).
  // (The buffers are the swarm's, reused from step to step.)
  std::vector<Placement>& ends = scratch_->ends;
  ends.resize(static_cast<std::size_t>(n) + 1);
  State& probe = scratch_->probe;
  place(from, ends[0]);
  for (int s = 1; s < n; ++s) {
    hermite_state(system_, from, to, from.t + (to.t - from.t) * s / n, probe);
    place(probe, ends[static_cast<std::size_t>(s)]);
  }
  place(to, ends[static_cast<std::size_t>(n)]);
  threads = std::max(1, std::min<int>(threads, static_cast<int>(size())));
  while (fields_.size() < static_cast<std::size_t>(threads)) fields_.push_back(fields_[0]);
  std::vector<State>& probes = scratch_->probes;
  probes.resize(static_cast<std::size_t>(threads));
  std::vector<std::int64_t>& steps = scratch_->steps;
  steps.assign(static_cast<std::size_t>(threads), 0);
  // One particle's flight through `through`, read from and written back to columns c of (x, v, a).
  auto fly = [&](Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& a, Eigen::Index c, ParticleOutcome& outcome,
                 const std::vector<Placement>& through, int thread) {
    Flight p{x.col(c), v.col(c), a.col(c), outcome};
    carry(p, through, from, to, fields_[static_cast<std::size_t>(thread)], probes[static_cast<std::size_t>(thread)]);
    x.col(c) = p.x, v.col(c) = p.v, a.col(c) = p.a;
    outcome = p.outcome;
  };
  parallel_for_each(size(), threads, [&](std::size_t i, int thread) {
    if (outcomes_[i].fate != ParticleFate::in_flight) return;
    fly(x_, v_, a_, static_cast<Eigen::Index>(i), outcomes_[i], ends, thread);
    steps[static_cast<std::size_t>(thread)] += n;
  });
  for (const std::int64_t s : steps) particle_steps_ += s;
  check_finite(to.t);
  if (!checked_.empty()) {  // the check's particles at half the step: the bodies at the midpoints too
    std::vector<Placement>& halves = scratch_->halves;
    halves.resize(2 * ends.size() - 1);
    for (int s = 0; s < n; ++s) {
      halves[2 * static_cast<std::size_t>(s)] = ends[static_cast<std::size_t>(s)];
      hermite_state(system_, from, to, from.t + (to.t - from.t) * (2 * s + 1) / (2 * n), probe);
      place(probe, halves[2 * static_cast<std::size_t>(s) + 1]);
    }
    halves.back() = ends.back();
    std::fill(steps.begin(), steps.end(), 0);
    parallel_for_each(checked_.size(), threads, [&](std::size_t k, int thread) {
      if (outcomes_half_[k].fate != ParticleFate::in_flight) return;
      fly(x_half_, v_half_, a_half_, static_cast<Eigen::Index>(k), outcomes_half_[k], halves, thread);
      steps[static_cast<std::size_t>(thread)] += 2 * n;
    });
    for (const std::int64_t s : steps) check_steps_ += s;
  }
  mark_escapes(to, x_, outcomes_);
  mark_escapes(to, x_half_, outcomes_half_);
  t_ = to.t;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The particles' centre at `bodies`: `around`, or the bodies' barycentre.
Vec3 ParticleSwarm::centre(const State& bodies) const {
  if (settings_.around) return bodies.x.col(static_cast<Eigen::Index>(*settings_.around));
  Vec3 c = Vec3::Zero();
  double m = 0.0;
  for (std::size_t b = 0; b < system_.size(); ++b) {
    c += system_.body(b).mass * bodies.x.col(static_cast<Eigen::Index>(b));
    m += system_.body(b).mass;
  }
  return c / m;
}

// Escapes, at a step's end: farther than `escape` from the centre.
void ParticleSwarm::mark_escapes(const State& bodies, const Eigen::Matrix3Xd& x,
                                 std::vector<ParticleOutcome>& outcomes) const {
  if (!(settings_.escape > 0.0) || outcomes.empty()) return;
  const Vec3 c = centre(bodies);
  for (std::size_t i = 0; i < outcomes.size(); ++i)
    if (outcomes[i].fate == ParticleFate::in_flight && (x.col(static_cast<Eigen::Index>(i)) - c).norm() > settings_.escape) {
      outcomes[i].fate = ParticleFate::escape;
      outcomes[i].t = bodies.t;
    }
}

ParticleCheck ParticleSwarm::check(const State& bodies) const {
  ParticleCheck out;
  out.checked = checked_.size();
  out.steps = check_steps_;
  const Vec3 c = centre(bodies);
  for (std::size_t k = 0; k < checked_.size(); ++k) {
    const std::size_t i = checked_[k];
    const ParticleOutcome &h = outcomes_[i], &half = outcomes_half_[k];
    if (h.fate != half.fate || h.body != half.body) {
      ++out.fates_differ;
      continue;
    }
    if (h.fate == ParticleFate::in_flight) {
      const Vec3 x = x_.col(static_cast<Eigen::Index>(i));
      const double r = (x - c).norm();
      if (r > 0) out.position = std::max(out.position, (x - Vec3(x_half_.col(static_cast<Eigen::Index>(k)))).norm() / r);
    } else if (h.fate == ParticleFate::impact) {
      const auto b = static_cast<std::size_t>(h.body);
      const double radius = b < system_.size() ? fields_[0][b].bounding_radius() : pull_radius_[b - system_.size()];
      out.landing_point = std::max(out.landing_point, (h.point - half.point).norm() / radius);
      out.landing_time = std::max(out.landing_time, std::abs(h.t - half.t));
    }
  }
  return out;
}

// (38.3): kick, drift, kick through each substep; a landing ends the particle's flight (38.4).
void ParticleSwarm::carry(Flight& p, const std::vector<Placement>& ends, const State& from, const State& to,
                          std::vector<BodyField>& fields, State& probe) const {
  Vec3 x = p.x, v = p.v, a = p.a;
  for (std::size_t s = 1; s < ends.size(); ++s) {
    const double h = ends[s].t - ends[s - 1].t;
    const Vec3 half = v + 0.5 * h * a;
    const Vec3 x1 = x + h * half;
    const Vec3 a1 = acceleration(x1, ends[s], fields);
    const Vec3 v1 = half + 0.5 * h * a1;
    for (std::size_t b = 0; b < fields.size(); ++b) {
      const BodyField& f = fields[b];
      if (!f.has_surface()) continue;
      const Vec3 r = ends[s].R[b].transpose() * (x1 - ends[s].x[b]);
      if (r.squaredNorm() > f.bounding_radius() * f.bounding_radius() || f.surface_gap(r) > 0.0) continue;
      ParticleOutcome landed = landing(b, ends[s - 1].t, ends[s].t, x, v, x1, v1, from, to, probe);
      // Of two bodies hit in one substep, the first.
      if (p.outcome.fate == ParticleFate::in_flight || landed.t < p.outcome.t) p.outcome = landed;
    }
    for (std::size_t j = 0; j < ends[s].pulls.size(); ++j) {  // a pulling point mass's sphere
      const PointPull& pull = ends[s].pulls[j];
      if (!(pull.radius > 0.0) || (x1 - pull.position).squaredNorm() > pull.radius * pull.radius) continue;
      ParticleOutcome landed = landing(fields.size() + j, ends[s - 1].t, ends[s].t, x, v, x1, v1, from, to, probe);
      if (p.outcome.fate == ParticleFate::in_flight || landed.t < p.outcome.t) p.outcome = landed;
    }
    if (p.outcome.fate == ParticleFate::impact) {
      // The particle stays where it landed, with the velocity it landed with (inertial).
      const double u = (p.outcome.t - ends[s - 1].t) / h;
      hermite_path(x, v, x1, v1, h, u, p.x, p.v);
      p.a = a1;
      return;
    }
    x = x1, v = v1, a = a1;
  }
  p.x = x, p.v = v, p.a = a;
}

// (38.4): the time in [ta, tb] where the particle's Hermite path meets surface `surface` (a body's,
// eq. 16.5, or a pulling point mass's sphere), which it is outside of at ta and inside of at tb,
// by the Illinois variant of regula falsi on the gap between the path and the surface at its
// interpolated place (16.2).
ParticleOutcome ParticleSwarm::landing(std::size_t surface, double ta, double tb, const Vec3& xa, const Vec3& va,
                                       const Vec3& xb, const Vec3& vb, const State& from, const State& to,
                                       State& probe) const {
  const std::size_t bodies = system_.size();
  const double h = tb - ta;
  // The particle relative to the surface at time t: its place in the body frame (from a point
  // mass's centre, inertial axes), and (when `rel`) its velocity relative to the spinning surface.
  auto relative = [&](double t, Vec3* rel) {
    Vec3 x, v;
    hermite_path(xa, va, xb, vb, h, (t - ta) / h, x, v);
    hermite_state(system_, from, to, t, probe);
    if (surface >= bodies) {
      const PointPull pull = place(probe).pulls[surface - bodies];
      if (rel) *rel = v - pull.velocity;
      return Vec3(x - pull.position);
    }
    const int k = system_.rigid_index(surface);
    const auto c = static_cast<Eigen::Index>(surface);
    const Mat3 R = k >= 0 ? probe.R[static_cast<std::size_t>(k)] : Mat3::Identity();
    const Vec3 r = R.transpose() * (x - probe.x.col(c));
    if (rel) {
      *rel = R.transpose() * (v - probe.p.col(c) / system_.body(surface).mass);
      if (k >= 0) {  // Ω = J⁻¹ Π, Π linear in time over the step
        const double u = (t - from.t) / (to.t - from.t);
        const Vec3 Pi = (1 - u) * from.Pi.col(k) + u * to.Pi.col(k);
        *rel -= (system_.body(surface).inertia_inverse * Pi).cross(r);
      }
    }
    return r;
  };
  auto gap = [&](double t) {
    const Vec3 r = relative(t, nullptr);
    return surface < bodies ? fields_[0][surface].surface_gap(r) : r.norm() - pull_radius_[surface - bodies];
  };
  const double c = detail::illinois_root(gap, ta, tb, gap(ta), gap(tb), 1e-15);
  ParticleOutcome out;
  out.fate = ParticleFate::impact;
  out.t = c;
  out.body = static_cast<int>(surface);
  out.point = relative(c, &out.velocity);
  return out;
}

// A particle's state stops being finite only where a point mass without a radius pulls it from
// zero distance: the run cannot go on with it.
void ParticleSwarm::check_finite(double t) const {
  for (std::size_t i = 0; i < outcomes_.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    if (x_.col(c).allFinite() && v_.col(c).allFinite()) continue;
    throw IntegrationError("particles: particle " + std::to_string(i) +
                               " (from 0) is no longer finite: it met the centre of a point mass that has no radius "
                               "(give the point-mass body, or the prescribed body, a `radius` and the particles land on it)",
                           t);
  }
}

}  // namespace noether
