#pragma once
// The `ballagg analyze` command: a state file and the configuration that gives its box,
// to the analysis files (io/analysis_files.hpp).
#include <string>

#include "ballagg/core/box.hpp"
#include "ballagg/io/state_csv.hpp"

namespace ballagg {

struct AnalyzeRequest {
  std::string run_dir;     // a finished run's directory (run/run_directory.hpp): its config.toml and final.csv
  std::string state_file;  // default: RUN_DIR/final.csv
  std::string config_file; // default: RUN_DIR/config.toml
  std::string out_dir;     // default: RUN_DIR, or the state file's directory
};

// Throws InputError (one line: the file and what is wrong) before writing anything.
// Returns the directory the files were written to.
std::string analyze_run(const AnalyzeRequest& request);

// The analysis files of the spheres of one state (read from `state_file`, which
// analysis.json records) written into the existing directory `out_dir`, analysis.json
// last. `ballagg analyze` and the end of a rigid-body run share it, so both give the same
// files.
template <int D>
void write_analysis(const Box<D>& box, const SphereTable<D>& spheres, const std::string& state_file,
                    const std::string& out_dir);

extern template void write_analysis<2>(const Box<2>&, const SphereTable<2>&, const std::string&, const std::string&);
extern template void write_analysis<3>(const Box<3>&, const SphereTable<3>&, const std::string&, const std::string&);

}  // namespace ballagg
