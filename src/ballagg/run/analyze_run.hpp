#pragma once
// The `ballagg analyze` command: a state file and the configuration that gives its box,
// to the analysis files (io/analysis_files.hpp).
#include <string>

namespace ballagg {

struct AnalyzeRequest {
  std::string run_dir;     // a finished run's directory (io/run_directory.hpp): its config.toml and final.csv
  std::string state_file;  // default: RUN_DIR/final.csv
  std::string config_file; // default: RUN_DIR/config.toml
  std::string out_dir;     // default: RUN_DIR, or the state file's directory
};

// Throws InputError (one line: the file and what is wrong) before writing anything.
// Returns the directory the files were written to.
std::string analyze_run(const AnalyzeRequest& request);

}  // namespace ballagg
