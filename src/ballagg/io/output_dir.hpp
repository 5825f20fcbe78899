#pragma once
// The run directory. Files are written to a temporary name and renamed into place, so a
// reader (or a crash) never sees a half-written file.
#include <string>

namespace ballagg {

// A fresh default directory name under `parent`: parent/YYYYmmdd-HHMMSS (with -2, -3, ...
// appended if that exists).
std::string default_output_dir(const std::string& parent = "out");

// Creates `dir` (and parents) if needed and checks that files can be created in it.
// Throws InputError naming the directory and the reason. Returns true if it was created.
bool prepare_output_dir(const std::string& dir);

// Where a file is written before it is renamed to `path`: .NAME.tmp in the same directory.
std::string temporary_path_for(const std::string& path);

// Renames the complete file `temporary` to `path` (for files written by a library: HDF5,
// cairo). On failure removes `temporary` and throws OutputError naming `path`.
void rename_into_place(const std::string& temporary, const std::string& path);

// Gives a checkpointed run back the temporary file of `path` if the run completed `path`
// (renamed it into place) and was killed before it finished (wrote summary.json and
// removed its checkpoint): the completed file holds every record the checkpoint saw and
// later ones, so the resumed run can cut it back and continue it as if it had been killed
// a moment earlier. Does nothing if the temporary file exists or `path` does not; a
// failed rename leaves the temporary missing, which the caller reports.
void reclaim_completed_file(const std::string& path);

// Writes `content` to dir/name atomically (AtomicFile). Throws OutputError on failure.
void write_file_atomically(const std::string& dir, const std::string& name, const std::string& content);

}  // namespace ballagg
