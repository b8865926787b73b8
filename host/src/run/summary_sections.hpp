#pragma once
// The run summary's structured rows (run/summary_schema.cpp): each one's JSON value and its text
// lines — forces, particles, the period changes, spin states, chaos indicators, the judged orbits and their
// step-halving check, the pair models, the verdict.
#include "run/summary_schema.hpp"

#include <string>

namespace noether::detail {

std::string forces_json(const RunSummary& s);
std::string forces_lines(const SummaryRow& row, const RunSummary& s);
std::string particles_json(const RunSummary& s);
std::string particles_lines(const SummaryRow& row, const RunSummary& s);
std::string closest_approaches_json(const RunSummary& s);
std::string closest_approaches_lines(const SummaryRow& row, const RunSummary& s);
std::string orbit_periods_json(const RunSummary& s);
std::string orbit_periods_lines(const SummaryRow& row, const RunSummary& s);
std::string period_changes_json(const RunSummary& s);
std::string period_changes_lines(const SummaryRow& row, const RunSummary& s);
std::string spin_states_json(const RunSummary& s);
std::string spin_states_lines(const SummaryRow& row, const RunSummary& s);
std::string chaos_json(const RunSummary& s);
std::string chaos_lines(const SummaryRow& row, const RunSummary& s);
std::string orbits_json(const RunSummary& s);
std::string orbits_lines(const SummaryRow& row, const RunSummary& s);
std::string resolution_json(const RunSummary& s);
std::string resolution_lines(const SummaryRow& row, const RunSummary& s);
std::string pair_models_json(const RunSummary& s);
std::string warnings_json(const RunSummary& s);
std::string warnings_lines(const SummaryRow& row, const RunSummary& s);
std::string verdict_json(const RunSummary& s);
std::string verdict_lines(const SummaryRow& row, const RunSummary& s);

}  // namespace noether::detail
