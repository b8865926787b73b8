#include <noether/compare.hpp>
#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "io/h5.hpp"
#include "run/summary_schema.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace noether {

std::vector<CompareRun> expand_runs(const Params& mapping) {
  if (!mapping.is_map() || !mapping.has("plugin"))
    throw SceneError(mapping.here() + "a compare run must be a mapping naming a plugin, e.g. "
                                      "{plugin: lgvi, step: [1e-3, 5e-4]}");
  std::size_t n = 1;
  std::string list_key;
  for (const auto& [key, value] : mapping.entries()) {
    if (!value.is_sequence()) continue;
    if (list_key.empty()) {
      n = value.size();
      list_key = key;
    } else if (value.size() != n) {
      throw SceneError(value.here() + "compare run: the lists '" + list_key + "' and '" + key +
                       "' must have the same length");
    }
  }
  if (n == 0) throw SceneError(mapping.here() + "compare run: an empty list gives no runs");
  // The family (one line in the plot): the plugin, its method, and the settings that stay
  // fixed — every non-list setting when some settings are lists, else the non-numeric ones
  // (renormalize=true, frame=relative, ...). The label: the settings that vary.
  std::string family = mapping.at("plugin").as_string();
  if (mapping.has("method") && mapping.at("method").is_scalar())
    family += " " + mapping.at("method").as_string();
  auto is_number = [](const Params& v) {
    try {
      v.as_double();
      return true;
    } catch (const SceneError&) {
      return false;
    }
  };
  auto fixed = [&](const Params& v) { return !v.is_sequence() && (!list_key.empty() || !is_number(v)); };
  for (const auto& [key, value] : mapping.entries())
    if (key != "plugin" && key != "method" && fixed(value)) family += " " + key + "=" + value.as_string();
  std::vector<CompareRun> runs;
  for (std::size_t k = 0; k < n; ++k) {
    CompareRun run;
    run.family = family;
    std::vector<std::pair<std::string, Params>> entries;
    for (const auto& [key, value] : mapping.entries()) {
      const Params item = value.is_sequence() ? value.items()[k] : value;
      entries.emplace_back(key, item);
      if (key != "plugin" && key != "method" && !fixed(value))
        run.label += (run.label.empty() ? "" : " ") + key + "=" + item.as_string();
    }
    run.integrator = Params::map(std::move(entries), mapping.where());
    run.integrator.set_path("integrator");
    runs.push_back(std::move(run));
  }
  return runs;
}

std::vector<CompareRun> expand_model_runs(const Params& mapping) {
  std::vector<CompareRun> runs = expand_runs(mapping);
  for (auto& r : runs) {
    // One line per swept setting: "model mutual-series tolerance", "model mutual-series order".
    r.family = "model " + r.family + (r.label.empty() ? "" : " " + r.label.substr(0, r.label.find('=')));
    r.potential = std::move(r.integrator);
    r.potential.set_path("potential");
    r.integrator = Params();
  }
  return runs;
}

namespace {

Params flow(const std::string& yaml) { return parse_params(yaml, "default compare spec"); }

std::string number(double v) {  // shortest text that reads back as exactly v
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

}  // namespace

CompareSpec default_compare_spec(const Scene& scene) {
  const double dt = scene.run.output_every;
  const std::string steps =
      "[" + number(dt / 10) + ", " + number(dt / 20) + ", " + number(dt / 50) + "]";
  CompareSpec spec;
  for (const std::string& run :
       {"{plugin: lgvi, step: " + steps + "}",
        std::string("{plugin: cvode, method: adams, rtol: [1.0e-6, 1.0e-8, 1.0e-10], "
                    "atol: [1.0e-8, 1.0e-10, 1.0e-12]}"),
        std::string("{plugin: cvode, method: bdf, rtol: [1.0e-6, 1.0e-8, 1.0e-10], "
                    "atol: [1.0e-8, 1.0e-10, 1.0e-12]}"),
        std::string("{plugin: rk, method: dopri5, rtol: [1.0e-6, 1.0e-8, 1.0e-10], "
                    "atol: [1.0e-8, 1.0e-10, 1.0e-12]}"),
        std::string("{plugin: rk, method: rkf78, rtol: [1.0e-6, 1.0e-8, 1.0e-10], "
                    "atol: [1.0e-8, 1.0e-10, 1.0e-12]}"),
        "{plugin: rk, method: rk4, step: " + steps + "}"})
    for (auto& r : expand_runs(flow(run))) spec.runs.push_back(std::move(r));
  spec.reference = flow("{plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-15}");
  spec.reference_check = flow("{plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-14}");
  return spec;
}

CompareSpec load_compare_spec(const std::filesystem::path& file, const Scene& scene) {
  const Params p = load_params_file(file);
  if (!p.is_map()) throw SceneError(file.string() + ": a compare file must be a mapping");
  p.check_keys({"repeats", "reference", "reference_check", "runs", "max_wall_time"}, "the compare file");
  CompareSpec spec = default_compare_spec(scene);
  spec.runs.clear();
  spec.repeats = static_cast<int>(p.get("repeats", 3L));
  spec.max_wall_seconds = p.get("max_wall_time", 0.0);
  if (!(spec.max_wall_seconds >= 0.0))
    throw SceneError(p.at("max_wall_time").here() + "max_wall_time must be a non-negative number of seconds");
  if (p.has("reference")) {  // the default check belongs to the default reference only
    spec.reference = p.at("reference");
    spec.reference_check = Params();
  }
  if (p.has("reference_check")) spec.reference_check = p.at("reference_check");
  for (const auto& run : p.at("runs").items())
    for (auto& r : expand_runs(run)) spec.runs.push_back(std::move(r));
  if (spec.repeats < 1) throw SceneError(p.at("repeats").here() + "repeats must be at least 1");
  return spec;
}

namespace {

Scene with_plugins(const Scene& scene, const Params& integrator, const Params& potential) {
  Scene s = scene;
  if (!integrator.is_null()) s.integrator = {integrator.at("plugin").as_string(), integrator};
  if (!potential.is_null()) s.potentials = {{potential.at("plugin").as_string(), potential}};
  return s;
}

// "order 6" or "orders 0, 0, 12": what a tolerance-driven model chose for the pairs.
std::string chosen_orders(const std::vector<PairModel>& models) {
  if (models.empty()) return {};
  std::string out = models.size() == 1 ? "order " : "orders ";
  for (std::size_t k = 0; k < models.size(); ++k) out += (k ? ", " : "") + std::to_string(models[k].order);
  return out;
}

// max_i ‖x_i − y_i‖ and max_k ‖R_k − Q_k‖_F.
std::pair<double, double> state_difference(const State& a, const State& b) {
  double dx = 0, dR = 0;
  for (Eigen::Index i = 0; i < a.x.cols(); ++i) dx = std::max(dx, (a.x.col(i) - b.x.col(i)).norm());
  for (std::size_t k = 0; k < a.R.size(); ++k) dR = std::max(dR, (a.R[k] - b.R[k]).norm());
  return {dx, dR};
}

std::string describe(const Params& p) {
  std::string out;
  for (const auto& [key, value] : p.entries())
    out += (out.empty() ? "" : ", ") + key + ": " + (value.is_scalar() ? value.as_string() : "...");
  return "{" + out + "}";
}

}  // namespace

CompareResult compare(const Scene& scene, PluginRegistry& registry, const CompareSpec& spec,
                      const CompareProgress& progress) {
  auto say = [&](const std::string& m) {
    if (progress) progress(m);
  };
  CompareResult result;
  result.reference = spec.reference.is_null() ? "the scene's integrator" : describe(spec.reference);
  if (!spec.reference_potential.is_null()) result.reference += " with " + describe(spec.reference_potential);
  say("reference " + result.reference);
  // The wall-time budget bounds the compared runs; the reference must finish.
  RunOptions budget;
  budget.max_wall_seconds = spec.max_wall_seconds;
  const RunSummary ref = run_scene(with_plugins(scene, spec.reference, spec.reference_potential), registry, {});
  result.reference_seconds = ref.wall_seconds;
  if (!ref.stop_reason.empty())
    throw Error("compare: the reference run stopped early (" + ref.stop_reason + ")");
  if (!spec.reference_check.is_null()) {
    const RunSummary check =
        run_scene(with_plugins(scene, spec.reference_check, spec.reference_potential), registry, {});
    const auto [dx, dR] = state_difference(ref.final_state, check.final_state);
    result.reference_error = std::max(dx, dR);
    if (result.reference_error == 0.0)
      result.reference_error_note = "its reference_check run reached the same final state: it is no check";
  } else {
    result.reference_error_note = spec.reference_potential.is_null()
                                      ? "the compare file gives no reference_check to estimate it with"
                                      : "model runs share its integrator, so its integration error cancels";
  }
  for (const auto& run : spec.runs) {
    CompareRow row;
    row.family = run.family;
    row.label = run.label;
    // "model mutual-series order" and "order=8" say "model mutual-series order=8".
    const std::size_t space = run.family.rfind(' ');
    const std::string swept = space == std::string::npos ? "" : run.family.substr(space + 1) + "=";
    say(!swept.empty() && run.label.rfind(swept, 0) == 0 ? run.family + run.label.substr(swept.size() - 1)
                                                          : run.family + " " + run.label);
    try {
      const Scene s = with_plugins(scene, run.integrator, run.potential);
      std::vector<double> seconds;
      RunSummary summary = run_scene(s, registry, budget);
      seconds.push_back(summary.wall_seconds);
      // Repeat for a stable median, but not runs that take more than two seconds.
      for (int k = 1; k < spec.repeats && summary.wall_seconds < 2.0; ++k)
        seconds.push_back(run_scene(s, registry, budget).wall_seconds);
      std::sort(seconds.begin(), seconds.end());
      row.wall_seconds = seconds[seconds.size() / 2];
      for (const detail::SummaryRow* column : detail::summary_rows_for(detail::kCompare))
        row.summary.emplace_back(column->key, column->number(summary));
      if (const std::string orders = chosen_orders(summary.pair_models); !orders.empty())
        row.label += " (" + orders + ")";
      if (!summary.stop_reason.empty()) throw Error("stopped early: " + summary.stop_reason);
      std::tie(row.final_position_error, row.final_attitude_error) =
          state_difference(summary.final_state, ref.final_state);
      row.ok = true;
    } catch (const Error& e) {
      row.ok = false;
      row.error = e.what();
      row.final_position_error = row.final_attitude_error = NAN;
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

// Compare's own columns, then the summary's (run/summary_schema.cpp).
const char* const kOwnColumns[] = {"wall_seconds", "final_position_error", "final_attitude_error"};

std::vector<std::string> compare_columns() {
  std::vector<std::string> out(std::begin(kOwnColumns), std::end(kOwnColumns));
  for (const detail::SummaryRow* column : detail::summary_rows_for(detail::kCompare)) out.emplace_back(column->key);
  return out;
}

double CompareRow::value(std::string_view column) const {
  if (column == "wall_seconds") return wall_seconds;
  if (column == "final_position_error") return final_position_error;
  if (column == "final_attitude_error") return final_attitude_error;
  for (const auto& [key, v] : summary)
    if (key == column) return v;
  if (!ok) return NAN;  // a failed run has no summary
  throw Error("compare: no column " + std::string(column));
}

std::string format_compare(const CompareResult& r) {
  std::ostringstream out;
  char line[512];
  out << "reference: " << r.reference << ", " << r.reference_seconds << " s; ";
  if (!r.reference_error_note.empty())
    out << "its own error not estimated (" << r.reference_error_note << ")\n";
  else
    out << "estimated error " << r.reference_error << " (final-state difference to a 10x looser run)\n";
  // The family column as wide as its longest entry ("model mutual-series tolerance"), so that a
  // family never runs into its setting.
  int width = 14;
  for (const auto& row : r.rows) width = std::max(width, static_cast<int>(row.family.size()));
  // The printed table's columns: compare's own and the summary's, each headed as its row says.
  struct Printed {
    const char* key;
    const char* heading;  // null: the summary row's heading
    const char* format;
  };
  const Printed table[] = {{"wall_seconds", "wall [s]", " %10.4f"},         {"potential_evaluations", nullptr, " %10.0f"},
                           {"final_position_error", "pos err", " %10.2e"}, {"final_attitude_error", "att err", " %10.2e"},
                           {"max_abs_energy_error", nullptr, " %10.2e"},   {"max_rel_angular_momentum_error", nullptr, " %10.2e"},
                           {"max_orthogonality_error", nullptr, " %10.2e"}};
  std::snprintf(line, sizeof line, "%-*s  %-28s", width, "family", "setting");
  out << line;
  for (const Printed& c : table) {
    std::snprintf(line, sizeof line, " %10s",
                  c.heading ? c.heading : std::string(detail::summary_row(c.key).heading).c_str());
    out << line;
  }
  out << "\n";
  for (const auto& row : r.rows) {
    std::snprintf(line, sizeof line, "%-*s  %-28s", width, row.family.c_str(), row.label.c_str());
    out << line;
    if (!row.ok) {
      out << " failed: " << row.error << "\n";
      continue;
    }
    for (const Printed& c : table) {
      std::snprintf(line, sizeof line, c.format, row.value(c.key));
      out << line;
    }
    out << "\n";
  }
  return out.str();
}

void write_compare_csv(const CompareResult& r, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw OutputError("cannot write " + file.string());
  out << "family,setting,ok";
  const std::vector<std::string> columns = compare_columns();
  for (const auto& c : columns) out << ',' << c;
  out << ",error\n";
  out.precision(6);
  for (const auto& row : r.rows) {
    std::string err = row.error;
    std::replace(err.begin(), err.end(), '"', '\'');
    out << row.family << ',' << row.label << ',' << (row.ok ? 1 : 0);
    for (const auto& c : columns) out << ',' << row.value(c);
    out << ",\"" << err << "\"\n";
  }
}

void write_compare_h5(const CompareResult& r, const Scene& scene, const std::filesystem::path& file) {
  using namespace io;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5Handle f(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!f.valid()) throw OutputError("cannot create " + file.string() + system_reason());
  H5Handle g = make_group(f, "compare");
  string_attribute(g, "scene_file", scene.file);
  string_attribute(g, "scene", scene.text);
  string_attribute(g, "reference", r.reference);
  numeric_attribute<double>(g, "reference_error", H5T_NATIVE_DOUBLE, {r.reference_error});
  string_attribute(g, "unit_length", scene.units.of_length());
  string_attribute(g, "unit_energy", scene.units.of_energy());
  string_attribute(g, "unit_time", scene.units.of_time());
  std::vector<std::string> family, label, error;
  std::vector<double> ok;
  for (const auto& row : r.rows) {
    family.push_back(row.family);
    label.push_back(row.label);
    error.push_back(row.error);
    ok.push_back(row.ok ? 1 : 0);
  }
  string_list_dataset(g, "family", family);
  string_list_dataset(g, "setting", label);
  string_list_dataset(g, "error", error);
  double_dataset(g, "ok", ok);
  for (const std::string& c : compare_columns()) {
    std::vector<double> values;
    for (const auto& row : r.rows) values.push_back(row.value(c));
    double_dataset(g, c.c_str(), values);
  }
  g.reset();
  if (!f.close()) check(-1, "closing the compare file");
}

CompareSpec make_compare_spec(const Scene& scene, const std::vector<std::string>& runs,
                              const std::vector<std::string>& models, const std::string& reference_model,
                              const std::string& spec_file, int repeats, double max_wall_seconds) {
  CompareSpec spec = spec_file.empty() ? default_compare_spec(scene) : load_compare_spec(spec_file, scene);
  if (!runs.empty() || !models.empty()) {
    spec.runs.clear();
    for (std::size_t k = 0; k < runs.size(); ++k)
      for (auto& r : expand_runs(parse_params(runs[k], "--run " + std::to_string(k + 1)))) spec.runs.push_back(std::move(r));
    for (std::size_t k = 0; k < models.size(); ++k)
      for (auto& r : expand_model_runs(parse_params(models[k], "--model " + std::to_string(k + 1))))
        spec.runs.push_back(std::move(r));
  }
  if (models.empty() && !reference_model.empty())
    throw SceneError("--reference-model goes with --model: it is the potential the models are "
                     "measured against (integrator runs are measured against the scene's potential)");
  if (!models.empty()) {
    // Models are measured against a reference model under the scene's own integrator, so that
    // the integration error cancels and the difference is the models'.
    spec.reference = Params();
    spec.reference_check = Params();
    spec.reference_potential =
        parse_params(reference_model.empty() ? "{plugin: mutual-exact}" : reference_model, "--reference-model");
  }
  if (repeats > 0) spec.repeats = repeats;
  if (max_wall_seconds > 0) spec.max_wall_seconds = max_wall_seconds;
  return spec;
}

}  // namespace noether
