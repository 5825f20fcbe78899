#pragma once
// The files ballagg writes in a run directory, and the rule for the directory of a new
// run (docs/outputs.md, "Run directories"): a run never mixes its files with another
// run's. A directory holding another run's files is refused unless the user asks for it
// to be replaced (--overwrite), which removes those files and only those; and the
// directory is locked while the run writes it.
#include <string>
#include <string_view>

#include "ballagg/io/directory_lock.hpp"

namespace ballagg {

// Whether `name` (a file name, no directory) is one ballagg writes in a run directory:
// those of `run` (config.toml, summary.json, final.csv, final.xyz, timeseries.csv,
// trajectory.h5md, trajectory.xyz, trajectory.gsd, checkpoint.bin), of `analyze` (analysis.json and its
// tables), `render`'s default pictures (final.png, frame-K.png), a sweep run's error.txt,
// and the temporary file .NAME.tmp of any of them.
bool is_run_file(std::string_view name);

// Removes every run file (is_run_file) in `dir`, quietly: what a new run that failed had
// written (run_simulation), never another run's (a new run's directory holds none at its
// start).
void remove_run_files(const std::string& dir);

// A directory ready for a new run and locked for it.
struct NewRunDirectory {
  DirectoryLock lock;
  bool created = false;  // the directory did not exist before
};

// Creates `dir` if needed (prepare_output_dir), locks it (DirectoryLock) and clears it of
// another run's files: without `overwrite` a directory holding any is refused, with it
// they are removed (other files stay; a run file that is not a regular file is refused,
// not removed). A directory holding a sweep (sweep.toml) is refused either way. Throws
// InputError naming the directory, leaving nothing it created.
NewRunDirectory open_new_run_directory(const std::string& dir, bool overwrite);

}  // namespace ballagg
