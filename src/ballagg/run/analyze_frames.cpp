#include "ballagg/run/analyze_frames.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/io/directory_lock.hpp"
#include "ballagg/io/frame_analysis_tables.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/run/run_directory.hpp"

namespace ballagg {
namespace {

// A frame as the analysis reads a state file: centres folded into the box, the run's
// cluster ids, the constant radii and masses.
template <int D>
SphereTable<D> spheres_of(const Frame<D>& frame, const Particles<D>& particles) {
  SphereTable<D> t;
  t.position = frame.position;
  t.velocity = frame.velocity;
  t.radius = particles.radius;
  t.mass = particles.mass;
  t.cluster.assign(frame.cluster.begin(), frame.cluster.end());
  return t;
}

template <int D>
FrameAnalysisTables analyze_trajectory(const std::string& trajectory, const std::vector<double>& wanted) {
  const H5mdReader<D> reader(trajectory);
  std::vector<int> chosen;
  if (wanted.empty()) {
    for (int k = 0; k < reader.frames(); ++k) chosen.push_back(k);
  } else {
    chosen = frames_nearest(reader.times(), wanted);
  }
  FrameAnalysisTables tables;
  for (int k : chosen) {
    const Frame<D> frame = reader.frame(k);
    tables.add(frame.time, frame.step, analyze_aggregates(reader.particles().box, spheres_of(frame, reader.particles())));
  }
  return tables;
}

}  // namespace

std::vector<int> frames_nearest(const std::vector<double>& times, const std::vector<double>& wanted) {
  std::vector<int> chosen;
  if (times.empty()) return chosen;  // no frame is nearest to anything (and end() - 1 would not exist)
  for (double t : wanted) {
    const auto after = std::lower_bound(times.begin(), times.end(), t);
    auto best = after;
    if (after == times.end() || (after != times.begin() && t - *(after - 1) <= *after - t)) best = after - 1;
    chosen.push_back(static_cast<int>(best - times.begin()));
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

std::string analyze_frames(const AnalyzeFramesRequest& r, int& frames) {
  for (double t : r.times)
    if (!std::isfinite(t)) throw InputError(fmt::format("analyze --times: {} is not a finite time", t));
  const RunDirectory run = open_run_directory(r.run_dir);
  const std::string trajectory = run.path("trajectory.h5md");
  if (!std::filesystem::is_regular_file(trajectory))
    throw InputError(fmt::format("analyze --frames: {} not found (a run writes it with output.snapshot_every > 0 "
                                 "and \"h5md\" in output.snapshot_formats)",
                                 trajectory));
  const FrameAnalysisTables tables = run.config.system.dimension == 2 ? analyze_trajectory<2>(trajectory, r.times)
                                                                      : analyze_trajectory<3>(trajectory, r.times);
  const std::string out_dir = r.out_dir.empty() ? run.dir : r.out_dir;
  prepare_output_dir(out_dir);
  const DirectoryLock lock(out_dir);  // not while a run writes there
  for (const auto& [name, content] : tables.files()) write_file_atomically(out_dir, name, content);
  frames = tables.frames();
  return out_dir;
}

}  // namespace ballagg
