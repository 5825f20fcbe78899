#include "ballagg/run/snapshots.hpp"

#include <cmath>
#include <filesystem>

#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"

namespace ballagg {

template <int D>
SnapshotRecorder<D>::SnapshotRecorder(double every, std::vector<std::unique_ptr<FrameSink<D>>> sinks,
                                      bool mirror_at_walls)
    : every_(every), writer_(std::move(sinks)), mirror_at_walls_(mirror_at_walls) {}

template <int D>
void SnapshotRecorder<D>::take(const State<D>& s, double t) {
  capture_source(s, t, events_, mirror_at_walls_, writer_.acquire());
  writer_.submit();
  ++frames_;
  last_time_ = t;
  last_events_ = events_;
}

template <int D>
void SnapshotRecorder<D>::on_start(const State<D>& s) {
  next_k_ = static_cast<std::int64_t>(std::floor(s.time / every_)) + 1;
  take(s, s.time);
}

template <int D>
void SnapshotRecorder<D>::before_event(const State<D>& s, double t) {
  // Frames due before the event describe the state as it still is. A frame due at the
  // very instant of an event (or of the end of a time step) is taken here at the next
  // call, or by on_finish: it shows the state after the event (the state a step resolved).
  for (; next_time() < t; ++next_k_)
    if (next_time() >= s.time) take(s, next_time());
}

template <int D>
void SnapshotRecorder<D>::after_event(const State<D>&, const EventRecord&, const EngineCounters& c) {
  events_ = c.events;
}

template <int D>
void SnapshotRecorder<D>::on_finish(const State<D>& s, const RunResult& r) {
  events_ = r.counters.events;
  // The final state, unless the last frame already is it (no event since, same time).
  if (s.time != last_time_ || events_ != last_events_) take(s, s.time);
  writer_.finish();
}

template <int D>
std::unique_ptr<SnapshotRecorder<D>> make_snapshot_recorder(const Config& c, const State<D>& initial,
                                                            const std::string& dir) {
  if (c.output.snapshot_every <= 0.0) return nullptr;
  const Particles<D> particles = particles_of(initial);
  std::vector<std::unique_ptr<FrameSink<D>>> sinks;
  for (SnapshotFormat f : c.output.snapshot_formats) {
    const std::string path = (std::filesystem::path(dir) / (f == SnapshotFormat::h5md ? "trajectory.h5md" : "trajectory.xyz")).string();
    if (f == SnapshotFormat::h5md) sinks.push_back(std::make_unique<H5mdWriter<D>>(path, particles, to_toml_text(c)));
    else sinks.push_back(std::make_unique<XyzTrajectoryWriter<D>>(path, particles));
  }
  return std::make_unique<SnapshotRecorder<D>>(c.output.snapshot_every, std::move(sinks),
                                               c.engine.kind == EngineKind::ts);
}

template class SnapshotRecorder<2>;
template class SnapshotRecorder<3>;
template std::unique_ptr<SnapshotRecorder<2>> make_snapshot_recorder<2>(const Config&, const State<2>&, const std::string&);
template std::unique_ptr<SnapshotRecorder<3>> make_snapshot_recorder<3>(const Config&, const State<3>&, const std::string&);

}  // namespace ballagg
