#pragma once
// The run directory. Files are written to a temporary name and renamed into place, so a
// reader (or a crash) never sees a half-written file.
#include <cstdint>
#include <functional>
#include <string>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {

// A fresh default directory name under `parent`: parent/YYYYmmdd-HHMMSS (with -2, -3, ...
// appended if that exists).
std::string default_output_dir(const std::string& parent = "out");

// Creates `dir` (and parents) if needed and checks that files can be created in it.
// Throws InputError naming the directory and the reason. Returns true if it was created.
bool prepare_output_dir(const std::string& dir);

// Where a file is written before it is renamed to `path`: .NAME.tmp in the same directory.
std::string temporary_path_for(const std::string& path);

// The rule for every output file (docs/outputs.md, "Output files"): it is written where
// nothing is, or over a regular file, which it replaces. Anything else at `path` is
// refused, since renaming over it would replace the node itself: a directory, a device, a
// FIFO, a socket, and a symbolic link whatever it points to (links are not written
// through; give the path of the file itself). Throws OutputError "PATH: cannot write: it
// is ...".
void check_output_path(const std::string& path);

// temporary_path_for(path), ready to be created: `path` checked (check_output_path) and a
// stale temporary that is not a regular file (a link or a FIFO left in its place) removed,
// so that what creates it (AtomicFile, HDF5, cairo, ffmpeg) makes a new regular file
// rather than writing through it. Throws OutputError.
std::string fresh_temporary_for(const std::string& path);

// Renames the complete file `temporary` to `path` (for files written by a library: HDF5,
// cairo), after check_output_path(path). On failure removes `temporary` and throws
// OutputError naming `path`.
void rename_into_place(const std::string& temporary, const std::string& path);

// Gives a checkpointed run back the temporary file of `path` if the run completed `path`
// (renamed it into place) and was killed before it finished (wrote summary.json and
// removed its checkpoint): the completed file holds every record the checkpoint saw and
// later ones, so the resumed run can cut it back and continue it as if it had been killed
// a moment earlier. Does nothing if the temporary file exists or `path` does not; a
// failed rename leaves the temporary missing, which the caller reports.
void reclaim_completed_file(const std::string& path);

// The temporary file of a checkpointed run's trajectory `path` (taken back from `path` if
// the run was killed after completing it: reclaim_completed_file), checked to be a regular
// file of at least `bytes` bytes, what the checkpoint saw. Returns `bytes`. Throws
// InputError.
std::uint64_t checked_temporary_size(const std::string& path, std::uint64_t bytes);

// Writes `content` to dir/name atomically (AtomicFile). Throws OutputError on failure.
void write_file_atomically(const std::string& dir, const std::string& name, const std::string& content);
// The same with the bytes `produce` hands its sink, written as they come (a file of any
// length through a bounded buffer).
void write_file_atomically(const std::string& dir, const std::string& name,
                           const std::function<void(ByteSink&)>& produce);

}  // namespace ballagg
