#include "ballagg/io/timeseries.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/io/output_count.hpp"

namespace ballagg {

template <int D>
void TimeseriesRecorder<D>::on_start(const State<D>& s) {
  if (resumed_) return;
  csv_ = "time,clusters,largest_cluster,kinetic_energy,";
  static constexpr const char* momentum_columns[] = {"px,", "py,", "pz,"};
  for (int a = 0; a < D; ++a) csv_ += momentum_columns[a];
  csv_ += "events,collisions";
  if (rotating_) {
    csv_ += ",first_time_collisions,max_mass";
    static constexpr const char* dispersion_columns[] = {",sigma_vx", ",sigma_vy", ",sigma_vz"};
    for (int a = 0; a < D; ++a) csv_ += dispersion_columns[a];
    csv_ += D == 2 ? ",rotational_energy,lz" : ",rotational_energy,lx,ly,lz";
  }
  csv_ += "\n";
  next_sample_ = s.time + interval_;
  row(s, s.time);
}

template <int D>
void TimeseriesRecorder<D>::schedule_drop(int clusters) {
  next_drop_ = clusters - std::max(1, static_cast<int>(kRowDrop * clusters));
}

template <int D>
void TimeseriesRecorder<D>::before_event(const State<D>& s, double t) {
  // Rows at sample times before this event describe the state as it still is. Cut short
  // when the run must stop: the engine then leaves the event for later, or ends the run.
  while (interval_ > 0.0 && next_sample_ < t) {
    if (guard_ != nullptr && guard_->poll()) return;
    row(s, next_sample_);
    next_sample_ += interval_;
  }
}

template <int D>
void TimeseriesRecorder<D>::after_event(const State<D>& s, const EventRecord&, const EngineCounters& c) {
  events_ = c.events;
  collisions_ = c.collisions;
  first_time_collisions_ = c.first_time_collisions;
  if (s.n_clusters() <= next_drop_) row(s, s.time);
}

template <int D>
void TimeseriesRecorder<D>::on_finish(const State<D>& s, const RunResult& r) {
  events_ = r.counters.events;
  collisions_ = r.counters.collisions;
  first_time_collisions_ = r.counters.first_time_collisions;
  if (events_ != last_row_events_ || s.time != last_row_time_) row(s, s.time);
}

// Rotating bodies: N_C1, the largest body mass, sigma_v per axis (over bodies), the
// rotational energy and the angular momentum about the box centre (centres of mass on
// their unwrapped trajectories: free flight conserves it exactly).
template <int D>
void TimeseriesRecorder<D>::rotation_columns(const State<D>& s, double t) {
  double max_mass = 0.0, rotational = 0.0;
  Vec<D> mean = Vec<D>::Zero(), mean_square = Vec<D>::Zero();
  Spin<D> angular = Spin<D>::Zero();
  const Vec<D> centre = Vec<D>::Constant(0.5 * s.box.length);
  for (int c : s.alive_clusters()) {
    const Cluster<D>& k = s.clusters[c];
    max_mass = std::max(max_mass, k.mass);
    mean += k.velocity;
    mean_square += k.velocity.cwiseProduct(k.velocity);
    angular += k.mass * cross(Vec<D>(s.origin(c, t) - centre), k.velocity);
    if (!s.spin.empty()) {
      rotational += s.spin[c].energy();
      angular += s.spin[c].angular_momentum;
    }
  }
  const double n = std::max(1, s.n_clusters());
  mean /= n;
  mean_square /= n;
  fmt::format_to(std::back_inserter(csv_), ",{},{}", first_time_collisions_, max_mass);
  for (int a = 0; a < D; ++a)
    fmt::format_to(std::back_inserter(csv_), ",{}", std::sqrt(std::max(0.0, mean_square[a] - mean[a] * mean[a])));
  fmt::format_to(std::back_inserter(csv_), ",{}", rotational);
  for (int a = 0; a < kSpinDim<D>; ++a) fmt::format_to(std::back_inserter(csv_), ",{}", angular[a]);
}

template <int D>
void TimeseriesRecorder<D>::row(const State<D>& s, double t) {
  const Vec<D>& p = s.running_momentum();
  fmt::format_to(std::back_inserter(csv_), "{},{},{},{},", t, s.n_clusters(), s.largest_cluster(),
                 s.running_kinetic_energy());
  for (int a = 0; a < D; ++a) fmt::format_to(std::back_inserter(csv_), "{},", p[a]);
  fmt::format_to(std::back_inserter(csv_), "{},{}", events_, collisions_);
  if (rotating_) rotation_columns(s, t);
  csv_ += '\n';
  last_row_time_ = t;
  last_row_events_ = events_;
  schedule_drop(s.n_clusters());
  if (++rows_ >= kMaxRows && guard_ != nullptr) guard_->stop(StopCause::output_limit);
}

template <int D>
std::string TimeseriesRecorder<D>::save() const {
  ByteWriter w;
  w.put(interval_);
  w.put(next_sample_);
  w.put(next_drop_);
  w.put(last_row_time_);
  w.put(last_row_events_);
  w.put(events_);
  w.put(collisions_);
  w.put_string(csv_);
  return w.take();
}

template <int D>
void TimeseriesRecorder<D>::restore(std::string_view saved) {
  ByteReader r(saved, "checkpoint of timeseries.csv");
  if (r.get<double>("interval") != interval_) r.fail("saved with another output.timeseries_interval");
  next_sample_ = r.get<double>("next sample");
  next_drop_ = r.get<int>("next drop");
  last_row_time_ = r.get<double>("last row time");
  last_row_events_ = r.get<std::int64_t>("last row events");
  events_ = r.get<std::int64_t>("events");
  collisions_ = r.get<std::int64_t>("collisions");
  csv_ = r.get_string("rows");
  r.expect_end();
  rows_ = std::count(csv_.begin(), csv_.end(), '\n') - 1;  // the header is no row
  resumed_ = true;
}

void check_timeseries_rows(double interval, double start_time, double stop_time) {
  check_output_count("output.timeseries_interval", interval, start_time, stop_time,
                     TimeseriesRecorder<2>::kMaxIntervalRows, "rows");
}

template class TimeseriesRecorder<2>;
template class TimeseriesRecorder<3>;

}  // namespace ballagg
