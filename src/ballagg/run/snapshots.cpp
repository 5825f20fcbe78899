#include "ballagg/run/snapshots.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/io/gsd_writer.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/output_count.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"

namespace ballagg {

template <int D>
SnapshotRecorder<D>::SnapshotRecorder(double every, std::vector<std::unique_ptr<FrameSink<D>>> sinks,
                                      bool mirror_at_walls, RunGuard* guard)
    : every_(every), writer_(std::move(sinks)), mirror_at_walls_(mirror_at_walls), guard_(guard) {}

template <int D>
void SnapshotRecorder<D>::take(const State<D>& s, double t) {
  capture_source(s, t, events_, mirror_at_walls_, writer_.acquire(), layouts_);
  writer_.submit();
  ++frames_;
  last_time_ = t;
  last_events_ = events_;
  // The initial frame, kMaxFrames at the interval, and one more: a run that check_snapshot_frames
  // let through never gets here.
  if (guard_ != nullptr && frames_ >= kMaxFrames + 2) guard_->stop(StopCause::output_limit);
}

template <int D>
void SnapshotRecorder<D>::on_start(const State<D>& s) {
  if (resumed_) return;
  next_k_ = static_cast<std::int64_t>(std::floor(s.time / every_)) + 1;
  take(s, s.time);
}

template <int D>
void SnapshotRecorder<D>::before_event(const State<D>& s, double t) {
  // Frames due before the event describe the state as it still is. A frame due at the
  // very instant of an event (or of the end of a time step) is taken here at the next
  // call, or by on_finish: it shows the state after the event (the state a step resolved).
  // Cut short when the run must stop: the engine then leaves the event for later, or ends
  // the run. A frame can be long (a million spheres): the clock is read before each.
  for (; next_time() < t; ++next_k_) {
    if (next_time() < s.time) continue;
    if (guard_ != nullptr && guard_->check()) return;
    take(s, next_time());
  }
}

template <int D>
void SnapshotRecorder<D>::after_event(const State<D>&, const EventRecord&, const EngineCounters& c) {
  events_ = c.events;
}

template <int D>
void SnapshotRecorder<D>::on_finish(const State<D>& s, const RunResult& r) {
  // A run stopped by a signal without a checkpoint of it is abandoned: its files are not
  // completed, and the temporary ones go with the writer (unless a checkpoint refers to them).
  if (r.reason == StopReason::interrupted) return;
  events_ = r.counters.events;
  // The final state, unless the last frame already is it (no event since, same time).
  if (s.time != last_time_ || events_ != last_events_) take(s, s.time);
  writer_.finish();
}

template <int D>
std::string SnapshotRecorder<D>::save() {
  ByteWriter w;
  w.put_vector(writer_.flush());
  w.put(every_);
  w.put(next_k_);
  w.put(events_);
  w.put(frames_);
  w.put(last_time_);
  w.put(last_events_);
  return w.take();
}

template <int D>
std::vector<std::uint64_t> SnapshotRecorder<D>::saved_marks(std::string_view saved) {
  ByteReader r(saved, "checkpoint of the trajectory");
  return r.get_vector<std::uint64_t>("file marks");
}

template <int D>
void SnapshotRecorder<D>::restore(std::string_view saved) {
  ByteReader r(saved, "checkpoint of the trajectory");
  r.get_vector<std::uint64_t>("file marks");
  if (r.get<double>("interval") != every_) r.fail("saved with another output.snapshot_every");
  next_k_ = r.get<std::int64_t>("next frame");
  events_ = r.get<std::int64_t>("events");
  frames_ = r.get<int>("frames");
  last_time_ = r.get<double>("last frame time");
  last_events_ = r.get<std::int64_t>("last frame events");
  r.expect_end();
  resumed_ = true;
}

std::string trajectory_file_name(SnapshotFormat format) { return fmt::format("trajectory.{}", to_string(format)); }

template <int D>
std::unique_ptr<SnapshotRecorder<D>> make_snapshot_recorder(const Config& c, const State<D>& initial,
                                                            const std::string& dir,
                                                            std::optional<std::string_view> saved, RunGuard* guard) {
  if (c.output.snapshot_every <= 0.0) return nullptr;
  const Particles<D> particles = particles_of(initial);
  std::vector<std::uint64_t> marks;
  if (saved) {
    marks = SnapshotRecorder<D>::saved_marks(*saved);
    if (marks.size() != c.output.snapshot_formats.size())
      throw CheckpointError("checkpoint of the trajectory: saved for other output.snapshot_formats");
  }
  std::vector<std::unique_ptr<FrameSink<D>>> sinks;
  for (std::size_t k = 0; k < c.output.snapshot_formats.size(); ++k) {
    const SnapshotFormat f = c.output.snapshot_formats[k];
    const std::string path = (std::filesystem::path(dir) / trajectory_file_name(f)).string();
    if (f == SnapshotFormat::h5md) {
      const SnapshotPrecision precision = c.output.snapshot_precision;
      const bool pad = c.output.h5md_pad_3d;
      if (saved) sinks.push_back(std::make_unique<H5mdWriter<D>>(path, particles, marks[k], precision, pad));
      else sinks.push_back(std::make_unique<H5mdWriter<D>>(path, particles, to_toml_text(c), precision, pad));
    } else if (f == SnapshotFormat::gsd) {
      if (saved) sinks.push_back(std::make_unique<GsdWriter<D>>(path, particles, marks[k]));
      else sinks.push_back(std::make_unique<GsdWriter<D>>(path, particles));
    } else {
      if (saved) sinks.push_back(std::make_unique<XyzTrajectoryWriter<D>>(path, particles, marks[k]));
      else sinks.push_back(std::make_unique<XyzTrajectoryWriter<D>>(path, particles));
    }
  }
  auto recorder = std::make_unique<SnapshotRecorder<D>>(c.output.snapshot_every, std::move(sinks),
                                                        c.engine.kind == EngineKind::ts, guard);
  if (saved) recorder->restore(*saved);
  return recorder;
}

void check_snapshot_frames(double every, double start_time, double stop_time) {
  check_output_count("output.snapshot_every", every, start_time, stop_time, SnapshotRecorder<2>::kMaxFrames, "frames");
}

template class SnapshotRecorder<2>;
template class SnapshotRecorder<3>;
template std::unique_ptr<SnapshotRecorder<2>> make_snapshot_recorder<2>(const Config&, const State<2>&, const std::string&,
                                                                        std::optional<std::string_view>, RunGuard*);
template std::unique_ptr<SnapshotRecorder<3>> make_snapshot_recorder<3>(const Config&, const State<3>&, const std::string&,
                                                                        std::optional<std::string_view>, RunGuard*);

}  // namespace ballagg
