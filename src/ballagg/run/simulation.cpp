#include "ballagg/run/simulation.hpp"

#include <unistd.h>

// The heap is trimmed with glibc's malloc_trim. Under AddressSanitizer glibc's allocator
// is never used, so the first malloc_trim sets its arena up; two runs of a sweep that end
// together race in that set-up, and one walks a half-initialised arena (a null chunk).
// There the trim is left out: the memory belongs to the sanitizer's allocator anyway.
#if defined(__SANITIZE_ADDRESS__)
#define BALLAGG_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BALLAGG_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__GLIBC__) && !defined(BALLAGG_ADDRESS_SANITIZER)
#define BALLAGG_TRIM_HEAP 1
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ballagg/analysis/overlap.hpp"
#include "ballagg/collision/contact_time.hpp"
#include "ballagg/config/rigid_body_section.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/finite_state.hpp"
#include "ballagg/core/state_codec.hpp"
#include "ballagg/core/version.hpp"
#include "ballagg/engines/event_driven/event_driven_engine.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/initial/state_ranges.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/io/timeseries.hpp"
#include "ballagg/io/xyz.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "ballagg/run/checkpointer.hpp"
#include "ballagg/run/collision_law_summary.hpp"
#include "ballagg/run/observer_list.hpp"
#include "ballagg/run/progress.hpp"
#include "ballagg/run/run_files.hpp"
#include "ballagg/run/snapshots.hpp"

namespace ballagg {

template <int D>
Config resolve_defaults(Config c, const State<D>& s) {
  const double mean_radius = s.mean_radius();
  double mean_square_speed = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) mean_square_speed += s.velocity(i).squaredNorm();
  mean_square_speed /= s.n_spheres();
  if (!c.engine.skin && c.engine.kind == EngineKind::rigid_body) c.engine.skin = rigid_body_skin(s);
  if (!c.engine.skin && c.engine.kind != EngineKind::ts) c.engine.skin = default_skin(s, c.collision.outcome);
  if (!c.ts.delta_w) c.ts.delta_w = 4.0 * mean_radius;
  if (!c.collision.tc_time && c.collision.outcome != CollisionOutcome::stick) {
    const double rms = std::sqrt(mean_square_speed);
    c.collision.tc_time = rms > 0.0 ? kDefaultTcFraction * 2.0 * mean_radius / rms : 0.0;
  }
  // Richardson §3 and §2.6: thresholds as multiples of the initial mean kinetic energy per body.
  if (c.engine.kind == EngineKind::rigid_body) resolve_rigid_body_energies(c, mean_kinetic_energy_per_body(s));
  check_resolved_ranges(c, s);
  return c;
}

template <int D>
std::unique_ptr<Engine<D>> make_engine(const Config& c) {
  switch (c.engine.kind) {
    case EngineKind::ed: return make_event_driven_engine<D>({c.collision, c.engine.skin});
    case EngineKind::ed_naive: return make_naive_event_driven_engine<D>({c.collision, c.engine.skin});
    case EngineKind::ts: return make_time_stepping_engine<D>(c.ts);
    case EngineKind::rigid_body: return make_rigid_body_engine<D>({c.collision, c.rigid_body, c.engine.skin, c.initial.speed});
  }
  throw std::logic_error("make_engine: no such engine kind");
}

StopCriteria stop_criteria(const Config& c) {
  StopCriteria s;
  s.clusters = static_cast<int>(std::min<std::int64_t>(c.stop.clusters, std::numeric_limits<int>::max()));
  s.time = c.stop.time;
  s.wall_seconds = c.stop.wall_seconds;
  s.aggregated_fraction = c.stop.aggregated_fraction.value_or(kNever);
  return s;
}

namespace {

template <int D>
nlohmann::json vector_json(const Vec<D>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (int k = 0; k < D; ++k) a.push_back(v[k]);
  return a;
}

// Spin angular momentum plus orbital angular momentum about the box centre (rigid bodies).
template <int D>
Spin<D> angular_momentum(const State<D>& s) {
  Spin<D> l = Spin<D>::Zero();
  const Vec<D> centre = Vec<D>::Constant(0.5 * s.box.length);
  for (int c : s.alive_clusters()) {
    const Cluster<D>& k = s.clusters[c];
    l += k.mass * cross(Vec<D>(s.origin(c, s.time) - centre), k.velocity);
    if (!s.spin.empty()) l += s.spin[c].angular_momentum;
  }
  return l;
}

template <int D>
double rotational_energy(const State<D>& s) {
  double e = 0.0;
  for (int c : s.alive_clusters())
    if (!s.spin.empty()) e += s.spin[c].energy();
  return e;
}

template <int D>
struct Totals {
  Vec<D> momentum;
  double kinetic_energy;
  std::int64_t pinnings;
  Vec<D> wall_impulse;
  double rotational_energy;
  explicit Totals(const State<D>& s)
      : momentum(s.momentum()), kinetic_energy(s.kinetic_energy()), pinnings(s.pinnings()),
        wall_impulse(s.wall_impulse()), rotational_energy(total_kinetic_energy(s) - s.kinetic_energy()) {}
  // Checkpoints.
  std::string encode() const {
    ByteWriter w;
    w.put(momentum);
    w.put(kinetic_energy);
    w.put(pinnings);
    w.put(wall_impulse);
    w.put(rotational_energy);
    return w.take();
  }
  explicit Totals(std::string_view saved) {
    ByteReader r(saved, "checkpoint of the initial totals");
    momentum = r.get<Vec<D>>("momentum");
    kinetic_energy = r.get<double>("kinetic energy");
    pinnings = r.get<std::int64_t>("pinnings");
    wall_impulse = r.get<Vec<D>>("wall impulse");
    rotational_energy = r.get<double>("rotational energy");
    r.expect_end();
  }
};

template <int D>
std::string summary_text(const Config& c, std::string_view engine, const Totals<D>& initial, const State<D>& s,
                         const RunResult& r) {
  nlohmann::ordered_json j;
  j["engine"] = engine;
  j["dimension"] = D;
  j["n_particles"] = s.n_spheres();
  j["box_length"] = s.box.length;
  j["boundary"] = to_string(s.box.boundary);
  j["n_clusters"] = s.n_clusters();
  j["largest_cluster"] = s.largest_cluster();
  j["time"] = s.time;
  j["stop_reason"] = to_string(r.reason);
  const EngineCounters& n = r.counters;
  j["events"] = n.events;
  j["collisions"] = n.collisions;
  j["merges"] = n.merges;
  j["bounces"] = n.bounces;
  j["wall_bounces"] = n.wall_bounces;
  for (const EngineCount& k : r.engine_counts) std::visit([&](auto v) { j[std::string(k.key)] = v; }, k.value);
  j["wall_pinnings"] = s.pinnings() - initial.pinnings;
  j["wall_seconds"] = r.wall_seconds;
  j["events_per_second"] = r.wall_seconds > 0 ? r.counters.events / r.wall_seconds : 0.0;
  j["mass_total"] = s.total_mass();
  j["momentum_initial"] = vector_json<D>(initial.momentum);
  j["momentum_final"] = vector_json<D>(s.momentum());
  j["wall_impulse"] = vector_json<D>(s.wall_impulse() - initial.wall_impulse);  // momentum_final - momentum_initial
  j["kinetic_energy_initial"] = initial.kinetic_energy;
  j["kinetic_energy_final"] = s.kinetic_energy();
  if (c.engine.kind == EngineKind::rigid_body) {
    // kinetic_energy_* above are translational; rotational energy (eq. 2) apart.
    j["rotational_energy_initial"] = initial.rotational_energy;
    j["rotational_energy_final"] = rotational_energy(s);
    j["angular_momentum_final"] = vector_json<kSpinDim<D>>(Vec<kSpinDim<D>>(angular_momentum(s)));
    j["collision_law"] = nlohmann::ordered_json::parse(collision_law_json_text(c));
  }
  const std::optional<double> overlap = max_relative_overlap(s);
  j["max_overlap"] = overlap ? nlohmann::ordered_json(*overlap) : nlohmann::ordered_json(nullptr);
  j["seed"] = c.initial.seed;
  j["version"] = kVersion;
  j["config"] = nlohmann::ordered_json::parse(to_json_text(c));
  return j.dump(2) + "\n";
}

// What a checkpoint of this run holds besides the state and the engine's state (which the
// checkpointer streams into the file), made when it asks (the recorders as they are then).
template <int D>
auto checkpoint_maker(const Config& config, std::string_view engine, double earlier_seconds, const Totals<D>& initial,
                      const TimeseriesRecorder<D>& timeseries, SnapshotRecorder<D>* snapshots) {
  return [config_toml = to_toml_text(config), engine_name = std::string(engine), earlier_seconds, &initial, &timeseries,
          snapshots](double seconds) {
    Checkpoint c;
    c.program_version = kVersion;
    c.dimension = D;
    c.engine = engine_name;
    c.config_toml = config_toml;
    c.wall_seconds = earlier_seconds + seconds;
    c.totals = initial.encode();
    c.timeseries = timeseries.save();
    if (snapshots) c.snapshots = snapshots->save();
    return c;
  };
}

// A run stopped by a signal without a checkpoint of that moment: its directory goes unless
// an earlier checkpoint can continue it; the message says which.
[[noreturn]] void throw_interrupted(const std::string& dir, bool created, double time) {
  std::error_code ec;
  const bool resumable = std::filesystem::exists(std::filesystem::path(dir) / kCheckpointFile, ec);
  if (created && !resumable) std::filesystem::remove(dir, ec);
  throw RunInterrupted(stop_signal(), fmt::format("interrupted by {} at t = {}: {}", signal_name(stop_signal()), time,
                                                  resumable ? fmt::format("continue from its last checkpoint with: "
                                                                          "ballagg run --resume {}", dir)
                                                            : std::string("the run's files were not written")));
}

// A new run that fails without a result (bad input found during the run, a state that is
// not finite) leaves nothing behind, as input rejected before the run: its trajectories'
// temporary files and its checkpoints go, then the lock, then the directory if the run
// created it. A resumed run's directory keeps what it held.
template <int D>
void discard_new_run(std::optional<NewRunDirectory>& fresh, std::unique_ptr<SnapshotRecorder<D>>& snapshots,
                     const std::string& dir) {
  if (!fresh) return;
  snapshots.reset();
  remove_run_files(dir);  // the directory held none at the start (open_new_run_directory)
  const bool created = fresh->created;
  fresh.reset();
  std::error_code ec;
  if (created) std::filesystem::remove(dir, ec);
}

// The files of a finished run, summary.json last; its checkpoint goes (nothing to resume).
template <int D>
void write_run_files(const std::string& dir, const Config& config, std::string_view engine, const Totals<D>& initial,
                     const State<D>& state, const RunResult& result, const std::string& timeseries_csv) {
  // Streamed: the text of final.csv and final.xyz is about 100 bytes per sphere.
  write_file_atomically(dir, "final.csv", [&](ByteSink& out) { write_state_csv(state, out); });
  if (config.output.xyz) write_file_atomically(dir, "final.xyz", [&](ByteSink& out) { write_xyz_frame(state, out); });
  write_file_atomically(dir, "timeseries.csv", timeseries_csv);
  if (config.engine.kind == EngineKind::rigid_body) {
    // Richardson's end-of-run statistics: the files of `ballagg analyze`, from final.csv
    // read as that command reads it, so that both give the same bytes.
    const std::string final_path = (std::filesystem::path(dir) / "final.csv").string();
    write_analysis(Box<D>{resolved_box_length(config), config.system.boundary}, read_state_csv<D>(final_path),
                   final_path, dir);
  }
  write_file_atomically(dir, "config.toml", to_toml_text(config));
  write_file_atomically(dir, "summary.json", summary_text(config, engine, initial, state, result));
  std::error_code ec;
  std::filesystem::remove(std::filesystem::path(dir) / kCheckpointFile, ec);
}

// The engine of a resumed run takes up its own state from the checkpoint, which must be
// its own engine's.
template <int D>
void resume_engine(Engine<D>& engine, State<D>& state, const Checkpoint& resume, const std::string& dir) {
  if (resume.engine != engine.name())
    throw CheckpointError(
        fmt::format("{}: written by engine {} for a configuration of engine {}", dir, resume.engine, engine.name()));
  engine.resume_from(state, resume.engine_state);
}

// A run stopped by the caps on rows and frames says so, and how to lift them.
template <int D>
void report_output_limit(double time) {
  fmt::print(stderr,
             "ballagg: the run stopped at t = {} with as many rows or frames as are written (at most {} rows of "
             "timeseries.csv, {} trajectory frames): set a larger output.timeseries_interval or "
             "output.snapshot_every, or a stop.time\n",
             time, TimeseriesRecorder<D>::kMaxRows, SnapshotRecorder<D>::kMaxFrames + 2);
}

// A fresh run (resume = null), or the continuation of one from its checkpoint (given is
// then the checkpoint's resolved configuration and options.out_dir its directory).
template <int D>
std::string run_in_dimension(const Config& given, const RunOptions& options, const Checkpoint* resume) {
  // All input checks happen before any output.
  State<D> state = resume ? StateCodec<D>::decode(resume->state) : make_initial_state<D>(given);
  const Config config = resume ? given : resolve_defaults(given, state);
  StopCriteria stop = stop_criteria(config);
  std::unique_ptr<Engine<D>> engine = make_engine<D>(config);
  const double earlier_seconds = resume ? resume->wall_seconds : 0.0;
  if (resume) {
    resume_engine(*engine, state, *resume, options.out_dir);
    stop.wall_seconds -= earlier_seconds;  // stop.wall_seconds bounds the whole run
  }

  if (!resume) {
    check_timeseries_rows(config.output.timeseries_interval, state.time, config.stop.time);
    check_snapshot_frames(config.output.snapshot_every, state.time, config.stop.time);
  }

  // Signals are heard from here on: everything is checked, and nothing written yet.
  std::optional<InterruptFlag> interrupts;
  if (options.checkpoint_on_signals) interrupts.emplace();
  const std::string dir = options.out_dir.empty() ? default_output_dir() : options.out_dir;
  // A resumed run's directory is locked by resume_simulation, before its checkpoint is read.
  std::optional<NewRunDirectory> fresh;
  if (!resume) fresh.emplace(open_new_run_directory(dir, options.overwrite));
  const bool created = fresh && fresh->created;

  // Polled by the engine and the recorders: the wall-clock limit, signals, output caps.
  RunGuard guard(stop.wall_seconds);
  stop.guard = &guard;
  const Totals<D> initial = resume ? Totals<D>(resume->totals) : Totals<D>(state);
  const bool rigid = config.engine.kind == EngineKind::rigid_body;
  TimeseriesRecorder<D> timeseries(config.output.timeseries_interval, rigid, &guard);
  if (resume) timeseries.restore(resume->timeseries);
  ProgressReporter<D> progress(stderr, options.progress_on_terminal && isatty(STDERR_FILENO), stop);
  ObserverList<D> observers;
  observers.add(&timeseries);
  std::optional<std::string_view> saved_snapshots;
  if (resume && !resume->snapshots.empty()) saved_snapshots = resume->snapshots;
  std::unique_ptr<SnapshotRecorder<D>> snapshots = make_snapshot_recorder(config, state, dir, saved_snapshots, &guard);
  if (snapshots) observers.add(snapshots.get());
  if (!options.quiet) observers.add(&progress);

  std::optional<Checkpointer<D>> checkpointer;
  if (engine->supports_checkpoints()) {
    checkpointer.emplace(dir, config.output.checkpoint_every, interrupts.has_value(),
                         checkpoint_maker<D>(config, engine->name(), earlier_seconds, initial, timeseries, snapshots.get()),
                         &guard);
    observers.add(&*checkpointer);
  }
  RunResult result;
  try {
    guard.start_clock();
    result = engine->run(state, stop, observers);
    if (result.reason != StopReason::interrupted) throw_if_not_finite(state, engine->name(), first_non_finite(state));
  } catch (const InputError&) {  // found during the run (coefficients that would create energy)
    discard_new_run(fresh, snapshots, dir);
    throw;
  } catch (const NonFiniteState&) {  // a numerical failure: no file may show it
    discard_new_run(fresh, snapshots, dir);
    throw;
  }
  if (result.reason == StopReason::interrupted) {
    // A signal, and no checkpoint of it (a run inside a sweep): nothing of this run is
    // written; its trajectories' temporary files go unless an earlier checkpoint refers to them.
    snapshots.reset();
    throw_interrupted(dir, created, state.time);
  }
  result.wall_seconds += earlier_seconds;
  if (result.reason == StopReason::output_limit && !options.quiet) report_output_limit<D>(state.time);

  const std::string engine_name(engine->name());
  checkpointer.reset();
  engine.reset();
  // glibc keeps the heap the engine freed (hundreds of bytes per sphere, in blocks below
  // its mmap threshold) resident in the process; giving it back to the system before the
  // output files are written keeps that phase's peak memory to what it uses.
#if defined(BALLAGG_TRIM_HEAP)
  malloc_trim(0);
#endif
  write_run_files(dir, config, engine_name, initial, state, result, timeseries.csv());
  return dir;
}

}  // namespace

std::string run_simulation(const Config& config, const RunOptions& options) {
  if (config.system.dimension == 2) return run_in_dimension<2>(config, options, nullptr);
  return run_in_dimension<3>(config, options, nullptr);
}

std::string resume_simulation(const std::string& dir, const RunOptions& options) {
  // Locked before the checkpoint is read: a second resume of the same directory is
  // refused, and cannot start from a checkpoint the first has finished with.
  std::error_code ec;
  std::optional<DirectoryLock> lock;
  if (std::filesystem::is_directory(dir, ec)) lock.emplace(dir);
  const Checkpoint checkpoint = read_checkpoint_file(dir);
  const Config config = parse_config_text(checkpoint.config_toml, (std::filesystem::path(dir) / kCheckpointFile).string());
  if (config.system.dimension != checkpoint.dimension)
    throw CheckpointError(fmt::format("{}: a checkpoint of dimension {} for a {}D configuration", dir,
                                      checkpoint.dimension, config.system.dimension));
  RunOptions resumed = options;
  resumed.out_dir = dir;
  if (config.system.dimension == 2) return run_in_dimension<2>(config, resumed, &checkpoint);
  return run_in_dimension<3>(config, resumed, &checkpoint);
}

template Config resolve_defaults<2>(Config, const State<2>&);
template Config resolve_defaults<3>(Config, const State<3>&);
template std::unique_ptr<Engine<2>> make_engine<2>(const Config&);
template std::unique_ptr<Engine<3>> make_engine<3>(const Config&);

}  // namespace ballagg
