#pragma once
// timeseries.csv: one row at t = 0, a row each time the number of clusters has dropped by
// kRowDrop (0.5 %, at least one cluster) since the previous row, a row every
// `interval` of simulated time if interval > 0, and one for the final state. That is
// about 200 rows per e-fold of the cluster count: enough to plot N(t) on log axes, and
// bounded (about 2800 rows for a million spheres).
//
// With rotating bodies (rigid-body engine) each row also has the first-time collisions
// N_C1, the largest body mass, the velocity dispersion of the bodies along each axis, the
// rotational kinetic energy and the total angular momentum (docs/outputs.md).
//
// output.timeseries_interval can ask for far more rows than that. A run whose stop.time
// would give more than kMaxIntervalRows rows at that interval is refused before it starts
// (check_timeseries_rows); a run without a finite stop.time that reaches kMaxRows rows
// ends there (stop_reason output_limit). The rows due before one event poll the run's guard
// (core/run_guard.hpp), so that neither the wall-clock limit nor a signal waits for them.
#include <cstdint>
#include <string>
#include <string_view>

#include "ballagg/engines/engine.hpp"

namespace ballagg {

template <int D>
class TimeseriesRecorder final : public RunObserver<D> {
 public:
  static constexpr double kRowDrop = 0.005;
  // About 100 MB of text (up to 150 bytes a row with the rotating bodies' columns), held
  // in memory and in every checkpoint; 350 times the rows of a default run of a million
  // spheres.
  static constexpr std::int64_t kMaxIntervalRows = 1'000'000;
  // The cap on all rows leaves room for those at drops of the cluster count (about 200 per
  // e-fold: fewer than 5000 for a billion spheres).
  static constexpr std::int64_t kMaxRows = kMaxIntervalRows + 10'000;

  // guard: the run's, polled between rows and stopped at the cap (null: neither).
  explicit TimeseriesRecorder(double interval, bool rotating = false, RunGuard* guard = nullptr)
      : interval_(interval), rotating_(rotating), guard_(guard) {}

  void on_start(const State<D>& s) override;
  void before_event(const State<D>& s, double t) override;
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override;
  void on_finish(const State<D>& s, const RunResult& r) override;

  const std::string& csv() const { return csv_; }

  // Checkpoints: the rows so far and where the recorder stands. A restored recorder
  // continues the file: its on_start adds nothing.
  std::string save() const;
  void restore(std::string_view saved);

 private:
  void row(const State<D>& s, double t);
  void rotation_columns(const State<D>& s, double t);
  void schedule_drop(int clusters);

  double interval_;
  bool rotating_;
  RunGuard* guard_;
  std::int64_t rows_ = 0;
  double next_sample_ = 0.0;
  int next_drop_ = 0;
  double last_row_time_ = -1.0;
  std::int64_t last_row_events_ = -1;
  std::int64_t events_ = 0, collisions_ = 0, first_time_collisions_ = 0;
  std::string csv_;
  bool resumed_ = false;
};

// Throws InputError naming output.timeseries_interval when a run from `start_time` to
// stop.time would take more than TimeseriesRecorder's kMaxIntervalRows rows at that interval.
void check_timeseries_rows(double interval, double start_time, double stop_time);

}  // namespace ballagg
