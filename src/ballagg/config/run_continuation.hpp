#pragma once
// A finished run's directory as the initial state (initial.file = "RUN_DIR"): the new run
// continues from the directory's final.csv, in the run's box and on its clock, as if the
// run had not stopped; only the configuration's other keys (the stop criteria above all)
// are the new run's. docs/configuration.md ("Continuing a finished run") states the rule.
#include <string>

#include "ballagg/config/config.hpp"
#include "ballagg/config/section_reader.hpp"

namespace ballagg {

// What the summary.json of a finished run records about where it ended.
struct RunEnd {
  int dimension = 2;
  double box_length = 0.0;
  Boundary boundary = Boundary::walls;
  double time = 0.0;
};

// Reads DIR/summary.json. Throws InputError naming the directory or the file when it is
// missing (the directory holds no finished run) or lacks a value.
RunEnd read_run_end(const std::string& dir);

// When c.initial.positions = "file" and c.initial.file names a directory: takes
// system.dimension, system.box_length, system.boundary and initial.time from that run
// and points initial.file at its final.csv. A box key or initial.time given with another
// value than the run's is refused (InputError naming where it was given), as is a
// system.volume_fraction whose box is not the run's; a volume fraction that gives the
// run's box is replaced by that box_length.
void continue_from_run_directory(Config& c, SectionReader& system, SectionReader& initial);

}  // namespace ballagg
