// noether fit: weighted least squares by Levenberg–Marquardt on the run's sensitivities, and the
// covariance of the estimate (docs/equations.md §28; docs/fitting.md).
#include "io/json_text.hpp"
#include "scene/scene_sensitivity.hpp"

#include <noether/error.hpp>
#include <noether/fit.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <optional>
#include <sstream>

namespace noether {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using detail::json_number;
using detail::json_string;
using detail::exact_text;

// The scene's overrides with each parameter set to its value.
std::vector<std::string> with_values(const std::vector<std::string>& overrides, const std::vector<std::string>& names,
                                     const VectorXd& values) {
  std::vector<std::string> out = overrides;
  for (std::size_t j = 0; j < names.size(); ++j) out.push_back(names[j] + "=" + exact_text(values[static_cast<Eigen::Index>(j)]));
  return out;
}

// The whitened residuals and Jacobian (28.3): r_i = (y_i − h_i)/σ_i, A_ij = (∂h_i/∂p_j)/σ_i.
struct Whitened {
  VectorXd r;
  MatrixXd A;
  double chi2 = 0.0;
  VectorXd computed;
  Verdict verdict;  // the run's
};

Whitened whiten(const Prediction& p, const std::vector<Observation>& obs) {
  Whitened w;
  w.verdict = p.verdict;
  const auto N = static_cast<Eigen::Index>(obs.size());
  w.r.resize(N);
  w.A.resize(N, p.jacobian.cols());
  for (Eigen::Index i = 0; i < N; ++i) {
    const Observation& o = obs[static_cast<std::size_t>(i)];
    w.r[i] = (o.value - p.values[i]) / o.sigma;
    w.A.row(i) = p.jacobian.row(i) / o.sigma;
  }
  w.chi2 = w.r.squaredNorm();
  w.computed = p.values;
  return w;
}

// Refuses parameters the observations do not determine (28.5): a column of A that is zero, or
// columns (each scaled to unit length) so nearly dependent that AᵀA is singular to working
// precision — the parameters with the largest share of the null direction named.
void require_observable(const MatrixXd& A, const std::vector<std::string>& names) {
  const Eigen::Index P = A.cols();
  VectorXd scale(P);
  for (Eigen::Index j = 0; j < P; ++j) {
    scale[j] = A.col(j).norm();
    if (!(scale[j] > 0) || !std::isfinite(scale[j]))
      throw SceneError("the observations do not depend on " + names[static_cast<std::size_t>(j)] +
                       " (its column of the Jacobian is " + (std::isfinite(scale[j]) ? "zero" : "not finite") +
                       "): it cannot be fitted; fix it, or add observations that see it");
  }
  const MatrixXd As = A * scale.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<MatrixXd> svd(As, Eigen::ComputeThinV);
  const VectorXd& s = svd.singularValues();
  const double condition = s[0] / s[P - 1];
  if (!(condition < 1e7)) {  // AᵀA's condition is its square: beyond ~1e14, its inverse is noise
    const VectorXd null = svd.matrixV().col(P - 1);
    std::string which;
    for (Eigen::Index j = 0; j < P; ++j)
      if (std::abs(null[j]) > 0.2) which += (which.empty() ? "" : ", ") + names[static_cast<std::size_t>(j)];
    std::ostringstream why;
    why.precision(2);
    why << "the observations do not determine " << which << " separately (the columns of the Jacobian, each scaled to "
        << "unit length, are dependent: condition number " << std::scientific << condition
        << "); fix one of them, or add observations that separate them";
    throw SceneError(why.str());
  }
}

}  // namespace

FitResult fit(const std::string& scene_file, const std::vector<std::string>& overrides,
              const std::string& observations_file, const FitOptions& options, PluginRegistry& registry) {
  if (options.free.empty()) throw SceneError("--free: name at least one key to fit");
  if (!(options.tolerance > 0)) throw SceneError("--tolerance must be positive");
  FitResult result;
  result.scene_file = scene_file;
  result.observations_file = observations_file;
  const Scene scene = load_scene(scene_file, overrides);
  std::vector<std::string> names;
  for (std::size_t j = 0; j < scene.system.size(); ++j) names.push_back(scene.system.body(j).name);
  const std::vector<Observation> obs = read_observations(observations_file, names);
  result.bodies = names;
  result.observations = obs.size();

  // The start: the run at the scene's values, which also names the parameters' components.
  Prediction at = predict(scene_file, overrides, obs, options.free, registry, observations_file);
  ++result.runs;
  result.names = at.names;
  const auto P = static_cast<Eigen::Index>(result.names.size());
  result.initial.resize(P);
  for (Eigen::Index j = 0; j < P; ++j) {
    try {
      result.initial[j] = sensitivity_key_value(scene, result.names[static_cast<std::size_t>(j)]);
    } catch (const SceneError& e) {
      throw SceneError(std::string("--free ") + e.what() + "; a fit varies values the scene writes");
    }
  }
  result.degrees_of_freedom = static_cast<std::ptrdiff_t>(obs.size()) - static_cast<std::ptrdiff_t>(P);
  if (result.degrees_of_freedom < 0)
    throw SceneError("--free: " + std::to_string(P) + " parameters from " + std::to_string(obs.size()) +
                     " observations: a fit needs at least as many observations as parameters");
  Whitened w = whiten(at, obs);
  require_observable(w.A, result.names);
  result.chi2_initial = w.chi2;
  VectorXd p = result.initial;

  // Levenberg–Marquardt (28.4): (AᵀA + λ diag(AᵀA)) δ = Aᵀr; a step that lowers χ² is taken
  // and λ falls tenfold (to 0, Gauss–Newton, below 1e-6), else λ rises tenfold (from 1e-3) and
  // the step is tried again. It starts as Gauss–Newton, which a nearly linear problem needs.
  double lambda = 0.0;
  result.stop = "the iteration limit (" + std::to_string(options.max_iterations) + ") was reached";
  while (result.iterations < options.max_iterations) {
    const MatrixXd N = w.A.transpose() * w.A;
    const VectorXd g = w.A.transpose() * w.r;
    const VectorXd sigma = N.ldlt().solve(MatrixXd::Identity(P, P)).diagonal().cwiseSqrt();
    bool taken = false;
    while (!taken) {
      MatrixXd damped = N;
      damped.diagonal() += lambda * N.diagonal();
      const VectorXd delta = damped.ldlt().solve(g);
      const VectorXd trial = p + delta;
      std::optional<Whitened> tried;
      try {
        tried = whiten(predict(scene_file, with_values(overrides, result.names, trial), obs, options.free, registry,
                               observations_file),
                       obs);
        ++result.runs;
      } catch (const Error&) {  // a step the scene refuses (a negative mass) or that fails: shorter
        ++result.runs;
        tried.reset();
      }
      if (tried && tried->chi2 <= w.chi2) {
        taken = true;
        p = trial;
        w = *tried;
        ++result.iterations;
        lambda = lambda / 10 < 1e-6 ? 0.0 : lambda / 10;
        if ((delta.cwiseAbs().array() < options.tolerance * sigma.array()).all()) {
          result.converged = true;
          result.stop = "every parameter moved by less than " + exact_text(options.tolerance) + " of its 1σ";
        }
      } else {
        lambda = lambda == 0.0 ? 1e-3 : 10 * lambda;
        if (lambda > 1e12) {
          result.stop = "no step lowers χ² (λ = 1e12): a minimum, or a model that cannot follow the data";
          result.converged = (g.cwiseAbs().array() <= 1e-9 * std::max(1.0, std::sqrt(w.chi2))).all();
          break;
        }
      }
    }
    if (!taken || result.converged) break;
  }

  // The estimate's covariance (28.5): (AᵀA)⁻¹ of the whitened Jacobian at the estimate.
  require_observable(w.A, result.names);
  result.estimate = p;
  result.chi2 = w.chi2;
  result.covariance = (w.A.transpose() * w.A).ldlt().solve(MatrixXd::Identity(P, P));
  result.sigma = result.covariance.diagonal().cwiseSqrt();
  result.correlation = result.sigma.cwiseInverse().asDiagonal() * result.covariance * result.sigma.cwiseInverse().asDiagonal();
  result.overrides = with_values(overrides, result.names, p);
  result.verdict = w.verdict;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    FitResidual r;
    r.observation = obs[i];
    r.computed = w.computed[static_cast<Eigen::Index>(i)];
    r.residual = obs[i].value - r.computed;
    r.normalized = r.residual / obs[i].sigma;
    result.residuals.push_back(r);
  }
  return result;
}

std::string format_fit(const FitResult& r) {
  std::ostringstream out;
  out << "fit of " << r.scene_file << " to " << r.observations_file << " (" << r.observations << " observations, "
      << r.names.size() << " parameters)\n";
  std::size_t width = 9;
  for (const auto& n : r.names) width = std::max(width, n.size());
  out << std::left << std::setw(static_cast<int>(width) + 2) << "parameter" << std::right << std::setw(24) << "estimate"
      << std::setw(12) << "1σ" << std::setw(24) << "initial" << "\n";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    const auto k = static_cast<Eigen::Index>(j);
    out << std::left << std::setw(static_cast<int>(width) + 2) << r.names[j] << std::right << std::setprecision(15)
        << std::setw(24) << r.estimate[k] << std::setprecision(3) << std::setw(12) << r.sigma[k] << std::setprecision(15)
        << std::setw(24) << r.initial[k] << "\n";
  }
  if (r.names.size() > 1) {
    out << "correlation\n";
    for (std::size_t j = 0; j < r.names.size(); ++j) {
      out << "  ";
      for (std::size_t k = 0; k < r.names.size(); ++k)
        out << std::fixed << std::setprecision(4) << std::setw(8)
            << r.correlation(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k));
      out << "\n";
    }
    out << std::defaultfloat;
  }
  out << std::setprecision(6) << "chi2                  " << r.chi2 << " for " << r.degrees_of_freedom
      << " degrees of freedom (from " << r.chi2_initial << " at the start)";
  if (r.degrees_of_freedom > 0)
    out << "; reduced " << r.chi2 / static_cast<double>(r.degrees_of_freedom) << ", expected 1 ± "
        << std::sqrt(2.0 / static_cast<double>(r.degrees_of_freedom));
  out << "\niterations            " << r.iterations << " (" << r.runs << " runs with sensitivities)\n";
  out << (r.converged ? "converged             " : "NOT CONVERGED         ") << r.stop << "\n";
  out << "verdict               ";
  if (r.verdict.trustworthy) {
    out << "trustworthy (the run at the estimate)\n";
  } else {
    out << "UNTRUSTWORTHY (the run at the estimate):";
    for (const auto& why : r.verdict.reasons) out << " " << why << ";";
    out << "\n";
  }
  return out.str();
}

namespace {

std::string json_matrix(const MatrixXd& m) {
  std::string out = "[";
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    out += i ? ", [" : "[";
    for (Eigen::Index j = 0; j < m.cols(); ++j) out += (j ? ", " : "") + json_number(m(i, j));
    out += "]";
  }
  return out + "]";
}

}  // namespace

std::string fit_json(const FitResult& r) {
  std::ostringstream out;
  out << "{\n  \"scene\": " << json_string(r.scene_file) << ",\n  \"observations_file\": "
      << json_string(r.observations_file) << ",\n  \"parameters\": [";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    const auto k = static_cast<Eigen::Index>(j);
    out << (j ? ",\n    " : "\n    ") << "{\"name\": " << json_string(r.names[j]) << ", \"estimate\": "
        << json_number(r.estimate[k]) << ", \"sigma\": " << json_number(r.sigma[k]) << ", \"initial\": "
        << json_number(r.initial[k]) << "}";
  }
  out << "],\n  \"covariance\": " << json_matrix(r.covariance) << ",\n  \"correlation\": " << json_matrix(r.correlation)
      << ",\n  \"chi2\": " << json_number(r.chi2) << ",\n  \"chi2_initial\": " << json_number(r.chi2_initial)
      << ",\n  \"observations\": " << r.observations << ",\n  \"degrees_of_freedom\": " << r.degrees_of_freedom
      << ",\n  \"iterations\": " << r.iterations << ",\n  \"runs\": " << r.runs << ",\n  \"converged\": "
      << (r.converged ? "true" : "false") << ",\n  \"stop\": " << json_string(r.stop)
      << ",\n  \"trustworthy\": " << (r.verdict.trustworthy ? "true" : "false") << ",\n  \"verdict\": [";
  for (std::size_t j = 0; j < r.verdict.reasons.size(); ++j) out << (j ? ", " : "") << json_string(r.verdict.reasons[j]);
  out << "],\n  \"overrides\": [";
  for (std::size_t j = 0; j < r.overrides.size(); ++j) out << (j ? ", " : "") << json_string(r.overrides[j]);
  out << "],\n  \"residuals\": [";
  for (std::size_t i = 0; i < r.residuals.size(); ++i) {
    const FitResidual& x = r.residuals[i];
    const Observation& o = x.observation;
    out << (i ? ",\n    " : "\n    ") << "{\"line\": " << o.line << ", \"t\": " << json_number(o.t)
        << ", \"observable\": " << json_string(observable_name(o.observable.kind))
        << ", \"target\": " << json_string(r.bodies.at(o.observable.target))
        << ", \"center\": " << json_string(r.bodies.at(o.observable.center)) << ", \"observed\": " << json_number(o.value) << ", \"sigma\": "
        << json_number(o.sigma) << ", \"computed\": " << json_number(x.computed) << ", \"residual\": "
        << json_number(x.residual) << ", \"normalized\": " << json_number(x.normalized) << "}";
  }
  out << "]\n}\n";
  return out.str();
}

}  // namespace noether
