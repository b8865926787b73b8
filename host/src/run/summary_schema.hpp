#pragma once
// The run summary's schema: one row per quantity a run reports — its key (the one spelling of
// its name in the JSON summary, the Python dict, the checkpoint, the ensemble file and compare's
// columns), its label in the text summary, its dimension, where its value lives in RunSummary,
// and where else it goes. format_summary, format_summary_json, Simulation::save/load, the
// ensemble's /summary columns and compare's columns are written from these rows; none of them
// names a quantity or reads one by position. docs/user-guide.md "Summary reference" is the
// table printed by summary_reference_markdown() (test SummarySchema.DocumentedInUserGuide).
#include <noether/simulation.hpp>

#include "io/frame_schema.hpp"

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace noether::detail {

// A row's value is measured in the scene's unit of its dimension (io::Dimension, io::unit_of:
// the frame schema's, so a quantity has the same unit in the output series and the summary).
using io::Dimension;

// How a row's value is written: a double, a whole number, true/false, a string, or a structure
// of its own (JSON written by the row's json function).
enum class Kind { number, integer, flag, text, structure };

// Where a row goes besides the JSON and text summaries (bits of SummaryRow::uses).
enum SummaryUse : unsigned {
  kNotJson = 1u << 0,     // kept in the checkpoint only (the summary's running values)
  kCheckpoint = 1u << 1,  // /checkpoint/summary of a saved simulation, restored by load
  kEnsemble = 1u << 2,    // a /summary/<key> column of an ensemble file, one value per sample
  kCompare = 1u << 3,     // a column of `noether compare`'s CSV, HDF5 file and Python table
};

// A checkpoint's named values (/checkpoint/summary's attributes): numbers and texts by key.
struct SavedSummary {
  std::vector<std::pair<std::string, std::vector<double>>> numbers;
  std::vector<std::pair<std::string, std::string>> texts;
  const std::vector<double>* number(std::string_view key) const;  // null: absent
  const std::string* text(std::string_view key) const;            // null: absent
  // The numbers of `key`, `size` of them; throws Error naming the key otherwise.
  const std::vector<double>& require(std::string_view key, std::size_t size) const;
};

struct SummaryRow {
  std::string_view key{};
  Kind kind = Kind::number;
  Dimension dimension = Dimension::kOne;
  unsigned uses = 0;
  std::string_view label{};  // the text summary's line starts with it ("": the value is on another row's line)
  std::string_view heading{};  // compare's printed table heads its column with it ("": not in that table)
  std::string_view doc{};    // one line for docs/user-guide.md "Summary reference"
  // The value, for kinds number, integer and flag (flag: 0 or 1); kind text: text.
  double (*number)(const RunSummary&) = nullptr;
  std::string (*text)(const RunSummary&) = nullptr;
  // Whether the run has it; false: null in JSON. Null: always.
  bool (*has)(const RunSummary&) = nullptr;
  // The JSON value of a structure.
  std::string (*json)(const RunSummary&) = nullptr;
  // The text summary's line(s) for this row, "" for none; null: "label  value unit".
  std::string (*line)(const SummaryRow&, const RunSummary&) = nullptr;
  // Checkpointed rows: the value back into the summary (scalars), or — a structure — saved and
  // restored as named values of its own.
  void (*restore_number)(RunSummary&, double) = nullptr;
  void (*restore_text)(RunSummary&, const std::string&) = nullptr;
  void (*save)(const RunSummary&, SavedSummary&) = nullptr;
  void (*restore)(RunSummary&, const SavedSummary&) = nullptr;
};

// Every row, in the order the text summary prints them.
std::span<const SummaryRow> summary_rows();
// The row of a key; throws std::out_of_range naming the key when there is none.
const SummaryRow& summary_row(std::string_view key);
// The rows with a use (kEnsemble, kCompare, kCheckpoint), in order.
std::vector<const SummaryRow*> summary_rows_for(SummaryUse use);

// A scalar row's value as the text summary prints it, and as JSON (null where the run lacks it).
std::string summary_value_text(const SummaryRow& row, const RunSummary& summary);
std::string summary_value_json(const SummaryRow& row, const RunSummary& summary);

// A row's text line padded as the summary prints it: the label in 30 columns, then the text.
std::string summary_line(std::string_view label, const std::string& text);
// " kg m^2/s^2" after a number in the scene's declared `unit` ("" when it declares none); the
// unit of time after a time, likewise (RunSummary::time_unit is set even without units).
std::string summary_unit(const std::string& unit);
std::string summary_time_unit(const RunSummary& summary);
// " = 11.9326 h" after a time `t` in seconds ("" in other units: `unit` is the scene's time unit).
std::string summary_hours(double t, const std::string& unit);

// The checkpointed rows' values (Simulation::save), and the summary restored from them
// (Simulation::load): throws Error naming the first key a checkpoint lacks.
SavedSummary save_summary(const RunSummary& summary);
void restore_summary(RunSummary& summary, const SavedSummary& saved);

// A checkpoint written before the schema (its numbers by position in "statistics", "initial",
// "final"; before 2026-11-28) with its values renamed to the rows' keys; others unchanged.
SavedSummary upgrade_saved_summary(SavedSummary saved);

// The "Summary reference" table of docs/user-guide.md: key, text line, unit, where it goes, doc.
std::string summary_reference_markdown();

}  // namespace noether::detail
