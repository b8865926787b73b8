// A run's summary as `noether run` prints it: text, or one JSON object (--summary json), each
// written row by row from the summary's schema (run/summary_schema.hpp).
#include "io/json_text.hpp"
#include "run/summary_schema.hpp"

#include <noether/simulation.hpp>

#include <cstdio>

namespace noether {

std::string format_pair_models(const std::vector<PairModel>& models) {
  std::string out;
  char line[512];
  for (const auto& m : models) {
    const std::string pair = "pair " + m.body_a + "–" + m.body_b;
    std::snprintf(line, sizeof line, "%-31s %s, estimated error %.1e at separation %.6g (tolerance %.0e)\n",
                  pair.c_str(), m.model.c_str(), m.estimated_error, m.separation, m.tolerance);
    out += line;
    if (m.exceeded) {
      std::snprintf(line, sizeof line,
                    "%-31s EXCEEDED at t = %.6g: separation %.6g, estimated error %.1e > tolerance %.0e\n", "",
                    m.exceeded_time, m.exceeded_separation, m.exceeded_error, m.tolerance);
      out += line;
    }
  }
  return out;
}

std::string format_summary(const RunSummary& s) {
  std::string out;
  for (const detail::SummaryRow& row : detail::summary_rows()) {
    if (row.line)
      out += row.line(row, s);
    else if (!row.label.empty())  // a scalar on a line of its own
      out += detail::summary_line(row.label, detail::summary_value_text(row, s));
  }
  return out;
}

std::string format_summary_json(const RunSummary& s) {
  std::string out;
  for (const detail::SummaryRow& row : detail::summary_rows()) {
    if (row.uses & detail::kNotJson) continue;
    out += out.empty() ? "{\n  " : ",\n  ";
    out += detail::json_string(std::string(row.key)) + ": " + detail::summary_value_json(row, s);
  }
  return out + "\n}\n";
}

}  // namespace noether
