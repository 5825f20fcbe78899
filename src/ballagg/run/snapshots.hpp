#pragma once
// Trajectory frames at exact simulated times: the initial state, every `every` of
// simulated time (t = k * every, k = 1, 2, ...), and the final state. Positions are lazy
// (State::position is valid at any time up to the next event), so a frame at k * every is
// written from before_event, between two events (ed, rigid-body) or two steps (ts), without
// changing the run: a run with snapshots gives the same results as one without. A frame due at the
// instant of an event, or of the end of a time step, shows the state after it.
//
// The frames due before one event check the run's guard (core/run_guard.hpp) one by one,
// so that neither the wall-clock limit nor a signal waits for them. A run whose stop.time
// would take more than kMaxFrames frames is refused before it starts
// (check_snapshot_frames); one without a finite stop.time ends after that many (stop_reason
// output_limit).
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <string>
#include <vector>

#include "ballagg/config/config.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/io/background_writer.hpp"

namespace ballagg {

template <int D>
class SnapshotRecorder final : public RunObserver<D> {
 public:
  // Frames taken at multiples of output.snapshot_every, at most: 100 times what a film
  // needs, and a bound on the disk a mistyped interval can fill.
  static constexpr std::int64_t kMaxFrames = 100'000;

  // `mirror_at_walls`: see capture_frame (true for the time-stepping engine). guard: the
  // run's, checked between frames and stopped at the cap (null: neither).
  SnapshotRecorder(double every, std::vector<std::unique_ptr<FrameSink<D>>> sinks, bool mirror_at_walls,
                   RunGuard* guard = nullptr);

  void on_start(const State<D>& s) override;
  void before_event(const State<D>& s, double t) override;
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override;
  void on_finish(const State<D>& s, const RunResult& r) override;
  // The rigid-body engine writes rotated sphere offsets only when asked: at each frame.
  double next_position_read() const override { return next_time(); }

  int frames() const { return frames_; }

  // Checkpoints: flushes the files (every frame so far on disk) and saves their marks and
  // where the recorder stands. A restored recorder's on_start takes no frame.
  std::string save();
  // The marks a saved recorder's sinks are to be reopened at (make_snapshot_recorder).
  static std::vector<std::uint64_t> saved_marks(std::string_view saved);
  void restore(std::string_view saved);

 private:
  double next_time() const { return static_cast<double>(next_k_) * every_; }
  void take(const State<D>& s, double t);

  double every_;
  LayoutCopies<D> layouts_;  // the frames' sphere layouts, shared while the state's is unchanged
  BackgroundWriter<D> writer_;
  bool mirror_at_walls_;
  RunGuard* guard_;
  std::int64_t next_k_ = 1;
  std::int64_t events_ = 0;
  int frames_ = 0;
  double last_time_ = 0.0;
  std::int64_t last_events_ = -1;
  bool resumed_ = false;
};

// trajectory.h5md, trajectory.xyz or trajectory.gsd.
std::string trajectory_file_name(SnapshotFormat format);

// The sinks a run's configuration asks for (trajectory_file_name of each in `dir`),
// on a background thread. Null when output.snapshot_every = 0. With `saved` (what save()
// returned), the recorder of a resumed run: it continues the files it saved.
template <int D>
std::unique_ptr<SnapshotRecorder<D>> make_snapshot_recorder(const Config& resolved, const State<D>& initial,
                                                            const std::string& dir,
                                                            std::optional<std::string_view> saved = std::nullopt,
                                                            RunGuard* guard = nullptr);

// Throws InputError naming output.snapshot_every when a run from `start_time` to stop.time
// would take more than SnapshotRecorder's kMaxFrames frames at that interval.
void check_snapshot_frames(double every, double start_time, double stop_time);

}  // namespace ballagg
