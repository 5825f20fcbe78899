#include "ballagg/run/run_files.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/output_dir.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

constexpr std::array<std::string_view, 17> kRunFiles = {
    // ballagg run
    "config.toml", "summary.json", "final.csv", "final.xyz", "timeseries.csv", "trajectory.h5md", "trajectory.xyz",
    "trajectory.gsd", kCheckpointFile,
    // ballagg analyze (analysis_files.hpp), also written at the end of a rigid-body run
    "analysis.json", "clusters.csv", "mass_spectrum.csv", "box_counting.csv", "pair_distribution.csv",
    "mass_radius.csv",
    // a failed run of a sweep
    "error.txt",
    // ballagg render without an output file: final.png (frame-K.png below)
    "final.png"};

// How many names a refusal lists at most (the count is always given).
constexpr std::size_t kNamesShown = 3;

bool is_frame_picture(std::string_view name) {
  constexpr std::string_view prefix = "frame-", suffix = ".png";
  if (name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) || !name.ends_with(suffix)) return false;
  const std::string_view k = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return std::all_of(k.begin(), k.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool is_final_name(std::string_view name) {
  return std::find(kRunFiles.begin(), kRunFiles.end(), name) != kRunFiles.end() || is_frame_picture(name);
}

// The run files in `dir`, sorted by name.
std::vector<std::string> run_files_in(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (is_run_file(e.path().filename().string())) names.push_back(e.path().filename().string());
  if (ec) throw InputError(fmt::format("--out {}: cannot list the directory: {}", dir, ec.message()));
  std::sort(names.begin(), names.end());
  return names;
}

std::string some_of(const std::vector<std::string>& names) {
  std::string list;
  for (std::size_t k = 0; k < std::min(names.size(), kNamesShown); ++k) list += (k ? ", " : "") + names[k];
  if (names.size() > kNamesShown) list += fmt::format(" and {} more", names.size() - kNamesShown);
  return list;
}

// Refuses `dir` if it holds a sweep or (without overwrite) another run; with overwrite
// removes the other run's files.
void clear_run_directory(const std::string& dir, bool overwrite) {
  std::error_code ec;
  if (fs::exists(fs::path(dir) / "sweep.toml", ec))
    throw InputError(fmt::format("--out {}: holds a sweep (sweep.toml); give a directory of its own to a run", dir));
  const std::vector<std::string> names = run_files_in(dir);
  if (names.empty()) return;
  if (!overwrite)
    throw InputError(fmt::format("--out {}: holds another run ({}); add --overwrite to replace it, or choose another "
                                 "--out (--resume DIR continues an interrupted run)", dir, some_of(names)));
  for (const std::string& name : names) {
    const fs::path path = fs::path(dir) / name;
    if (!fs::is_regular_file(fs::symlink_status(path, ec)))
      throw InputError(fmt::format("--out {}: {} is not a regular file (--overwrite removes only files ballagg wrote)",
                                   dir, path.string()));
  }
  for (const std::string& name : names)
    if (!fs::remove(fs::path(dir) / name, ec) && ec)
      throw InputError(fmt::format("--out {}: cannot remove {} of the run it held: {}", dir, name, ec.message()));
}

}  // namespace

bool is_run_file(std::string_view name) {
  constexpr std::string_view dot = ".", tmp = ".tmp";
  if (name.size() > dot.size() + tmp.size() && name.starts_with(dot) && name.ends_with(tmp))
    return is_final_name(name.substr(dot.size(), name.size() - dot.size() - tmp.size()));
  return is_final_name(name);
}

void remove_run_files(const std::string& dir) {
  std::error_code ec;
  std::vector<fs::path> paths;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (is_run_file(e.path().filename().string())) paths.push_back(e.path());
  for (const fs::path& path : paths) fs::remove(path, ec);
}

NewRunDirectory open_new_run_directory(const std::string& dir, bool overwrite) {
  const bool created = prepare_output_dir(dir);
  try {
    NewRunDirectory run{DirectoryLock(dir), created};
    clear_run_directory(dir, overwrite);
    return run;
  } catch (...) {
    std::error_code ec;
    if (created) fs::remove(dir, ec);  // empty again: the lock has gone with the exception
    throw;
  }
}

}  // namespace ballagg
