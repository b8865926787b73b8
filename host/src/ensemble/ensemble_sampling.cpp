// Ensemble sampling (docs/ensembles.md): --vary KEY=DIST parsed, and sample i's values drawn
// from (seed, i) alone, so that any sample can be run, or run again, by itself.
#include <noether/ensemble.hpp>
#include <noether/error.hpp>
#include <noether/params.hpp>
#include <noether/scene.hpp>

#include "scene/portable_random.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <sstream>

namespace noether {

namespace {

double number(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  while (used < text.size() && std::isspace(static_cast<unsigned char>(text[used]))) ++used;
  if (used != text.size() || text.empty() || !std::isfinite(v))
    throw SceneError(where + ": '" + text + "' is not a finite number");
  return v;
}

}  // namespace

Variation parse_variation(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--vary '" + text + "': expected KEY=DISTRIBUTION, e.g. bodies.beta.mass=normal(1, 0.01)");
  Variation v;
  v.key = text.substr(0, eq);
  v.text = text;
  const std::string spec = text.substr(eq + 1);
  const auto open = spec.find('('), close = spec.rfind(')');
  const std::string where = "--vary " + v.key;
  if (open == std::string::npos || close == std::string::npos || close < open || close + 1 != spec.size())
    throw SceneError(where + ": '" + spec +
                     "' is not a distribution: normal(mean, sd), uniform(a, b), log-uniform(a, b), list(v1, ...), "
                     "grid(a, b, n)");
  const std::string name = spec.substr(0, open);
  std::vector<std::string> parts;
  {
    std::stringstream ss(spec.substr(open + 1, close - open - 1));
    for (std::string part; std::getline(ss, part, ',');) {
      const auto a = part.find_first_not_of(" \t"), b = part.find_last_not_of(" \t");
      parts.push_back(a == std::string::npos ? std::string() : part.substr(a, b - a + 1));
    }
  }
  for (const auto& p : parts) v.args.push_back(number(p, where));
  auto need = [&](std::size_t n, const char* form) {
    if (v.args.size() != n) throw SceneError(where + ": " + name + " takes " + form + ", not '" + spec + "'");
  };
  if (name == "normal") {
    v.kind = Variation::Kind::Normal;
    need(2, "(mean, sd)");
    if (!(v.args[1] >= 0)) throw SceneError(where + ": normal's standard deviation must be ≥ 0");
    // Box–Muller draws lie within 8.6 sd of the mean (u ≥ 2^-53): they must stay finite.
    if (!std::isfinite(std::abs(v.args[0]) + 9.0 * v.args[1]))
      throw SceneError(where + ": normal(mean, sd) would draw values that overflow (|mean| + 9 sd is not finite)");
  } else if (name == "uniform") {
    v.kind = Variation::Kind::Uniform;
    need(2, "(a, b)");
    if (!(v.args[0] < v.args[1])) throw SceneError(where + ": uniform(a, b) needs a < b");
    if (!std::isfinite(v.args[1] - v.args[0])) throw SceneError(where + ": uniform(a, b): b − a overflows");
  } else if (name == "log-uniform") {
    v.kind = Variation::Kind::LogUniform;
    need(2, "(a, b)");
    if (!(v.args[0] > 0 && v.args[0] < v.args[1])) throw SceneError(where + ": log-uniform(a, b) needs 0 < a < b");
  } else if (name == "list") {
    v.kind = Variation::Kind::List;
    if (v.args.empty()) throw SceneError(where + ": list() needs at least one value");
  } else if (name == "grid") {
    v.kind = Variation::Kind::Grid;
    need(3, "(a, b, n)");
    if (!(v.args[2] >= 1 && v.args[2] == std::floor(v.args[2]) && v.args[2] <= 1e9))
      throw SceneError(where + ": grid(a, b, n) needs a whole n from 1 to 10^9");
    if (v.args[2] > 1 && !(v.args[0] < v.args[1])) throw SceneError(where + ": grid(a, b, n) needs a < b");
    if (!std::isfinite((v.args[1] - v.args[0]) * (v.args[2] - 1)))
      throw SceneError(where + ": grid(a, b, n): (b − a)(n − 1) overflows");
  } else {
    throw SceneError(where + ": unknown distribution '" + name +
                     "' (normal, uniform, log-uniform, list, grid)");
  }
  return v;
}

std::size_t grid_size(const std::vector<Variation>& vary) {
  std::size_t n = 1;
  constexpr std::size_t kMax = std::size_t{1} << 53;  // sample indices stay exact in a double
  for (const auto& v : vary)
    if (v.kind == Variation::Kind::Grid) {
      const auto points = static_cast<std::size_t>(v.args[2]);
      if (n > kMax / points)
        throw SceneError("--vary " + v.key + ": the grids' product has more than 2^53 points");
      n *= points;
    }
  return n;
}

std::vector<Variation> variations_from_fit(const std::filesystem::path& fit_json) {
  std::ifstream in(fit_json);
  if (!in) throw SceneError(fit_json.string() + ": cannot read the fit");
  std::stringstream text;
  text << in.rdbuf();
  const std::string file = fit_json.string();
  const Params fit = parse_params(text.str(), file);  // JSON is YAML
  if (!fit.is_map() || !fit.has("parameters") || !fit.has("covariance") || !fit.at("parameters").is_sequence())
    throw SceneError(file + ": not a fit's JSON (noether fit -o FILE.json): it needs parameters and covariance");
  const auto& parameters = fit.at("parameters").items();
  const auto P = static_cast<Eigen::Index>(parameters.size());
  Eigen::MatrixXd C(P, P);
  const auto& rows = fit.at("covariance").items();
  if (static_cast<Eigen::Index>(rows.size()) != P)
    throw SceneError(file + ": its covariance has " + std::to_string(rows.size()) + " rows for " + std::to_string(P) +
                     " parameters");
  for (Eigen::Index i = 0; i < P; ++i) {
    const std::vector<double> row = rows[static_cast<std::size_t>(i)].as_doubles();
    if (static_cast<Eigen::Index>(row.size()) != P) throw SceneError(file + ": its covariance is not square");
    for (Eigen::Index j = 0; j < P; ++j) C(i, j) = row[static_cast<std::size_t>(j)];
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (C + C.transpose()));
  if (llt.info() != Eigen::Success || !C.allFinite())
    throw SceneError(file + ": its covariance is not positive definite; it cannot be sampled");
  const Eigen::MatrixXd L = llt.matrixL();
  std::vector<Variation> out;
  for (Eigen::Index j = 0; j < P; ++j) {
    const Params& p = parameters[static_cast<std::size_t>(j)];
    Variation v;
    v.kind = Variation::Kind::Fitted;
    v.key = p.at("name").as_string();
    v.args.push_back(p.at("estimate").as_double());
    for (Eigen::Index k = 0; k <= j; ++k) v.args.push_back(L(j, k));
    // What /inputs/<key> records as its distribution (and --resume compares): all of it.
    std::ostringstream text;
    text.precision(17);
    text << v.key << "=fit(" << file << "; mean " << v.args[0] << ", Cholesky row";
    for (std::size_t k = 1; k < v.args.size(); ++k) text << " " << v.args[k];
    text << ")";
    v.text = text.str();
    out.push_back(v);
  }
  if (out.empty()) throw SceneError(file + ": the fit has no parameters");
  return out;
}

std::vector<double> sample_values(const std::vector<Variation>& vary, std::uint64_t seed, std::size_t index) {
  std::vector<double> out;
  std::vector<double> z;  // the standard normals of the Fitted variations so far
  // Grids: the index in mixed radix, the first grid the slowest digit.
  std::size_t stride = grid_size(vary);
  for (std::size_t k = 0; k < vary.size(); ++k) {
    const Variation& v = vary[k];
    const double u1 = uniform01(seed, index, 2 * k), u2 = uniform01(seed, index, 2 * k + 1);
    switch (v.kind) {
      case Variation::Kind::Normal:  // Box–Muller
        out.push_back(v.args[0] + v.args[1] * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
        break;
      case Variation::Kind::Uniform:
        out.push_back(v.args[0] + (v.args[1] - v.args[0]) * u1);
        break;
      case Variation::Kind::LogUniform:
        out.push_back(std::clamp(std::exp(std::log(v.args[0]) + (std::log(v.args[1]) - std::log(v.args[0])) * u1),
                                 v.args[0], v.args[1]));  // exp(log b) may round past b
        break;
      case Variation::Kind::List:
        out.push_back(v.args[std::min(v.args.size() - 1, static_cast<std::size_t>(u1 * static_cast<double>(v.args.size())))]);
        break;
      case Variation::Kind::Fitted: {  // x_j = μ_j + Σ_{k ≤ j} L_jk z_k
        z.push_back(std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
        double x = v.args[0];
        for (std::size_t m = 0; m < z.size() && m + 1 < v.args.size(); ++m) x += v.args[m + 1] * z[m];
        out.push_back(x);
        break;
      }
      case Variation::Kind::Grid: {
        const auto n = static_cast<std::size_t>(v.args[2]);
        stride /= n;
        const std::size_t digit = (index / stride) % n;
        out.push_back(n == 1 ? v.args[0] : v.args[0] + (v.args[1] - v.args[0]) * static_cast<double>(digit) /
                                                           static_cast<double>(n - 1));
        break;
      }
    }
  }
  return out;
}

}  // namespace noether
