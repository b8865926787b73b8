// The run summary's schema (host/src/run/summary_schema.hpp): one row per quantity, and every
// writer of the summary driven by it — the JSON and text summaries, the checkpoint, the
// ensemble's columns, compare's columns — and docs/user-guide.md's reference table.
#include "test_support.hpp"

#include "run/summary_schema.hpp"

#include <noether/compare.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

using namespace noether;
using namespace noether::detail;

namespace {

// A run with rigid bodies, orbits the verdict judges and a closest approach: the dumbbells to t = 1.
RunSummary dumbbell_summary() {
  PluginRegistry registry = test::bundled_plugins();
  const Scene scene = test::dumbbell_scene({"run.t_end=1", "run.output_every=0.1"});
  return run_scene(scene, registry, {});
}

// The checkpointed rows' values as the checkpoint holds them, by key.
std::string as_text(const SavedSummary& saved) {
  std::ostringstream out;
  out.precision(17);
  for (const auto& [key, values] : saved.numbers) {
    out << key << ":";
    for (double v : values) out << " " << v;
    out << "\n";
  }
  for (const auto& [key, text] : saved.texts) out << key << ": " << text << "\n";
  return out.str();
}

}  // namespace

TEST(SummarySchema, EveryKeyOnceAndEveryRowWritable) {
  std::set<std::string_view> keys;
  for (const SummaryRow& row : summary_rows()) {
    EXPECT_TRUE(keys.insert(row.key).second) << row.key << " twice";
    EXPECT_FALSE(row.doc.empty()) << row.key << " has no doc line";
    switch (row.kind) {
      case Kind::number:
      case Kind::integer:
      case Kind::flag: EXPECT_TRUE(row.number) << row.key; break;
      case Kind::text: EXPECT_TRUE(row.text) << row.key; break;
      case Kind::structure: EXPECT_TRUE(row.json || (row.uses & kNotJson)) << row.key; break;
    }
    if (row.uses & kCheckpoint)
      EXPECT_TRUE((row.save && row.restore) || row.restore_number || row.restore_text) << row.key << " is not restorable";
    if (row.uses & (kEnsemble | kCompare)) EXPECT_TRUE(row.number) << row.key << " is a column without a number";
    if (!row.heading.empty()) EXPECT_TRUE(row.uses & kCompare) << row.key;
  }
  EXPECT_THROW(summary_row("min_distance"), std::out_of_range);
}

// The JSON summary holds exactly the rows' keys, each once, in the rows' order.
TEST(SummarySchema, TheJsonSummaryIsTheRows) {
  const std::string json = format_summary_json(dumbbell_summary());
  std::vector<std::string> written;
  const std::regex key("\n  \"([a-zA-Z0-9_]+)\": ");
  for (auto it = std::sregex_iterator(json.begin(), json.end(), key); it != std::sregex_iterator(); ++it)
    written.push_back((*it)[1]);
  std::vector<std::string> expected;
  for (const SummaryRow& row : summary_rows())
    if (!(row.uses & kNotJson)) expected.emplace_back(row.key);
  EXPECT_EQ(written, expected);
  EXPECT_NE(json.find("\"closest_approach\": 0."), std::string::npos) << json;  // the dumbbells approach
}

// What Simulation::save writes restores every checkpointed row: saved again, the same values
// bit for bit (Simulation.SaveAndLoadContinueBitwise continues runs through it).
TEST(SummarySchema, CheckpointRowsRoundTrip) {
  const RunSummary summary = dumbbell_summary();
  const SavedSummary saved = save_summary(summary);
  for (const SummaryRow* row : summary_rows_for(kCheckpoint))
    if (!row->save)
      EXPECT_TRUE(saved.number(row->key) || saved.text(row->key)) << row->key << " not saved";
  RunSummary restored;
  restore_summary(restored, saved);
  EXPECT_EQ(as_text(save_summary(restored)), as_text(saved));
  EXPECT_EQ(restored.initial.energy, summary.initial.energy);
  EXPECT_EQ(restored.min_distance_pair, summary.min_distance_pair);
  ASSERT_EQ(restored.orbits.size(), summary.orbits.size());
  for (std::size_t k = 0; k < summary.orbits.size(); ++k) {
    EXPECT_EQ(restored.orbits[k].body, summary.orbits[k].body);
    EXPECT_EQ(restored.orbits[k].energy_scale, summary.orbits[k].energy_scale);
  }
  SavedSummary lacking = saved;
  lacking.numbers.erase(lacking.numbers.begin());
  try {
    restore_summary(restored, lacking);
    ADD_FAILURE() << "a checkpoint without " << saved.numbers.front().first << " was restored";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(saved.numbers.front().first), std::string::npos) << e.what();
  }
}

// A checkpoint saved before the schema held its numbers by position ("statistics", "initial",
// "final"; written here as that noether wrote them): read, its values land on the same rows.
TEST(SummarySchema, ACheckpointFromBeforeTheSchemaIsRead) {
  const RunSummary s = dumbbell_summary();
  auto pack = [](const Diagnostics& d) {
    return std::vector<double>{d.kinetic_translational, d.kinetic_rotational, d.potential, d.energy,
                               d.linear_momentum.x(),   d.linear_momentum.y(),  d.linear_momentum.z(),
                               d.angular_momentum.x(),  d.angular_momentum.y(), d.angular_momentum.z(),
                               d.orthogonality_error};
  };
  SavedSummary old;
  old.numbers = {{"initial", pack(s.initial)},
                 {"final", pack(s.final)},
                 {"statistics",
                  {s.max_abs_energy_error, s.max_rel_linear_momentum_error, s.max_rel_angular_momentum_error,
                   s.max_orthogonality_error, s.conserves_linear_momentum ? 1.0 : 0.0,
                   s.conserves_angular_momentum ? 1.0 : 0.0, s.min_gap, s.min_gap_reach, s.min_distance,
                   s.t_of_min_distance, 0.25, 0.5}},
                 {"frames", {static_cast<double>(s.frames)}},
                 {"orbit_scales", {s.orbits.empty() ? 0.0 : s.orbits[0].energy_scale}},
                 {"exchanged_momenta", {1.5, 2.5}}};
  std::string orbits;
  for (const auto& o : s.orbits) orbits += o.body + "\t" + o.about + "\n";
  old.texts = {{"min_gap_pair", s.min_gap_pair}, {"stop_reason", s.stop_reason},
               {"min_distance_pair", s.min_distance_pair}, {"orbits", orbits}};
  ASSERT_LE(s.orbits.size(), 1u);
  const SavedSummary upgraded = upgrade_saved_summary(old);
  RunSummary restored;
  restore_summary(restored, upgraded);
  EXPECT_EQ(as_text(save_summary(restored)), as_text(save_summary(s)));
  EXPECT_EQ((*upgraded.number("angular_momentum_scale"))[0], 0.5);
  EXPECT_EQ((*upgraded.number("exchanged_angular_momentum"))[0], 2.5);
  // A checkpoint of today's layout passes unchanged.
  EXPECT_EQ(as_text(upgrade_saved_summary(save_summary(s))), as_text(save_summary(s)));
}

// docs/user-guide.md's "Summary reference" is the schema's table, and docs/ensembles.md names
// the ensemble's columns.
TEST(SummarySchema, DocumentedInUserGuide) {
  const std::string guide = test::source_text("docs/user-guide.md");
  const std::string begin = "<!-- summary reference: generated from host/src/run/summary_schema.cpp -->\n",
                    end = "<!-- end of the summary reference -->";
  const std::size_t from = guide.find(begin), to = guide.find(end);
  ASSERT_NE(from, std::string::npos) << "docs/user-guide.md lacks the line " << begin;
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(guide.substr(from + begin.size(), to - from - begin.size()), summary_reference_markdown())
      << "docs/user-guide.md's summary reference differs from the schema; the table should read:\n"
      << summary_reference_markdown();
  const std::string ensembles = test::source_text("docs/ensembles.md");
  const std::size_t row = ensembles.find("| `/summary/*` |");
  ASSERT_NE(row, std::string::npos);
  const std::string line = ensembles.substr(row, ensembles.find('\n', row) - row);
  for (const SummaryRow* column : summary_rows_for(kEnsemble))
    EXPECT_TRUE(std::regex_search(line, std::regex("[ ,]" + std::string(column->key) + "[ ,]"))) << column->key << " in " << line;
}

// Compare's columns are its own three and the schema's compare rows, in order.
TEST(SummarySchema, CompareColumnsAreTheRows) {
  std::vector<std::string> expected{"wall_seconds", "final_position_error", "final_attitude_error"};
  for (const SummaryRow* row : summary_rows_for(kCompare)) expected.emplace_back(row->key);
  EXPECT_EQ(compare_columns(), expected);
  CompareRow row;
  row.ok = true;
  row.summary = {{"steps", 12.0}};
  EXPECT_EQ(row.value("steps"), 12.0);
  EXPECT_THROW(row.value("max_distance"), Error);
}
