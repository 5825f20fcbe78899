// Checkpoints and restarts: a run saved at any point between two events (or steps) and
// resumed continues bit for bit as if it had never stopped, including after SIGKILL at a
// random moment; a checkpoint that is not exactly what we wrote is refused, never misread.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state_codec.hpp"
#include "ballagg/engines/event_driven/neighbor_keeper.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "ballagg/engines/rigid_body/rigid_body_settings.hpp"
#include "ballagg/engines/time_stepping/ts_counters.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/spatial/grid_geometry.hpp"
#include "cli_support.hpp"
#include "fuzz/checkpoint_payload.hpp"
#include "support.hpp"
#include "thread_count.hpp"

extern char** environ;

namespace ballagg {
namespace {

using testing::small_config;
using testing::TempDir;

const auto read_file = testing::slurp;

// ---- in process: checkpoints at chosen points -------------------------------------------

// Takes a checkpoint (state and engine bytes) at the first chance after `after` events.
template <int D>
class SaveOnce final : public RunObserver<D> {
 public:
  explicit SaveOnce(std::int64_t after) : after_(after) {}
  void after_event(const State<D>&, const EventRecord&, const EngineCounters& c) override { events_ = c.events; }
  bool checkpoint_due() override { return state.empty() && events_ >= after_; }
  void on_checkpoint(const State<D>& s, const EngineCounters&, const std::string& engine_state) override {
    state = StateCodec<D>::encode(s);
    engine = engine_state;
  }
  std::string state, engine;

 private:
  std::int64_t after_;
  std::int64_t events_ = 0;
};

// Runs `config` to the end uninterrupted, then again saved at the first checkpoint point
// after each fraction of its events and finished by a new engine resumed from the saved
// bytes: the final states must be equal bit for bit, and so must the counters.
template <int D>
void expect_resumed_runs_identical(const Config& given, std::vector<double> fractions, RunResult* uninterrupted = nullptr) {
  State<D> reference = make_initial_state<D>(given);
  const Config c = resolve_defaults(given, reference);
  RunObserver<D> none;
  const RunResult whole = make_engine<D>(c)->run(reference, stop_criteria(c), none);
  if (uninterrupted) *uninterrupted = whole;
  for (double f : fractions) {
    const auto after = static_cast<std::int64_t>(f * static_cast<double>(whole.counters.events));
    SCOPED_TRACE("saved after " + std::to_string(after) + " of " + std::to_string(whole.counters.events) + " events");
    State<D> first = make_initial_state<D>(given);
    SaveOnce<D> saver(after);
    make_engine<D>(c)->run(first, stop_criteria(c), saver);
    ASSERT_FALSE(saver.state.empty());
    State<D> resumed = StateCodec<D>::decode(saver.state);
    std::unique_ptr<Engine<D>> engine = make_engine<D>(c);
    engine->resume_from(resumed, saver.engine);
    const RunResult rest = engine->run(resumed, stop_criteria(c), none);

    EXPECT_EQ(state_csv_text(resumed), state_csv_text(reference));
    EXPECT_EQ(resumed.time, reference.time);
    EXPECT_EQ(rest.reason, whole.reason);
    EXPECT_EQ(rest.counters, whole.counters);
    EXPECT_EQ(rest.engine_counts, whole.engine_counts);
  }
}

// The event-driven engines can save every 256 events (event_loop.hpp).
TEST(Checkpoint, EventDrivenResumesBitForBitFromAnyPoint2DWalls) {
  expect_resumed_runs_identical<2>(small_config(2, 1500, 0.2, Boundary::walls, 5), {0.0, 0.3, 0.6, 0.85});
}

TEST(Checkpoint, EventDrivenResumesBitForBit3DPeriodicWithBounces) {
  Config c = small_config(3, 300, 0.15, Boundary::periodic, 6);
  c.collision.outcome = CollisionOutcome::bounce;
  c.collision.restitution = 0.9;
  c.stop.time = 20.0;
  expect_resumed_runs_identical<3>(c, {0.2, 0.7});
}

TEST(Checkpoint, NaiveEventDrivenResumesBitForBit) {
  Config c = small_config(2, 60, 0.2, Boundary::walls, 7);
  c.engine.kind = EngineKind::ed_naive;
  c.collision.outcome = CollisionOutcome::bounce;  // enough events to pass 256
  c.stop.time = 30.0;
  expect_resumed_runs_identical<2>(c, {0.5});
}

// The time-stepping engine can save between any two steps. On one thread: at this size
// threads only wait for each other on a busy machine (the command-line test below resumes
// a run on the default number of threads).
TEST(Checkpoint, TimeSteppingResumesBitForBitEveryModel) {
  const testing::ThreadCount one_thread(1);
  for (TsModel model : {TsModel::rigid, TsModel::almost_rigid, TsModel::non_rigid}) {
    Config c = small_config(2, 100, 0.2, Boundary::walls, 8);
    c.engine.kind = EngineKind::ts;
    c.ts.model = model;
    c.stop.clusters = 40;
    expect_resumed_runs_identical<2>(c, {0.1, 0.6});
  }
  Config c = small_config(3, 150, 0.2, Boundary::periodic, 9);
  c.engine.kind = EngineKind::ts;
  c.stop.clusters = 20;
  expect_resumed_runs_identical<3>(c, {0.3});
}

// The time-stepping engine's saved time step (after its counters: the initial cluster
// count, then the initial step) is checked like the state's numbers: a NaN or negative
// step would make every later step NaN or run backwards.
TEST(Checkpoint, TimeSteppingRefusesASavedTimeStepNoRunCanHave) {
  Config given = small_config(2, 100, 0.2, Boundary::walls, 8);
  given.engine.kind = EngineKind::ts;
  State<2> s = make_initial_state<2>(given);
  const Config c = resolve_defaults(given, s);
  SaveOnce<2> saver(0);
  make_engine<2>(c)->run(s, {.clusters = 90}, saver);
  ASSERT_FALSE(saver.engine.empty());
  ByteWriter counters;
  TimeSteppingCounters{}.save(counters);
  const std::size_t step_at = counters.bytes().size() + sizeof(std::int32_t);
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), -1.0, std::numeric_limits<double>::infinity()}) {
    std::string bytes = saver.engine;
    std::memcpy(bytes.data() + step_at, &bad, sizeof bad);
    State<2> resumed = StateCodec<2>::decode(saver.state);
    EXPECT_THROW(make_engine<2>(c)->resume_from(resumed, bytes), CheckpointError) << bad;
  }
  State<2> resumed = StateCodec<2>::decode(saver.state);
  EXPECT_NO_THROW(make_engine<2>(c)->resume_from(resumed, saver.engine));  // the bytes as saved
}

// The rigid-body engine can save every 256 events, like the event-driven ones: its bodies
// (free rotations, own-frame coordinates), lists, calendar and searches are restored as
// they were, and final.csv (with the spin columns) comes out the same.
Config rigid_config(int dimension, int n, double volume_fraction, Boundary boundary, std::uint64_t seed) {
  Config c = small_config(dimension, n, volume_fraction, boundary, seed);
  c.engine.kind = EngineKind::rigid_body;
  c.initial.velocities = InitialVelocities::gaussian;
  return c;
}

TEST(Checkpoint, RigidBodyResumesBitForBit3DPeriodicCoagulation) {
  Config c = rigid_config(3, 300, 0.1, Boundary::periodic, 11);
  c.stop.clusters = 25;
  RunResult whole;
  expect_resumed_runs_identical<3>(c, {0.0, 0.3, 0.6, 0.85}, &whole);
  EXPECT_GT(whole.count("contact_searches"), 0);  // rotating bodies were searched for
}

TEST(Checkpoint, RigidBodyResumesBitForBit2DWalls) {
  Config c = rigid_config(2, 300, 0.15, Boundary::walls, 12);
  c.stop.clusters = 20;
  expect_resumed_runs_identical<2>(c, {0.25, 0.75});
}

// Richardson's model (v) physics: energy-threshold outcome, the Bridges restitution law.
Config with_model_v_physics(Config c) {
  c.collision.outcome = CollisionOutcome::energy_threshold;
  c.rigid_body.restitution_law = RestitutionLaw::bridges;
  c.rigid_body.velocity_unit = 0.01;
  return c;
}

TEST(Checkpoint, RigidBodyResumesBitForBitWithRestitution) {
  Config c = with_model_v_physics(rigid_config(3, 200, 0.1, Boundary::periodic, 13));
  c.stop.time = 15.0;
  RunResult whole;
  expect_resumed_runs_identical<3>(c, {0.2, 0.7}, &whole);
  EXPECT_GT(whole.counters.bounces, 0);
  EXPECT_GT(whole.counters.merges, 0);
}

TEST(Checkpoint, RigidBodyResumesBitForBitWithFragmentation) {
  Config c = rigid_config(3, 200, 0.12, Boundary::walls, 14);
  c.rigid_body.fragmentation_energy = 0.6;
  c.stop.time = 15.0;
  RunResult whole;
  expect_resumed_runs_identical<3>(c, {0.3, 0.8}, &whole);
  EXPECT_GT(whole.count("fragmentations"), 0);
}

// Sphere coagulation (model ii) renumbers spheres and rebuilds the lists at every merge.
TEST(Checkpoint, RigidBodyResumesBitForBitWithSphereCoagulation) {
  Config c = rigid_config(3, 500, 0.05, Boundary::periodic, 15);
  c.rigid_body.coagulation = Coagulation::sphere;
  c.stop.clusters = 200;
  expect_resumed_runs_identical<3>(c, {0.5});
}

// The rigid-body engine's grid has at most RigidBodySettings::cells_per_sphere cells per
// sphere. In a gas dilute enough that CellGrid's default of 2 binds, a grid of either count
// gives the same run, and a checkpoint saved with the coarser grid is resumed with it, bit
// for bit, by an engine that would build the finer one; a grid finer than the engine's own
// is refused.
TEST(Checkpoint, RigidBodyGridsOfEitherCellCountGiveTheSameRunAndResume) {
  Config given = with_model_v_physics(rigid_config(3, 400, 0.002, Boundary::periodic, 17));
  given.stop.clusters = 330;
  State<3> reference = make_initial_state<3>(given);
  const Config c = resolve_defaults(given, reference);
  const auto settings = [&](double cells_per_sphere) {
    RigidBodySettings s{c.collision, c.rigid_body, c.engine.skin, c.initial.speed};
    s.cells_per_sphere = cells_per_sphere;
    return s;
  };
  constexpr double kCoarse = 2.0, kFine = kRigidBodyCellsPerSphere;
  const double narrowest = binning_cell_size(reference.max_radius(), *c.engine.skin);
  ASSERT_LT(GridGeometry<3>(reference.box, narrowest, 400, kCoarse).per_side(),
            GridGeometry<3>(reference.box, narrowest, 400, kFine).per_side());

  RunObserver<3> none;
  const RunResult whole = make_rigid_body_engine<3>(settings(kFine))->run(reference, stop_criteria(c), none);
  EXPECT_GT(whole.counters.merges, 0);
  EXPECT_GT(whole.counters.bounces, 0);
  State<3> coarse = make_initial_state<3>(given);
  const RunResult coarse_run = make_rigid_body_engine<3>(settings(kCoarse))->run(coarse, stop_criteria(c), none);
  EXPECT_EQ(state_csv_text(coarse), state_csv_text(reference));
  EXPECT_EQ(coarse_run.counters, whole.counters);

  SaveOnce<3> coarse_saver(whole.counters.events / 2), fine_saver(whole.counters.events / 2);
  State<3> first = make_initial_state<3>(given);
  make_rigid_body_engine<3>(settings(kCoarse))->run(first, stop_criteria(c), coarse_saver);
  State<3> again = make_initial_state<3>(given);
  make_rigid_body_engine<3>(settings(kFine))->run(again, stop_criteria(c), fine_saver);
  ASSERT_FALSE(coarse_saver.state.empty());
  ASSERT_FALSE(fine_saver.state.empty());
  State<3> resumed = StateCodec<3>::decode(coarse_saver.state);
  std::unique_ptr<Engine<3>> engine = make_rigid_body_engine<3>(settings(kFine));
  engine->resume_from(resumed, coarse_saver.engine);
  const RunResult rest = engine->run(resumed, stop_criteria(c), none);
  EXPECT_EQ(state_csv_text(resumed), state_csv_text(reference));
  EXPECT_EQ(rest.counters, whole.counters);

  State<3> finer = StateCodec<3>::decode(fine_saver.state);
  EXPECT_THROW(make_rigid_body_engine<3>(settings(kCoarse))->resume_from(finer, fine_saver.engine), CheckpointError);
}

TEST(Checkpoint, RigidBodyRefusesBytesOfAnotherRun) {
  const Config c = rigid_config(3, 200, 0.1, Boundary::periodic, 16);
  State<3> s = make_initial_state<3>(c);
  SaveOnce<3> saver(0);
  make_engine<3>(resolve_defaults(c, s))->run(s, {.clusters = 150}, saver);
  ASSERT_FALSE(saver.engine.empty());
  State<3> other = make_initial_state<3>(rigid_config(3, 190, 0.1, Boundary::periodic, 16));
  EXPECT_THROW(make_engine<3>(resolve_defaults(c, other))->resume_from(other, saver.engine), CheckpointError);
  for (std::size_t cut : {saver.engine.size() / 3, saver.engine.size() - 1}) {
    State<3> same = StateCodec<3>::decode(saver.state);
    EXPECT_THROW(make_engine<3>(resolve_defaults(c, same))->resume_from(same, saver.engine.substr(0, cut)), CheckpointError);
  }
}

TEST(Checkpoint, StateRoundTripsExactly) {
  State<3> s = make_initial_state<3>(small_config(3, 200, 0.2, Boundary::periodic, 3));
  RunObserver<3> none;
  make_event_driven_engine<3>({})->run(s, {.clusters = 60}, none);
  const std::string bytes = StateCodec<3>::encode(s);
  const State<3> back = StateCodec<3>::decode(bytes);
  EXPECT_EQ(StateCodec<3>::encode(back), bytes);
  EXPECT_EQ(back.alive_clusters(), s.alive_clusters());
  EXPECT_EQ(back.running_kinetic_energy(), s.running_kinetic_energy());
  EXPECT_EQ(back.pinnings(), s.pinnings());
}

// An engine refuses saved bytes that do not fit the state it is to continue.
TEST(Checkpoint, EngineRefusesBytesOfAnotherRun) {
  const Config c = small_config(2, 100, 0.2, Boundary::walls, 2);
  State<2> s = make_initial_state<2>(c);
  SaveOnce<2> saver(0);
  make_engine<2>(resolve_defaults(c, s))->run(s, {}, saver);
  State<2> other = make_initial_state<2>(small_config(2, 90, 0.2, Boundary::walls, 2));
  EXPECT_THROW(make_engine<2>(resolve_defaults(c, other))->resume_from(other, saver.engine), CheckpointError);
  State<2> same = StateCodec<2>::decode(saver.state);
  const std::string cut = saver.engine.substr(0, saver.engine.size() / 2);
  EXPECT_THROW(make_engine<2>(resolve_defaults(c, same))->resume_from(same, cut), CheckpointError);
  EXPECT_THROW(StateCodec<2>::decode(saver.state.substr(0, saver.state.size() - 1)), CheckpointError);
  EXPECT_THROW(StateCodec<3>::decode(saver.state), CheckpointError);  // a 2D state read as 3D
}

// A saved state whose structure is sound but whose numbers no run can hold is refused with
// one CheckpointError naming the field, before any engine sees it.
TEST(Checkpoint, StateWithNumbersNoRunCanHoldIsRefused) {
  const Config c = small_config(2, 100, 0.2, Boundary::walls, 2);
  State<2> ran = make_initial_state<2>(c);
  RunObserver<2> none;
  make_event_driven_engine<2>({})->run(ran, {.clusters = 60}, none);
  const std::string good = StateCodec<2>::encode(ran);
  ASSERT_NO_THROW(StateCodec<2>::decode(good));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto refused = [&](const std::string& what, auto change) {
    SCOPED_TRACE(what);
    State<2> s = StateCodec<2>::decode(good);
    change(s);
    try {
      StateCodec<2>::decode(StateCodec<2>::encode(s));
      ADD_FAILURE() << "accepted";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const int c0 = ran.spheres.cluster[0];
  refused("sphere radius", [&](State<2>& s) { s.spheres.radius[5] = nan; });
  refused("sphere radius", [&](State<2>& s) { s.spheres.radius[5] = -0.5; });
  refused("sphere mass", [&](State<2>& s) { s.spheres.mass[7] = 0.0; });
  refused("sphere offset", [&](State<2>& s) { s.spheres.offset[0][1] = std::numeric_limits<double>::infinity(); });
  refused("cluster's motion", [&](State<2>& s) { s.clusters[c0].velocity[0] = nan; });
  refused("cluster mass", [&](State<2>& s) { s.clusters[c0].mass = nan; });
  refused("time", [&](State<2>& s) { s.time = nan; });
  refused("largest radius", [&](State<2>& s) { s.spheres.radius[3] = 2.0 * s.max_radius(); });
  refused("box length outside", [&](State<2>& s) { s.clusters[c0].anchor[0] = 3.0 * s.box.length; });
  // A stamp no run hands out: the event calendar's kind bits would take it (core/state.hpp).
  refused("cluster stamp", [&](State<2>& s) { s.clusters[c0].stamp = kStampLimit; });
  // The largest radius itself (a cache, saved as is): the bytes patched in place.
  std::string patched = good;
  const std::size_t at = patched.size() - (4 + 2 * 8 + 8 + 2 * 8 + 8 + 8 + 8);  // see StateCodec::encode
  std::memcpy(patched.data() + at, &nan, sizeof nan);
  EXPECT_THROW(StateCodec<2>::decode(patched), CheckpointError);
}

// A rigid-body checkpoint whose state's largest radius is NaN (the fuzz_checkpoint_sections
// corpus file below) would reach the engine's cell grid, which converts NaN to int: the
// state decoder refuses it.
TEST(Checkpoint, FuzzedStateWithNanLargestRadiusIsRefused) {
  const std::string payload = read_file(std::filesystem::path(BALLAGG_SOURCE_DIR) / "tests" / "fuzz" / "corpus" /
                                        "fuzz_checkpoint_sections" / "nan_largest_radius.payload");
  ASSERT_FALSE(payload.empty());
  const Checkpoint c = decode_checkpoint(testing::checkpoint_file_of(payload), "nan_largest_radius.payload");
  ASSERT_EQ(c.dimension, 3);
  EXPECT_THROW(StateCodec<3>::decode(c.state), CheckpointError);
}

// ---- the file format -------------------------------------------------------------------

Checkpoint small_checkpoint() {
  Checkpoint c;
  c.program_version = "test";
  c.dimension = 2;
  c.engine = "ed";
  c.config_toml = "[system]\nn = 10\n";
  c.wall_seconds = 1.5;
  c.state = std::string(300, 'x');
  c.engine_state = "engine";
  return c;
}

TEST(CheckpointFile, RoundTrips) {
  const Checkpoint c = small_checkpoint();
  const Checkpoint back = decode_checkpoint(encode_checkpoint(c), "f");
  EXPECT_EQ(back.config_toml, c.config_toml);
  EXPECT_EQ(back.state, c.state);
  EXPECT_EQ(back.engine_state, c.engine_state);
  EXPECT_EQ(back.wall_seconds, c.wall_seconds);
}

// Every prefix of a checkpoint (a write cut short), every single flipped bit, another
// format version and a foreign file: each is one CheckpointError saying which.
TEST(CheckpointFile, RefusesTruncatedCorruptForeignAndOldFiles) {
  const std::string good = encode_checkpoint(small_checkpoint());
  for (std::size_t n = 0; n < good.size(); ++n) EXPECT_THROW(decode_checkpoint(good.substr(0, n), "f"), CheckpointError) << n;
  for (std::size_t byte = 0; byte < good.size(); ++byte) {
    std::string bad = good;
    bad[byte] = static_cast<char>(bad[byte] ^ (1 << (byte % 8)));
    EXPECT_THROW(decode_checkpoint(bad, "f"), CheckpointError) << byte;
  }
  auto message = [](const std::string& bytes) {
    try {
      decode_checkpoint(bytes, "run/checkpoint.bin");
    } catch (const CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_CONTAINS(message("time,clusters\n0,10\n"), "run/checkpoint.bin: not a ballagg checkpoint");
  EXPECT_CONTAINS(message(good.substr(0, good.size() - 10)), "truncated");
  std::string old = good;
  old[16] = 0;  // format version 0 (the little-endian low byte of the version)
  EXPECT_CONTAINS(message(old), "checkpoint format 0, this ballagg reads format 2 only");
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_CONTAINS(message(flipped), "corrupt (checksum mismatch)");
}

// ---- the command line: signals, SIGKILL, resume ---------------------------------------

// Starts the ballagg binary with `args` (stdout and stderr to files in `dir`).
pid_t spawn_ballagg(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<std::string> all{BALLAGG_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, all[0].c_str(), &files, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&files);
  return pid;
}

int wait_status(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int run_ballagg(const std::vector<std::string>& args, const std::filesystem::path& log) {
  return wait_status(spawn_ballagg(args, log));
}

// Starts a run, waits for its first checkpoint, lets it go on for a random while and
// sends `signal`. Returns false if the run finished first.
bool interrupt_run(const std::vector<std::string>& args, const std::filesystem::path& dir, int signal,
                   std::mt19937& random, int* status = nullptr) {
  const pid_t pid = spawn_ballagg(args, dir.string() + ".log");
  const auto checkpoint = dir / kCheckpointFile;
  for (int k = 0; k < 4000 && !std::filesystem::exists(checkpoint); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const int delay_ms = std::uniform_int_distribution<int>(0, 150)(random);
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  const bool finished = std::filesystem::exists(dir / "summary.json");
  kill(pid, signal);
  const int s = wait_status(pid);
  if (status) *status = s;
  return !finished && !std::filesystem::exists(dir / "summary.json");
}

std::vector<std::string> run_args(const std::string& out, std::vector<std::string> sets) {
  std::vector<std::string> args{"run", "--quiet", "--out", out, "--set", "output.checkpoint_every=0.03"};
  for (const std::string& s : sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  return args;
}

template <int D>
void expect_same_h5md_frames(const std::filesystem::path& a, const std::filesystem::path& b) {
  const H5mdReader<D> x(a.string()), y(b.string());
  ASSERT_EQ(x.frames(), y.frames());
  for (int k = 0; k < x.frames(); ++k) {
    const Frame<D> f = x.frame(k), g = y.frame(k);
    EXPECT_EQ(f.time, g.time);
    EXPECT_EQ(f.step, g.step);
    EXPECT_EQ(f.position, g.position) << "frame " << k;
    EXPECT_EQ(f.velocity, g.velocity) << "frame " << k;
    EXPECT_EQ(f.cluster, g.cluster) << "frame " << k;
  }
}

// `text` with every occurrence of `dir` removed.
std::string without(std::string text, const std::string& dir) {
  for (std::size_t at; (at = text.find(dir)) != std::string::npos;) text.erase(at, dir.size());
  return text;
}

// Every output file of the run directory `run` as the reference run's, byte for byte (the
// H5MD trajectory frame by frame; summary.json has wall times), and no checkpoint or
// temporary trajectory left.
template <int D>
void expect_same_outputs(const std::filesystem::path& reference, const std::filesystem::path& run, bool trajectory) {
  int compared = 0;
  for (const auto& entry : std::filesystem::directory_iterator(reference)) {
    const std::string f = entry.path().filename().string();
    if (f == "summary.json" || f == "trajectory.h5md") continue;
    // analysis.json names the run directory's final.csv: the directories' names differ.
    EXPECT_TRUE(without(read_file(entry.path()), reference.string()) == without(read_file(run / f), run.string()))
        << f << " differs";
    ++compared;
  }
  EXPECT_GE(compared, trajectory ? 5 : 4);  // final.csv, final.xyz, timeseries.csv, config.toml (, trajectory.xyz)
  if (trajectory) expect_same_h5md_frames<D>(reference / "trajectory.h5md", run / "trajectory.h5md");
  EXPECT_FALSE(std::filesystem::exists(run / kCheckpointFile));  // finished: removed
  EXPECT_FALSE(std::filesystem::exists(run / ".trajectory.h5md.tmp"));
  EXPECT_FALSE(std::filesystem::exists(run / ".trajectory.xyz.tmp"));
}

// The test: SIGKILL at a random moment (after the first checkpoint), resume, and
// every output file as the uninterrupted run's. The random delay's seed is printed, so a
// failure can be replayed.
template <int D = 2>
void expect_killed_run_resumes_identically(const std::vector<std::string>& sets, bool trajectory) {
  TempDir tmp;
  std::random_device seed;
  const unsigned s = seed();
  SCOPED_TRACE("delay seed " + std::to_string(s));
  std::mt19937 random(s);
  const std::string ref = (tmp / "reference").string(), run = (tmp / "killed").string();
  ASSERT_EQ(run_ballagg(run_args(ref, sets), tmp / "reference.log"), 0) << read_file(tmp / "reference.log");
  bool killed = false;
  for (int attempt = 0; attempt < 3 && !killed; ++attempt) {
    std::filesystem::remove_all(run);
    killed = interrupt_run(run_args(run, sets), run, SIGKILL, random);
  }
  ASSERT_TRUE(killed) << "the run always finished before it could be killed";
  ASSERT_EQ(run_ballagg({"run", "--quiet", "--resume", run}, tmp / "resume.log"), 0) << read_file(tmp / "resume.log");
  expect_same_outputs<D>(ref, run, trajectory);
}

TEST(CheckpointCli, EventDrivenKilledAtRandomResumesIdentically) {
  expect_killed_run_resumes_identically({"system.n=10000", "output.snapshot_every=25",
                                         "output.snapshot_formats=[\"h5md\", \"xyz\"]"}, true);
}

// 10^4 discs: about 0.5 s in Release, so that the kill (at most 150 ms after the first
// checkpoint, 0.03 s in) comes before the end (1500 discs took 0.05 s once small loops ran
// on one thread, and the run finished before it could be killed).
TEST(CheckpointCli, TimeSteppingKilledAtRandomResumesIdentically) {
  expect_killed_run_resumes_identically({"engine.kind=\"ts\"", "system.n=10000", "stop.clusters=20",
                                         "output.snapshot_every=5", "output.snapshot_formats=[\"h5md\", \"xyz\"]"},
                                        true);
}

// The last instants of a run: its trajectories complete and renamed into place, summary.json
// not yet written, the checkpoint not yet removed. A kill there (seen once in `make test`,
// with the random kill above) left a run that could not be resumed ("the trajectory of the
// checkpointed run is missing"). Made here exactly: the finished reference run's directory
// without its summary.json, and a checkpoint of the same run taken earlier.
TEST(CheckpointCli, KilledAfterItsTrajectoriesWereCompletedResumesIdentically) {
  TempDir tmp;
  const std::vector<std::string> sets{"system.n=10000", "output.snapshot_every=25",
                                      "output.snapshot_formats=[\"h5md\", \"xyz\"]"};
  const std::string ref = (tmp / "reference").string(), run = (tmp / "killed").string();
  ASSERT_EQ(run_ballagg(run_args(ref, sets), tmp / "reference.log"), 0) << read_file(tmp / "reference.log");
  std::mt19937 random(7);
  ASSERT_TRUE(interrupt_run(run_args(run, sets), run, SIGKILL, random)) << "the run finished before it was killed";
  const std::filesystem::path window = tmp / "window";
  std::filesystem::copy(ref, window);
  std::filesystem::remove(window / "summary.json");
  std::filesystem::copy_file(tmp / "killed" / kCheckpointFile, window / kCheckpointFile);
  ASSERT_EQ(run_ballagg({"run", "--quiet", "--resume", window.string()}, tmp / "resume.log"), 0)
      << read_file(tmp / "resume.log");
  expect_same_outputs<2>(ref, window, true);
}

// Model (v)'s physics (rotating aggregates, energy threshold, Bridges restitution) on a
// smaller gas, with trajectories (frames at exact times between events) and the analysis
// files written at the end.
TEST(CheckpointCli, RigidBodyKilledAtRandomResumesIdentically) {
  expect_killed_run_resumes_identically<3>(
      {"engine.kind=\"rigid-body\"", "system.dimension=3", "system.n=1500", "system.box_length=10", "system.radius=0.033",
       "system.boundary=\"periodic\"", "initial.positions=\"random\"", "initial.velocities=\"gaussian\"",
       "initial.speed=10", "initial.zero_momentum=true", "collision.outcome=\"energy-threshold\"",
       "collision.restitution_law=\"bridges\"", "collision.velocity_unit=0.01", "stop.time=4",
       "output.timeseries_interval=0.2", "output.snapshot_every=1", "output.snapshot_formats=[\"h5md\", \"xyz\"]"},
      true);
}

// The fragmentation threshold taken from the initial energy: a resumed run keeps the
// threshold of its start (saved with the configuration), not one from the energy at the
// checkpoint, which collisions have lowered.
TEST(CheckpointCli, RigidBodyWithInitialEnergyFragmentationResumesIdentically) {
  expect_killed_run_resumes_identically<3>(
      {"engine.kind=\"rigid-body\"", "system.dimension=3", "system.n=1500", "system.box_length=10", "system.radius=0.033",
       "system.boundary=\"periodic\"", "initial.positions=\"random\"", "initial.velocities=\"gaussian\"",
       "initial.speed=10", "initial.zero_momentum=true", "collision.outcome=\"energy-threshold\"",
       "collision.restitution_law=\"bridges\"", "collision.velocity_unit=0.01",
       "collision.fragmentation=\"initial-energy\"", "stop.time=8"},
      false);
}

// SIGTERM (and SIGINT) write a checkpoint, say how to resume, exit with 128 + signal.
TEST(CheckpointCli, SigtermWritesCheckpointAndSaysHowToResume) {
  TempDir tmp;
  const std::string run = (tmp / "run").string();
  std::vector<std::string> args{"run", "--quiet", "--out", run, "--set", "system.n=30000"};
  // checkpoint_every = 0: the only checkpoint is the one the signal asks for.
  args.insert(args.end(), {"--set", "output.checkpoint_every=0"});
  const pid_t pid = spawn_ballagg(args, tmp / "run.log");
  // The signal handlers are installed once the input is checked and the run directory
  // made (a signal before that ends the program as any other would): wait for the
  // directory, however slow the start (a sanitizer build), then let the run go on a little.
  for (int k = 0; k < 10000 && !std::filesystem::exists(run); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kill(pid, SIGTERM);
  const int status = wait_status(pid);
  const std::string log = read_file(tmp / "run.log");
  if (std::filesystem::exists(tmp / "run" / "summary.json")) GTEST_SKIP() << "finished before the signal";
  EXPECT_EQ(status, 128 + SIGTERM) << log;
  EXPECT_CONTAINS(log, "interrupted by SIGTERM");
  EXPECT_CONTAINS(log, "ballagg run --resume " + run);
  ASSERT_TRUE(std::filesystem::exists(tmp / "run" / kCheckpointFile));
  ASSERT_EQ(run_ballagg({"run", "--quiet", "--resume", run}, tmp / "resume.log"), 0) << read_file(tmp / "resume.log");
  ASSERT_EQ(run_ballagg({"run", "--quiet", "--out", (tmp / "ref").string(), "--set", "system.n=30000", "--set",
                         "output.checkpoint_every=0"}, tmp / "ref.log"), 0);
  EXPECT_TRUE(read_file(tmp / "ref" / "final.csv") == read_file(tmp / "run" / "final.csv"));
}

// A bad checkpoint on the command line: one line, exit status 2, nothing changed.
TEST(CheckpointCli, BadCheckpointIsOneLineAndExitStatus2) {
  TempDir tmp;
  std::filesystem::create_directories(tmp / "run");
  auto resume_message = [&](const std::string& content) {
    tmp.write("run/checkpoint.bin", content);
    EXPECT_EQ(run_ballagg({"run", "--resume", (tmp / "run").string()}, tmp / "log"), 2);
    return read_file(tmp / "log");
  };
  EXPECT_CONTAINS(resume_message("[system]\nn = 3\n"), "checkpoint.bin: not a ballagg checkpoint");
  const std::string good = encode_checkpoint(small_checkpoint());
  const std::string cut = resume_message(good.substr(0, good.size() / 2));
  EXPECT_CONTAINS(cut, "truncated");
  EXPECT_EQ(std::count(cut.begin(), cut.end(), '\n'), 1) << cut;
  std::filesystem::remove(tmp / "run" / "checkpoint.bin");
  EXPECT_EQ(run_ballagg({"run", "--resume", (tmp / "run").string()}, tmp / "log"), 2);
  EXPECT_CONTAINS(read_file(tmp / "log"), "no checkpoint to resume from");
  EXPECT_EQ(run_ballagg({"run", "--resume", (tmp / "run").string(), "--seed", "3"}, tmp / "log"), 2);
}

}  // namespace
}  // namespace ballagg
