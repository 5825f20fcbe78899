#include "ballagg/config/run_continuation.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/text_file.hpp"
#include "ballagg/config/value_ranges.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

// summary.json's value of `key`, a number accepted by `ok` (an InputError otherwise).
double summary_number(const nlohmann::json& summary, const std::string& path, const char* key, bool (*ok)(double),
                      const char* allowed) {
  const auto it = summary.find(key);
  if (it == summary.end() || !it->is_number() || !ok(it->get<double>()))
    throw InputError(fmt::format("{}: not the summary of a finished ballagg run (\"{}\" {}: {})", path, key,
                                 it == summary.end() ? "is missing" : "= " + it->dump(), allowed));
  return it->get<double>();
}

// The directory itself: a finished run has its summary.json and its final.csv.
void check_finished_run(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::path(dir) / "summary.json", ec))
    throw InputError(fmt::format("{}: cannot read the state file: it is a directory that holds no finished run (no "
                                 "summary.json; initial.file names a state file or the --out directory of a finished "
                                 "ballagg run, and an interrupted run is finished with ballagg run --resume)", dir));
  if (!fs::is_regular_file(fs::path(dir) / "final.csv", ec))
    throw InputError(fmt::format("{}: cannot read the state file: the run in this directory has a summary.json but no "
                                 "final.csv, the state a run continuing it starts from", dir));
}

}  // namespace

RunEnd read_run_end(const std::string& dir) {
  check_finished_run(dir);
  const std::string path = (fs::path(dir) / "summary.json").string();
  const nlohmann::json summary = nlohmann::json::parse(read_text_file(path, "run summary", kMaxSettingsFileBytes),
                                                       nullptr, false);
  if (summary.is_discarded() || !summary.is_object())
    throw InputError(fmt::format("{}: not the summary of a finished ballagg run (not a JSON object)", path));
  RunEnd end;
  end.dimension = static_cast<int>(summary_number(summary, path, "dimension", [](double d) { return d == 2 || d == 3; },
                                                  "must be 2 or 3"));
  end.box_length = summary_number(summary, path, "box_length",
                                  [](double l) { return l > 0.0 && l <= range::kMaxBoxLength; },
                                  "must be a length > 0 within system.box_length's range");
  end.time = summary_number(summary, path, "time", [](double t) { return std::isfinite(t) && t >= 0.0; },
                            "must be a finite time >= 0");
  const auto boundary = summary.find("boundary");
  if (boundary == summary.end() || !boundary->is_string() ||
      (*boundary != "walls" && *boundary != "periodic"))
    throw InputError(fmt::format("{}: not the summary of a finished ballagg run (\"boundary\" must be \"walls\" or "
                                 "\"periodic\")", path));
  end.boundary = *boundary == "walls" ? Boundary::walls : Boundary::periodic;
  return end;
}

namespace {

// The box of the run: keys given with other values are refused, the others take the run's.
void take_box(Config& c, SectionReader& system, const RunEnd& end, const std::string& run) {
  if (system.has("dimension") && c.system.dimension != end.dimension)
    system.refuse("dimension", fmt::format("{} is {}D: leave system.dimension out or give {}", run, end.dimension,
                                           end.dimension));
  c.system.dimension = end.dimension;
  if (system.has("boundary") && c.system.boundary != end.boundary)
    system.refuse("boundary", fmt::format("{} has boundary = \"{}\": leave system.boundary out or give that", run,
                                          to_string(end.boundary)));
  c.system.boundary = end.boundary;
  if (c.system.box_length && *c.system.box_length != end.box_length)
    system.refuse("box_length", fmt::format("{} has box_length = {}: leave system.box_length out or give that", run,
                                            end.box_length));
  if (c.system.volume_fraction && !c.system.box_length) {
    // The run's own configuration gives its box again (the same n, radius and fraction).
    if (resolved_box_length(c) != end.box_length)
      system.refuse("volume_fraction",
                    fmt::format("with system.n = {} and system.radius = {} it gives a box of length {}, but {} has "
                                "box_length = {}: leave system.volume_fraction out", c.system.n, c.system.radius,
                                resolved_box_length(c), run, end.box_length));
    c.system.volume_fraction.reset();
  }
  // Both given: left for the rule "not both" (config.cpp) to refuse.
  if (!c.system.volume_fraction) c.system.box_length = end.box_length;
}

}  // namespace

void continue_from_run_directory(Config& c, SectionReader& system, SectionReader& initial) {
  std::error_code ec;
  if (c.initial.positions != InitialPositions::file || !fs::is_directory(c.initial.file, ec)) return;
  const std::string dir = c.initial.file;
  const RunEnd end = read_run_end(dir);
  const std::string run = fmt::format("the run in {}, which initial.file continues,", dir);
  take_box(c, system, end, run);
  if (initial.has("time") && c.initial.time != end.time)
    initial.refuse("time", fmt::format("{} ended at t = {}, where a run continuing it starts: leave initial.time out "
                                       "or give that", run, end.time));
  c.initial.time = end.time;
  c.initial.file = (fs::path(dir) / "final.csv").string();
}

}  // namespace ballagg
