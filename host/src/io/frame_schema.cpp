// The frame schema (frame_schema.hpp): one row per series of an output file, with the function
// that computes one frame of it and, for the series a continued run reads back, the function
// that puts it back. docs/user-guide.md, "Output", lists the same series for users.
#include "io/frame_schema.hpp"
#include "io/state_quantities.hpp"

#include "run/binary_pair.hpp"
#include "run/spin_state_tracker.hpp"

#include <algorithm>
#include <limits>
#include <cstring>
#include <stdexcept>

namespace noether::io {

namespace {

using Matrix = Eigen::Matrix3Xd;

double* doubles(void* out) { return static_cast<double*>(out); }
const double* doubles(const void* in) { return static_cast<const double*>(in); }
std::int64_t* integers(void* out) { return static_cast<std::int64_t*>(out); }

void copy(const Matrix& m, void* out) { std::copy(m.data(), m.data() + m.size(), doubles(out)); }
void copy(double x, void* out) { *doubles(out) = x; }
void copy(const Vec3& v, void* out) { std::copy(v.data(), v.data() + 3, doubles(out)); }
Matrix matrix(const void* in, std::size_t width) {
  return Eigen::Map<const Matrix>(doubles(in), 3, static_cast<Eigen::Index>(width / 3));
}

// The quantities the run hands the writer (FrameFill::of_run), copied as each frame arrives.
void step(const FrameInput& in, void* out) { *integers(out) = in.work.steps; }
void time(const FrameInput& in, void* out) { copy(in.state.t, out); }
void position(const FrameInput& in, void* out) { copy(in.state.x, out); }
// Columns [first, last) of State::tangent as [coordinate][column], row-major (Eigen's storage is
// column-major).
void tangent_columns(const Eigen::MatrixXd& V, Eigen::Index first, Eigen::Index last, void* out) {
  double* o = doubles(out);
  for (Eigen::Index r = 0; r < V.rows(); ++r)
    for (Eigen::Index c = first; c < last; ++c) *o++ = V(r, c);
}
void stm(const FrameInput& in, void* out) {
  tangent_columns(in.state.tangent, 0, static_cast<Eigen::Index>(in.stm_columns), out);
}
void sensitivity(const FrameInput& in, void* out) {
  const Eigen::Index last = in.state.tangent.cols();
  tangent_columns(in.state.tangent, last - static_cast<Eigen::Index>(in.sensitivity_columns), last, out);
}
void force_balance(const FrameInput& in, void* out) {  // [force][7]: Eigen's columns are the forces
  std::copy(in.state.force_balance.data(), in.state.force_balance.data() + in.state.force_balance.size(), doubles(out));
}
void run_features(const FrameInput& in, void* out) { std::copy(in.features.begin(), in.features.end(), doubles(out)); }
void spin(const FrameInput& in, void* out) { copy(in.state.Pi, out); }
void energy(const FrameInput& in, void* out) { copy(in.diagnostics.energy, out); }
void kinetic_translational(const FrameInput& in, void* out) { copy(in.diagnostics.kinetic_translational, out); }
void kinetic_rotational(const FrameInput& in, void* out) { copy(in.diagnostics.kinetic_rotational, out); }
void potential(const FrameInput& in, void* out) { copy(in.diagnostics.potential, out); }
void orthogonality(const FrameInput& in, void* out) { copy(in.diagnostics.orthogonality_error, out); }
void linear_momentum(const FrameInput& in, void* out) { copy(in.diagnostics.linear_momentum, out); }
void angular_momentum(const FrameInput& in, void* out) { copy(in.diagnostics.angular_momentum, out); }
void momentum(const FrameInput& in, void* out) { copy(in.state.p, out); }
void attitude(const FrameInput& in, void* out) {  // row-major, as the file's [row][column]
  double* R = doubles(out);
  for (std::size_t k = 0; k < in.state.R.size(); ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R[9 * k + static_cast<std::size_t>(3 * r + c)] = in.state.R[k](r, c);
}
void wall_time(const FrameInput& in, void* out) { copy(in.wall_seconds, out); }
void integrator(const FrameInput& in, void* out) { std::copy(in.integrator.begin(), in.integrator.end(), doubles(out)); }
void work(const FrameInput& in, void* out) {
  const std::int64_t w[5] = {in.work.steps, in.work.potential_evaluations, in.work.newton_iterations,
                             in.work.rejected_steps, in.interpolated};
  std::memcpy(out, w, sizeof w);
}

// The restore functions of the checkpointed series (FrameQuantity::restore).
void restore_force_balance(const void* in, std::size_t width, RecordedFrame& f) {  // [force][7]
  f.state.force_balance = Eigen::Map<const Eigen::MatrixXd>(doubles(in), kBalanceRows,
                                                            static_cast<Eigen::Index>(width / kBalanceRows));
}
void restore_time(const void* in, std::size_t, RecordedFrame& f) { f.state.t = *doubles(in); }
void restore_position(const void* in, std::size_t width, RecordedFrame& f) { f.state.x = matrix(in, width); }
void restore_momentum(const void* in, std::size_t width, RecordedFrame& f) { f.state.p = matrix(in, width); }
void restore_spin(const void* in, std::size_t width, RecordedFrame& f) { f.state.Pi = matrix(in, width); }
void restore_attitude(const void* in, std::size_t width, RecordedFrame& f) {
  f.state.R.resize(width / 9);
  for (std::size_t k = 0; k < width / 9; ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f.state.R[k](r, c) = doubles(in)[9 * k + static_cast<std::size_t>(3 * r + c)];
}
void restore_potential(const void* in, std::size_t, RecordedFrame& f) { f.U = *doubles(in); }
void restore_wall(const void* in, std::size_t, RecordedFrame& f) { f.wall_seconds = *doubles(in); }
void restore_integrator(const void* in, std::size_t width, RecordedFrame& f) {
  f.integrator.assign(doubles(in), doubles(in) + width);
}
// [coordinate][column] row-major into a matrix; the coordinates, 6 per body and 6 per rigid body
// (eq. 21.1), from the state restored before (positions and attitudes have lower columns).
Eigen::MatrixXd restore_tangent_columns(const void* in, std::size_t width, const RecordedFrame& f) {
  const auto rows = 6 * (f.state.x.cols() + static_cast<Eigen::Index>(f.state.R.size()));
  Eigen::MatrixXd V(rows, rows > 0 ? static_cast<Eigen::Index>(width) / rows : 0);
  const double* v = doubles(in);
  for (Eigen::Index r = 0; r < V.rows(); ++r)
    for (Eigen::Index c = 0; c < V.cols(); ++c) V(r, c) = *v++;
  return V;
}
void restore_stm(const void* in, std::size_t width, RecordedFrame& f) { f.stm = restore_tangent_columns(in, width, f); }
void restore_sensitivity(const void* in, std::size_t width, RecordedFrame& f) {
  f.sensitivity = restore_tangent_columns(in, width, f);
}
void restore_features(const void* in, std::size_t width, RecordedFrame& f) {
  f.features.assign(doubles(in), doubles(in) + width);
}
void restore_work(const void* in, std::size_t, RecordedFrame& f) {
  std::int64_t w[5];
  std::memcpy(w, in, sizeof w);
  f.work = WorkCounters{w[0], w[1], w[2], w[3]};
  f.interpolated = w[4];
}

using E = Extent;
using D = Dimension;
constexpr Element kH5md = Element::kH5md, kPlain = Element::kPlain;

// The table. The checksum columns 0–13 are the file format of /checkpoint/checksum: a new
// checkpointed series takes the next free column.
const FrameQuantity kFrameSchema[] = {
    {"step", "/particles/bodies/position/step", E::kStepCount, D::kOne, kH5md,
     "the integrator's step count at each frame", -1, step, nullptr},
    {"time", "/particles/bodies/position/time", E::kScalar, D::kTime, kH5md, "time of each frame", 0, time,
     restore_time},
    {"positions", "/particles/bodies/position/value", E::kBodyVector, D::kLength, kH5md,
     "position x of each body's centre of mass, inertial frame [frame][body][xyz]", 1, position, restore_position},
    {"velocities", "/particles/bodies/velocity/value", E::kBodyVector, D::kVelocity, kH5md,
     "velocity of each body's centre of mass, inertial frame [frame][body][xyz]", -1, of_state::velocity, nullptr},
    {"quaternions", "/particles/bodies/orientation/value", E::kRigidQuaternion, D::kOne, kH5md,
     "attitude R (body to inertial frame) of each rigid body as a unit quaternion (w, x, y, z) "
     "[frame][rigid body][wxyz]; body_index names the bodies",
     -1, of_state::quaternion, nullptr},
    {"angular_momenta", "/particles/bodies/angular_momentum/value", E::kRigidVector, D::kAngularMomentum, kH5md,
     "spin angular momentum Π = J Ω of each rigid body, body frame [frame][rigid body][xyz]", 4, spin, restore_spin},
    {"angular_velocities", "/particles/bodies/angular_velocity/value", E::kRigidVector, D::kAngularVelocity, kH5md,
     "angular velocity Ω = J⁻¹Π of each rigid body, body frame [frame][rigid body][xyz]", -1, of_state::angular_velocity,
     nullptr},
    {"energy", "/observables/energy/value", E::kScalar, D::kEnergy, kH5md, "total energy E = T + U at each frame", -1,
     energy, nullptr},
    {"kinetic_energy_translational", "/observables/kinetic_energy_translational/value", E::kScalar, D::kEnergy, kH5md,
     "Σ |γ|²/(2m)", -1, kinetic_translational, nullptr},
    {"kinetic_energy_rotational", "/observables/kinetic_energy_rotational/value", E::kScalar, D::kEnergy, kH5md,
     "Σ Π·J⁻¹Π/2", -1, kinetic_rotational, nullptr},
    {"potential_energy", "/observables/potential_energy/value", E::kScalar, D::kEnergy, kH5md,
     "the mutual potential U", 5, potential, restore_potential},
    {"orthogonality_error", "/observables/orthogonality_error/value", E::kScalar, D::kOne, kH5md,
     "max over rigid bodies of ‖I − RᵀR‖_F", -1, orthogonality, nullptr},
    {"linear_momentum", "/observables/linear_momentum/value", E::kVector, D::kMomentum, kH5md,
     "total linear momentum Σ γ, inertial frame", -1, linear_momentum, nullptr},
    {"angular_momentum", "/observables/angular_momentum/value", E::kVector, D::kAngularMomentum, kH5md,
     "total angular momentum about the origin, Σ x × γ + R Π, inertial frame", -1, angular_momentum, nullptr},
    {"separation", "/observables/separation/value", E::kBinaryScalar, D::kLength, kH5md,
     "distance between the centres of mass of the binary (attrs primary, secondary: the two bodies that hold 99 % "
     "of the mass)",
     -1, of_state::separation, nullptr},
    {"relative_positions", "/observables/relative_position/value", E::kBinaryVector, D::kLength, kH5md,
     "the secondary's position relative to the primary, x_s − x_p, inertial frame", -1, of_state::binary_position, nullptr},
    {"relative_velocities", "/observables/relative_velocity/value", E::kBinaryVector, D::kVelocity, kH5md,
     "the secondary's velocity relative to the primary, v_s − v_p, inertial frame", -1, of_state::binary_velocity, nullptr},
    {"relative_positions_primary_frame", "/observables/relative_position_primary_frame/value", E::kPrimaryFrame,
     D::kLength, kH5md, "the secondary's position in the primary's body frame, R_pᵀ (x_s − x_p)", -1,
     of_state::position_in_primary_frame, nullptr},
    {"relative_velocities_primary_frame", "/observables/relative_velocity_primary_frame/value", E::kPrimaryFrame,
     D::kVelocity, kH5md,
     "the secondary's velocity seen in the primary's rotating body frame, R_pᵀ (v_s − v_p) − Ω_p × R_pᵀ (x_s − x_p)",
     -1, of_state::velocity_in_primary_frame, nullptr},
    {"osculating_elements", "/observables/osculating_elements/value", E::kBinaryElements, D::kMixed, kH5md,
     "the binary's osculating Keplerian elements as two point masses (μ = G (m_p + m_s)): a [length], e, i, Ω, ω, "
     "ν [deg] (docs/equations.md §17); NaN when unbound",
     -1, of_state::osculating_elements, nullptr},
    {"libration_angles", "/observables/libration_angle/value", E::kSecondaryAngle, D::kDegrees, kH5md,
     "the angle in the secondary's body xy plane between its x axis and the line to the primary, atan2(u_y, u_x) "
     "with u = R_sᵀ (x_p − x_s), folded into (−90, 90] (either end of the axis may face the primary): a synchronous "
     "secondary librates about 0",
     -1, of_state::libration, nullptr},
    {"euler_angles", "/particles/bodies/euler_angles/value", E::kRigidVector, D::kDegrees, kH5md,
     "3-2-1 Euler angles (yaw ψ, pitch θ, roll φ) of each rigid body's attitude in the scene frame, "
     "R = Rz(ψ) Ry(θ) Rx(φ) (docs/equations.md eq. 17.9); ψ, φ in (−180, 180], θ in [−90, 90]",
     -1, of_state::euler_angles, nullptr},
    {"secondary_euler_angles", "/observables/secondary_euler_angles/value", E::kSecondaryVector, D::kDegrees, kH5md,
     "3-2-1 Euler angles (yaw, pitch, roll) of the secondary's attitude in the orbit frame (x towards the primary, "
     "z along the orbit normal r × v; eq. 17.10), yaw folded into (−90, 90] (either end of the axis may face the "
     "primary): a synchronous secondary's libration in yaw, pitch and roll",
     -1, of_state::secondary_euler_angles, nullptr},
    {"nutation_angles", "/observables/nutation_angle/value", E::kRigidScalar, D::kDegrees, kH5md,
     "the angle between each rigid body's angular momentum and its principal axis of largest moment (eq. 17.11), "
     "in [0, 90]: 0 for rotation about that axis (the relaxed state), larger for a tumbling or precessing body; NaN "
     "while the body does not rotate (Π = 0: no angular momentum to measure it from)",
     -1, of_state::nutation_angles, nullptr},
    {"stm", "/derivatives/stm/value", E::kTangent, D::kMixed, kH5md,
     "the state-transition matrix of the run's own map, ∂z(t)/∂z(t0) (run.stm, docs/derivatives.md): rows and "
     "columns in the order of z = (x, θ, γ, Π) (docs/equations.md eq. 21.1), named by /derivatives/coordinates; θ "
     "is the right perturbation R exp(S(θ)) of an attitude, Π the body-frame angular momentum",
     12, stm, restore_stm},
    {"sensitivity", "/derivatives/sensitivity/value", E::kSensitivity, D::kMixed, kH5md,
     "the sensitivities ∂z(t)/∂p of the state to keys of the bodies' initial states and to parameters of the "
     "dynamics (run.sensitivities, "
     "docs/derivatives.md): rows in the order of z = (x, θ, γ, Π) (docs/equations.md eq. 21.1, "
     "/derivatives/coordinates), columns named by /derivatives/parameters, per unit of each key as the scene "
     "gives it",
     13, sensitivity, restore_sensitivity},
    {"megno", "/derivatives/megno/value", E::kChaos, D::kOne, kH5md,
     "MEGNO ⟨Y⟩ (Cincotta & Simó 2000; run.chaos, docs/derivatives.md, docs/equations.md eq. 23.3) of a deviation "
     "vector carried by the tangent map, at the method's last step up to each frame: → 2 on a regular orbit, "
     "grows as λ t / 2 on a chaotic one; NaN before the first step and after ‖δ‖ overflowed",
     -1, kByFeature, nullptr},
    {"fli", "/derivatives/fli/value", E::kChaos, D::kOne, kH5md,
     "fast Lyapunov indicator, max over s ≤ t of log10 ‖δ(s)‖/‖δ0‖ (Froeschlé, Lega & Gonczi 1997; run.chaos, "
     "docs/equations.md eq. 23.4), in the scaled norm of eq. 23.1: grows as log10 t on a regular orbit, linearly in "
     "t on a chaotic one",
     -1, kByFeature, nullptr},
    {"force_balance", "/observables/force_balance/value", E::kForceBalance, D::kMixed, kH5md,
     "what each force beyond the potential (the scene's forces:, named by /parameters/forces) put into the run since "
     "t0 [frame][force][7]: the work W, the linear momentum ΔP (3) and the angular momentum ΔL about the origin (3) "
     "(docs/equations.md eq. 33.3), in the units of energy, momentum and angular momentum; E − ΣW, P − ΣΔP and "
     "L − ΣΔL are what the forced flow conserves",
     9, force_balance, restore_force_balance},
    {"particle_positions", "/particles/test_particles/position/value", E::kParticleVector, D::kLength, kH5md,
     "position of each recorded massless particle (the scene's first particles.record particles, docs/user-guide.md "
     "\"Particles\"), inertial frame [frame][particle][xyz]; a landed particle rides on its body at the point "
     "where it landed",
     10, kByFeature, nullptr},
    {"momenta", "/checkpoint/linear_momentum", E::kBodyVector, D::kMomentum, kPlain,
     "linear momentum γ = m v of each body, inertial frame [frame][body][xyz], exact", 2, momentum, restore_momentum},
    {"attitudes", "/checkpoint/attitude", E::kRigidMatrix, D::kOne, kPlain,
     "attitude matrix R (body to inertial) of each rigid body [frame][rigid body][row][column], exact", 3, attitude,
     restore_attitude},
    {"wall_time", "/checkpoint/wall_time", E::kScalar, D::kWallSeconds, kPlain,
     "wall time spent by the run up to each frame", 7, wall_time, restore_wall},
    {"integrator_checkpoint", "/checkpoint/integrator", E::kIntegrator, D::kMixed, kPlain,
     "the integrator's own variables at each frame (Integrator::checkpoint: a relative frame's coordinates, a "
     "two-step form's previous step, a fixed step's clock t0 + k h), from which a continued run restores it",
     8, integrator, restore_integrator},
    {"work", "/checkpoint/work", E::kWork, D::kOne, kPlain,
     "work up to each frame: steps, potential evaluations, Newton iterations, rejected steps, frames interpolated "
     "between the method's steps",
     6, work, restore_work},
    {"run_features", "/checkpoint/run_features", E::kRunFeatures, D::kMixed, kPlain,
     "the run features' own variables at each frame, named by the attribute `fields` (run.chaos: the deviation "
     "vector δ and the indicators' running sums; impulses: how many were applied), from which a continued run "
     "restores them",
     11, run_features, restore_features},
};

}  // namespace

std::span<const FrameQuantity> frame_schema() { return kFrameSchema; }

std::vector<const FrameQuantity*> checkpointed_series() {
  std::vector<const FrameQuantity*> out;
  for (const auto& q : kFrameSchema)
    if (q.checksum_column >= 0) out.push_back(&q);
  std::sort(out.begin(), out.end(),
            [](const FrameQuantity* a, const FrameQuantity* b) { return a->checksum_column < b->checksum_column; });
  for (std::size_t c = 0; c < out.size(); ++c)
    if (out[c]->checksum_column != static_cast<int>(c) ||
        !(out[c]->fill.by_feature || (out[c]->restore && out[c]->fill.of_run)))
      throw std::logic_error(
          "frame schema: the checksum columns must be 0, 1, 2, … each filled by a feature or from the run with a "
          "restore function (a quantity of the state alone is computed from them)");
  return out;
}

const FeatureSeries* feature_series(const FrameQuantity& q, const FrameLayout& l) {
  if (!q.fill.by_feature) return nullptr;
  for (const auto& s : l.feature_series)
    if (s.name == q.name) return &s;
  return nullptr;
}

bool present(const FrameQuantity& q, const FrameLayout& l) {
  if (q.fill.by_feature) return feature_series(q, l) != nullptr;
  switch (q.extent) {
    case E::kRigidVector:
    case E::kRigidQuaternion:
    case E::kRigidMatrix:
    case E::kRigidScalar: return l.rigid > 0;
    case E::kIntegrator: return l.width > 0;
    case E::kTangent: return l.stm_columns > 0;
    case E::kSensitivity: return l.sensitivity_columns > 0;
    case E::kForceBalance: return l.forces > 0;
    case E::kRunFeatures: return l.features > 0;
    case E::kBinaryScalar:
    case E::kBinaryVector:
    case E::kBinaryElements: return l.binary;
    case E::kPrimaryFrame: return l.binary && l.primary_rigid;
    case E::kSecondaryAngle:
    case E::kSecondaryVector: return l.binary && l.secondary_rigid;
    default: return true;
  }
}

std::vector<std::size_t> frame_shape(const FrameQuantity& q, const FrameLayout& l) {
  if (q.fill.by_feature) {  // as the feature declares it
    const FeatureSeries* s = feature_series(q, l);
    return s ? s->shape : std::vector<std::size_t>{};
  }
  switch (q.extent) {
    case E::kStepCount:
    case E::kScalar:
    case E::kChaos:
    case E::kBinaryScalar:
    case E::kSecondaryAngle: return {};
    case E::kVector:
    case E::kBinaryVector:
    case E::kPrimaryFrame:
    case E::kSecondaryVector: return {3};
    case E::kBinaryElements: return {6};
    case E::kBodyVector: return {l.bodies, 3};
    case E::kRigidScalar: return {l.rigid};
    case E::kRigidVector: return {l.rigid, 3};
    case E::kRigidQuaternion: return {l.rigid, 4};
    case E::kRigidMatrix: return {l.rigid, 3, 3};
    case E::kWork: return {5};
    case E::kIntegrator: return {l.width};
    case E::kTangent: return {6 * (l.bodies + l.rigid), l.stm_columns};
    case E::kSensitivity: return {6 * (l.bodies + l.rigid), l.sensitivity_columns};
    case E::kForceBalance: return {l.forces, 7};
    case E::kParticleVector: return {};  // filled by a feature: its shape as declared (above)
    case E::kRunFeatures: return {l.features};
  }
  return {};
}

std::size_t frame_rank(Extent e) {
  const std::string brackets = describe_extent(e);
  return static_cast<std::size_t>(std::count(brackets.begin(), brackets.end(), '[')) - 1;
}

FrameLayout layout_of(const System& system, std::size_t width, std::size_t stm_columns,
                      std::size_t sensitivity_columns, std::size_t forces, std::vector<FeatureSeries> feature_series,
                      std::size_t features) {
  FrameLayout l;
  l.features = features;
  l.forces = forces;
  l.feature_series = std::move(feature_series);
  l.stm_columns = stm_columns;
  l.sensitivity_columns = sensitivity_columns;
  l.bodies = system.size();
  l.rigid = system.rigid_count();
  l.width = width;
  if (const auto pair = binary_pair(system)) {
    l.binary = true;
    l.primary_rigid = system.rigid_index(pair->primary) >= 0;
    l.secondary_rigid = system.rigid_index(pair->secondary) >= 0;
  }
  return l;
}

bool rigid_only(const FrameQuantity& q) {
  return q.extent == E::kRigidVector || q.extent == E::kRigidQuaternion || q.extent == E::kRigidMatrix ||
         q.extent == E::kRigidScalar;
}
bool optional(const FrameQuantity& q) {
  return q.extent == E::kIntegrator || q.extent == E::kTangent || q.extent == E::kSensitivity || q.extent == E::kChaos ||
         q.extent == E::kForceBalance || q.extent == E::kParticleVector || q.extent == E::kRunFeatures;
}
bool binary_only(const FrameQuantity& q) {
  return q.extent == E::kBinaryScalar || q.extent == E::kBinaryVector || q.extent == E::kBinaryElements ||
         q.extent == E::kPrimaryFrame || q.extent == E::kSecondaryAngle || q.extent == E::kSecondaryVector;
}
std::string requirement(const FrameQuantity& q) {
  switch (q.extent) {
    case E::kRigidVector:
    case E::kRigidQuaternion:
    case E::kRigidMatrix:
    case E::kRigidScalar: return "rigid bodies";
    case E::kIntegrator: return "an integrator with variables of its own";
    case E::kTangent: return "run.stm";
    case E::kSensitivity: return "run.sensitivities";
    case E::kChaos: return "run.chaos";
    case E::kForceBalance: return "forces";
    case E::kParticleVector: return "particles";
    case E::kRunFeatures: return "run.chaos or impulses";
    case E::kBinaryScalar:
    case E::kBinaryVector:
    case E::kBinaryElements: return "a binary";
    case E::kPrimaryFrame: return "a binary with a rigid primary";
    case E::kSecondaryAngle:
    case E::kSecondaryVector: return "a binary with a rigid secondary";
    default: return "";
  }
}

bool is_integer(const FrameQuantity& q) { return q.extent == E::kStepCount || q.extent == E::kWork; }

std::string unit_of(Dimension d, const Units& u) {
  switch (d) {
    case D::kOne: return "1";
    case D::kTime: return u.of_time();
    case D::kLength: return u.of_length();
    case D::kVelocity: return u.of_velocity();
    case D::kMomentum: return u.of_momentum();
    case D::kAngularMomentum: return u.of_angular_momentum();
    case D::kEnergy: return u.of_energy();
    case D::kAngularVelocity: return u.of_angular_velocity();
    case D::kWallSeconds: return "s";
    case D::kDegrees: return "deg";
    case D::kMixed: return "mixed";
  }
  return "";
}

std::string describe_extent(Extent e) {
  switch (e) {
    case E::kStepCount:
    case E::kScalar:
    case E::kChaos: return "[frame]";
    case E::kVector: return "[frame][3]";
    case E::kBodyVector: return "[frame][body][3]";
    case E::kRigidVector: return "[frame][rigid body][3]";
    case E::kRigidScalar: return "[frame][rigid body]";
    case E::kRigidQuaternion: return "[frame][rigid body][4]";
    case E::kRigidMatrix: return "[frame][rigid body][3][3]";
    case E::kWork: return "[frame][5]";
    case E::kIntegrator: return "[frame][width]";
    case E::kTangent: return "[frame][coordinate][coordinate]";
    case E::kSensitivity: return "[frame][coordinate][parameter]";
    case E::kForceBalance: return "[frame][force][7]";
    case E::kParticleVector: return "[frame][particle][3]";
    case E::kRunFeatures: return "[frame][field]";
    case E::kBinaryScalar:
    case E::kSecondaryAngle: return "[frame]";
    case E::kBinaryVector:
    case E::kPrimaryFrame:
    case E::kSecondaryVector: return "[frame][3]";
    case E::kBinaryElements: return "[frame][6]";
  }
  return "";
}

std::span<const double> RecordedFrame::series_named(std::string_view name) const {
  for (const auto& [n, values] : series)
    if (n == name) return values;
  return {};
}

void RecordedFrame::set_series(std::string_view name, const double* values, std::size_t count) {
  for (auto& [n, v] : series)
    if (n == name) return v.assign(values, values + count);
  series.emplace_back(std::string(name), std::vector<double>(values, values + count));
}

}  // namespace noether::io

namespace noether {

std::size_t FeatureSeries::size() const {
  std::size_t n = 1;
  for (const auto d : shape) n *= d;
  return n;
}

}  // namespace noether
