#include "ballagg/run/analyze_kinetics.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "ballagg/analysis/kinetics.hpp"
#include "ballagg/config/text_file.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/io/csv_reader.hpp"
#include "ballagg/io/directory_lock.hpp"
#include "ballagg/io/kinetics_files.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/run/run_directory.hpp"

namespace ballagg {
namespace {

int required_column(const CsvReader& csv, const char* name) {
  const int c = csv.column(name);
  if (c < 0) throw InputError(fmt::format("{}: no column {}", csv.source(), name));
  return c;
}

KineticSeries read_series(const std::string& path) {
  const std::string text = read_text_file(path, "time series", kMaxStateFileBytes);
  CsvReader csv(text, path, "time,clusters,...,kinetic_energy,...");
  const int time = required_column(csv, "time"), clusters = required_column(csv, "clusters"),
            energy = required_column(csv, "kinetic_energy");
  KineticSeries s;
  for (CsvRow row; csv.next(row);) {
    s.time.push_back(csv.number(row, time));
    s.clusters.push_back(csv.number(row, clusters));
    s.energy.push_back(csv.number(row, energy));
    if (s.time.size() > 1 && !(s.time.back() >= s.time[s.time.size() - 2]))
      throw InputError(fmt::format("{}:{}: time goes back", path, row.line));
  }
  return s;
}

// The collapse of every frame of frames_mass_spectrum.csv (rows grouped by time).
std::vector<CollapsePoint> read_collapse(const std::string& path) {
  std::vector<CollapsePoint> points;
  if (!std::filesystem::is_regular_file(path)) return points;
  const std::string text = read_text_file(path, "frames' mass spectra", kMaxStateFileBytes);
  CsvReader csv(text, path, "time,size,mass,clusters");
  const int time = required_column(csv, "time"), size = required_column(csv, "size"),
            mass = required_column(csv, "mass"), clusters = required_column(csv, "clusters");
  std::vector<MassSpectrumBin> frame;
  double at = std::nan("");
  auto flush = [&] {
    const std::vector<CollapsePoint> p = scaling_collapse(at, frame);
    points.insert(points.end(), p.begin(), p.end());
    frame.clear();
  };
  for (CsvRow row; csv.next(row);) {
    const double t = csv.number(row, time);
    if (t != at && !frame.empty()) flush();
    at = t;
    frame.push_back({static_cast<std::int32_t>(csv.integer(row, size)), csv.number(row, mass), csv.integer(row, clusters)});
  }
  if (!frame.empty()) flush();
  return points;
}

void check_window(std::optional<std::pair<double, double>> window) {
  if (!window) return;
  const auto [t0, t1] = *window;
  if (!(std::isfinite(t0) && std::isfinite(t1) && t0 > 0.0 && t1 > t0))
    throw InputError(fmt::format("analyze --window {},{}: must be two times 0 < T0 < T1", t0, t1));
}

}  // namespace

std::map<std::string, std::string> kinetics_of_run(const RunDirectory& run,
                                                   std::optional<std::pair<double, double>> window) {
  check_window(window);
  const std::string series_file = run.path("timeseries.csv");
  const Kinetics k = fit_kinetics(read_series(series_file), window);
  const std::vector<CollapsePoint> collapse = read_collapse(run.path("frames_mass_spectrum.csv"));
  return kinetics_files(k, run.config.system.dimension, series_file, collapse);
}

std::string analyze_kinetics(const AnalyzeKineticsRequest& r) {
  check_window(r.window);  // before the run directory: the argument's error first
  const RunDirectory run = open_run_directory(r.run_dir);
  const std::map<std::string, std::string> files = kinetics_of_run(run, r.window);
  const std::string out_dir = r.out_dir.empty() ? run.dir : r.out_dir;
  prepare_output_dir(out_dir);
  const DirectoryLock lock(out_dir);  // not while a run writes there
  for (const auto& [name, content] : files) write_file_atomically(out_dir, name, content);
  return out_dir;
}

}  // namespace ballagg
