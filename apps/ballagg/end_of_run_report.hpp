#pragma once
// What `run` and `analyze` print when they finish (unless --quiet), read from the files they
// have just written (summary.json, analysis.json), so that a resumed run and a fresh one
// report alike and the terminal never says what the files do not.
#include <string>

#include <nlohmann/json.hpp>

namespace ballagg::cli {

// Two lines, like LAMMPS's "Loop time": the engine, the stop and its reason, events or
// steps, engine time and rate; then the clusters, the kinetic energy against its start and
// the largest overlap.
std::string run_report(const nlohmann::json& summary);

// run_report of DIR/summary.json, or nothing when it cannot be read (the run's files are
// written; the report is only a convenience).
std::string run_report_of(const std::string& run_dir);

// The headline indicators of an analysis: D_f by box counting with its error, N_c, and the
// largest cluster's size, aspect ratio and mass-radius f_D (or why it is withheld).
std::string analysis_headline(const nlohmann::json& analysis);
std::string analysis_headline_of(const std::string& analysis_dir);

// The kinetic exponents of DIR/kinetics.json with their window (`analyze --kinetics`).
std::string kinetics_headline_of(const std::string& dir);

}  // namespace ballagg::cli
