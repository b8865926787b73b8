// The scene's impulses as a run feature (impulse_feature.hpp).
#include "run/impulse_feature.hpp"

#include <noether/error.hpp>
#include <noether/parameter_derivatives.hpp>
#include <noether/stepping.hpp>

#include "run/impulse_frame.hpp"
#include "run/summary_schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <spdlog/spdlog.h>

namespace noether::detail {

ImpulseFeature::ImpulseFeature(const System& system, const std::vector<Impulse>& impulses, double t0, double h,
                               Units units)
    : system_(system), impulses_(impulses), order_(impulses.size()), units_(std::move(units)) {
  for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = k;
  std::stable_sort(order_.begin(), order_.end(),
                   [this](std::size_t a, std::size_t b) { return impulses_[a].time < impulses_[b].time; });
  // A fixed-step method applies each impulse at a step of its grid (those still to come: a
  // loaded simulation's initial state may stand after some).
  if (h > 0)
    for (std::size_t k = 0; k < impulses.size(); ++k)
      if (impulses[k].time > t0) whole_steps(impulses[k].time - t0, h, ("impulses." + std::to_string(k) + ".time − t0").c_str());
}

void ImpulseFeature::start(const State& state, Eigen::Ref<Eigen::MatrixXd>) {
  applied_ = 0;
  warnings_.clear();
  while (applied_ < order_.size() && impulses_[order_[applied_]].time <= state.t) ++applied_;
}

void ImpulseFeature::save(Eigen::Ref<const Eigen::MatrixXd>, std::span<double> out) const {
  out[0] = static_cast<double>(applied_);
}

void ImpulseFeature::restore(std::span<const double> in, Eigen::Ref<Eigen::MatrixXd>) {
  if (in.size() != 1 || !(in[0] >= 0.0 && in[0] <= static_cast<double>(order_.size())) || in[0] != std::floor(in[0]))
    throw Error("impulses: a checkpoint's count of applied impulses does not fit the scene's " +
                std::to_string(order_.size()));
  applied_ = static_cast<std::size_t>(in[0]);
}

std::optional<std::size_t> ImpulseFeature::next() const {
  if (applied_ >= order_.size()) return std::nullopt;
  return order_[applied_];
}

std::optional<double> ImpulseFeature::next_jump() const {
  if (const std::optional<std::size_t> k = next()) return impulses_[*k].time;
  return std::nullopt;
}

// Applies impulse k where the run stands, at its time (docs/equations.md §24): the body's
// momentum jumps by m Δv (24.1), the tangent by the jump's derivative (24.2, 24.6, 24.7). Counted
// as applied first: the frame after it holds the count.
void ImpulseFeature::jump(StateJump& at) {
  const std::size_t k = *next();
  mark_applied();
  const Impulse& impulse = impulses_[k];
  const System& sys = system_;
  State& state = at.state;
  const auto b = static_cast<Eigen::Index>(impulse.body), c = static_cast<Eigen::Index>(impulse.around);
  const double mass = sys.body(impulse.body).mass;
  const State before = state;
  const bool rtn = impulse.frame == Impulse::Frame::rtn;
  const RelativeOrbit orbit = rtn ? relative_orbit(impulse, sys, before) : RelativeOrbit{};
  Mat3 Q = Mat3::Identity();
  if (rtn) {
    try {
      Q = rtn_frame(orbit.r, orbit.v);
    } catch (const Error& e) {  // named: which impulse, whose orbit, when
      std::ostringstream where;
      where.precision(10);
      where << "impulses." << k << " (body '" << sys.body(impulse.body).name << "' about '"
            << sys.body(impulse.around).name << "', t = " << impulse.time << "): " << e.what();
      throw Error(where.str());
    }
  }
  const Vec3 dv = Q * impulse.delta_v;
  state.p.col(b) += mass * dv;  // (24.1)
  Eigen::MatrixXd& V = state.tangent;
  if (V.size() == 0) return;
  const auto n = static_cast<Eigen::Index>(sys.size()), q = 3 * (n + static_cast<Eigen::Index>(sys.rigid_count()));
  const Eigen::Index row = q + 3 * b;  // γ_b's rows; x_b's are 3b
  const auto P = static_cast<Eigen::Index>(at.sensitivity_names.size());
  const auto Qp = at.parameters ? static_cast<Eigen::Index>(at.parameters->size()) : Eigen::Index{0};
  auto mass_derivative = [&](Eigen::Index column, std::size_t body) {  // ∂m_body/∂p of a parameter's column
    const Eigen::Index j = column - (V.cols() - Qp);
    return j >= 0 ? at.parameters->parameters[static_cast<std::size_t>(j)].mass(static_cast<Eigen::Index>(body)) : 0.0;
  };
  if (rtn) {  // (24.6): the frame turns with the orbit, ∂γ_b⁺/∂z⁻ = m_b (∂Q/∂z⁻) Δv_RTN, on every column
    const double mc = sys.body(impulse.around).mass;
    const Eigen::MatrixXd W = V;
    for (Eigen::Index j = 0; j < V.cols(); ++j) {
      const double dmb = mass_derivative(j, impulse.body), dmc = mass_derivative(j, impulse.around);
      const Vec3 dr = W.block<3, 1>(3 * b, j) - W.block<3, 1>(3 * c, j);
      const Vec3 dvel = (W.block<3, 1>(q + 3 * b, j) - before.p.col(b) * dmb / mass) / mass -
                        (W.block<3, 1>(q + 3 * c, j) - before.p.col(c) * dmc / mc) / mc;
      V.block<3, 1>(row, j) += mass * rtn_frame_derivative(orbit.r, orbit.v, dr, dvel) * impulse.delta_v;
    }
  }
  const std::string key = "impulses." + std::to_string(k) + ".";  // + delta_v.a or time
  for (Eigen::Index col = 0; col < P; ++col) {
    const std::string& name = at.sensitivity_names[static_cast<std::size_t>(col)];
    if (name.rfind(key, 0) != 0) continue;
    const Eigen::Index j = V.cols() - P + col;
    if (name == key + "time") {
      // (24.7): ∂z⁺/∂t_i = F(z⁻) − F(z⁺) + (∂z⁺/∂z⁻ − I) F(z⁻): x_b's rate drops by Δv; in the RTN
      // frame Δv also turns with the orbit along the flow (δr = v, δv = the relative acceleration).
      V.block<3, 1>(3 * b, j) -= dv;
      if (rtn) {
        Forces f;  // at z⁻, by the run's own evaluator (its workspace: the orders it chose)
        f.resize(sys);
        at.forces_at(before, f);
        const Vec3 acceleration = f.f.col(b) / mass - f.f.col(c) / sys.body(impulse.around).mass;
        V.block<3, 1>(row, j) += mass * rtn_frame_derivative(orbit.r, orbit.v, orbit.v, acceleration) * impulse.delta_v;
      }
    } else {  // (24.2): ∂γ_b⁺/∂Δv = m_b Q
      V.block<3, 1>(row, j) += mass * Q.col(name.back() - '0');
    }
  }
  for (Eigen::Index j = V.cols() - Qp; j < V.cols(); ++j)  // (24.2): ∂γ_b⁺/∂p += (∂m_b/∂p) Δv
    V.block<3, 1>(row, j) += mass_derivative(j, impulse.body) * dv;
}

namespace {

// The speed at distance r from the impulse's `around` below which its body is bound to it:
// √(2 G (m + m_around) / r).
double escape_speed(const System& sys, const Impulse& impulse, double r) {
  return std::sqrt(2 * sys.G() * (sys.body(impulse.body).mass + sys.body(impulse.around).mass) / r);
}

}  // namespace

void ImpulseFeature::after_jump(const State& before, const State& after) {
  // The impulse this jump was: one at its time whose body's momentum changed.
  for (std::size_t k = 0; k < impulses_.size(); ++k) {
    const Impulse& impulse = impulses_[k];
    const auto b = static_cast<Eigen::Index>(impulse.body);
    if (impulse.time != after.t || before.p.col(b) == after.p.col(b)) continue;
    const RelativeOrbit was = relative_orbit(impulse, system_, before), is = relative_orbit(impulse, system_, after);
    const double r = is.r.norm(), escape = escape_speed(system_, impulse, r);
    if (!(was.v.norm() < escape) || is.v.norm() < escape) return;
    // Would the same Δv a thousand times smaller have kept the pair bound (a unit slip)?
    const bool slip = (was.v + (is.v - was.v) / 1000.0).norm() < escape;
    const std::string velocity = units_.declared ? " " + units_.of_velocity() : "",
                      length = units_.declared ? " " + units_.of_length() : "",
                      time = units_.declared ? " " + units_.of_time() : "";
    const std::string& around = system_.body(impulse.around).name;
    char text[640];
    std::snprintf(text, sizeof text,
                  "impulses.%zu (t = %.10g%s) unbinds %s from %s: its |delta_v| of %.4g%s took the speed relative to "
                  "%s from %.4g to %.4g%s, past the escape speed %.4g%s at %.4g%s",
                  k, impulse.time, time.c_str(), system_.body(impulse.body).name.c_str(), around.c_str(),
                  impulse.delta_v.norm(), velocity.c_str(), around.c_str(), was.v.norm(), is.v.norm(), velocity.c_str(),
                  escape, velocity.c_str(), r, length.c_str());
    std::string warning = text;
    if (slip)
      warning += units_.declared && units_.of_velocity() == "m/s"
                     ? "; a thousandth of it would keep the pair bound: a delta_v in mm/s typed as m/s?"
                     : "; a thousandth of it would keep the pair bound: a delta_v in a unit 1000 times too large?";
    spdlog::warn("{}", warning);
    warnings_.push_back(std::move(warning));
    return;
  }
}

void ImpulseFeature::save_running(SavedSummary& out) const {
  std::string joined;
  for (const std::string& w : warnings_) joined += w + "\n";
  if (!joined.empty()) out.texts.emplace_back("impulses.warnings", joined);
}

void ImpulseFeature::restore_running(const SavedSummary& in) {
  warnings_.clear();
  if (const std::string* joined = in.text("impulses.warnings"))
    for (std::size_t at = 0, end; (end = joined->find('\n', at)) != std::string::npos; at = end + 1)
      warnings_.push_back(joined->substr(at, end - at));
}

void ImpulseFeature::summarize(RunSummary& summary) const {
  summary.warnings.insert(summary.warnings.end(), warnings_.begin(), warnings_.end());
}

}  // namespace noether::detail
