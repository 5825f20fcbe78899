// Finite but extreme values (config/value_ranges.hpp): keys, state-file rows and resolved
// values outside the ranges in which the engines' arithmetic is sound are refused naming
// the key or the file line and column and the allowed range; values at the bounds are
// accepted; the event calendar, the event loop and the cell grid stop with an error
// rather than spinning or indexing with a NaN.
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/value_ranges.hpp"
#include "ballagg/engines/event_driven/bucket_queue.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/spatial/grid_geometry.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

std::string config_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_config_text(text, "run.toml", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected InputError for: " << text;
  return {};
}

TEST(ValueRanges, KeysOutsideTheirRangesAreRefusedWithTheRange) {
  struct Case {
    std::string section, key, value, allowed;
  };
  const std::vector<Case> cases = {
      {"system", "radius", "1e21", "from 1e-20 to 1e+20"},
      {"system", "radius", "1e102", "from 1e-20 to 1e+20"},
      {"system", "radius", "1e155", "from 1e-20 to 1e+20"},
      {"system", "radius", "1e-300", "from 1e-20 to 1e+20"},
      {"system", "mass", "1e307", "from 1e-30 to 1e+30"},
      {"system", "mass", "1e308", "from 1e-30 to 1e+30"},
      {"system", "mass", "1e-31", "from 1e-30 to 1e+30"},
      {"initial", "speed", "1e300", "at most 1e+20"},
      {"initial", "speed", "2e20", "at most 1e+20"},
      {"system", "box_length", "1e27", "at most 1e+26"},
      {"ts", "dt_factor", "1e-300", "at least 1e-09"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.section + "." + c.key + " = " + c.value);
    const std::string m = config_error("[" + c.section + "]\n" + c.key + " = " + c.value + "\n");
    EXPECT_CONTAINS(m, "run.toml:2");
    EXPECT_CONTAINS(m, c.section + "." + c.key + " = ");
    EXPECT_CONTAINS(m, c.allowed);
  }
}

TEST(ValueRanges, TheBoundsThemselvesAreAccepted) {
  for (const std::string text : {"[system]\nradius = 1e-20\nmass = 1e-30\n", "[system]\nradius = 1e20\nmass = 1e30\n",
                                 "[initial]\nspeed = 1e20\n", "[system]\nbox_length = 2e5\n",
                                 "[engine]\nskin = 2e-7\n", "[ts]\ndt_factor = 1e-9\n"}) {
    SCOPED_TRACE(text);
    EXPECT_NO_THROW(parse_config_text(text, "run.toml"));
  }
}

TEST(ValueRanges, ABoxTooLongForTheRadiusIsRefused) {
  const std::string m = config_error("[system]\nbox_length = 3e5\n");
  EXPECT_CONTAINS(m, "run.toml:2: system.box_length = 300000");
  EXPECT_CONTAINS(m, "at most 1e+06 times system.radius = 0.2");
  // Named as given on the command line.
  EXPECT_CONTAINS(config_error("", {"system.box_length=3e5"}), "--set system.box_length");
}

TEST(ValueRanges, AVolumeFractionGivingTooLongABoxIsRefusedWithTheSmallestAllowed) {
  const std::string m = config_error("[system]\nvolume_fraction = 1e-12\n");
  EXPECT_CONTAINS(m, "run.toml:2: system.volume_fraction = 1e-12");
  EXPECT_CONTAINS(m, "with system.n = 2500");
  EXPECT_CONTAINS(m, "must be at least 7.86e-09");
  EXPECT_NO_THROW(parse_config_text("[system]\nvolume_fraction = 7.86e-09\n", "run.toml"));
  // 3D: the box in radii is a cube root, so far smaller fractions still pass.
  EXPECT_NO_THROW(parse_config_text("[system]\ndimension = 3\nvolume_fraction = 1e-12\n", "run.toml"));
}

TEST(ValueRanges, ASkinBelowTheResolutionOrBeyondTenBoxesIsRefused) {
  const std::string tiny = config_error("", {"engine.skin=1e-300"});
  EXPECT_CONTAINS(tiny, "--set engine.skin: engine.skin = 1e-300");
  EXPECT_CONTAINS(tiny, "must be from 2e-07 to");
  const std::string huge = config_error("[engine]\nskin = 1e9\n");
  EXPECT_CONTAINS(huge, "run.toml:2: engine.skin = 1000000000");
  EXPECT_CONTAINS(huge, "10 box lengths");
}

// ---- state files ---------------------------------------------------------------------------

class StateFileRanges : public ::testing::Test {
 protected:
  // The message of the InputError make_initial_state throws for the 2D state `rows`
  // (after a header) in a box of side 10 with the given boundary.
  std::string error_of(const std::string& header, const std::string& rows, Boundary boundary = Boundary::walls,
                       std::optional<double> skin = std::nullopt) const {
    const auto file = dir_.write("state.csv", header + "\n" + rows);
    Config c;
    c.initial.positions = InitialPositions::file;
    c.initial.file = file.string();
    c.system.box_length = 10.0;
    c.system.boundary = boundary;
    c.engine.kind = EngineKind::rigid_body;
    c.engine.skin = skin;
    try {
      make_initial_state<2>(c);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "expected InputError for: " << rows;
    return {};
  }
  std::string file() const { return (dir_ / "state.csv").string(); }

  TempDir dir_;
};

TEST_F(StateFileRanges, RadiiMassesSpeedsAndSpinsOutsideTheirRangesAreRefusedWithTheLineAndColumn) {
  const std::string h = "x,y,vx,vy,radius,mass";
  const std::string ok = "1,1,0,0,0.2,1\n";
  struct Case {
    std::string header, bad_row, needle;
  };
  const std::vector<Case> cases = {
      {h, "5,5,0,0,1e21,1\n", "column radius: 1e+21 is outside [1e-20, 1e+20]"},
      {h, "5,5,0,0,1e-300,1\n", "column radius: 1e-300 is outside [1e-20, 1e+20]"},
      {h, "5,5,0,0,0.2,1e307\n", "column mass: 1e+307 is outside [1e-30, 1e+30]"},
      {h, "5,5,1e308,0,0.2,1\n", "columns vx,vy: the speed 1e+308 is above 1e+20"},
      {h, "5,5,1e300,1e300,0.2,1\n", "columns vx,vy: the speed 1.41421e+300 is above 1e+20"},
      {h + ",wz", "5,5,0,0,0.2,1,1e21\n", "columns wz: the spin 1e+21 times the radius 0.2 is a speed above 1e+20"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.bad_row);
    const std::string first = c.header == h ? ok : "1,1,0,0,0.2,1,0\n";
    const std::string m = error_of(c.header, first + c.bad_row);
    EXPECT_CONTAINS(m, file() + ":3: ");
    EXPECT_CONTAINS(m, c.needle);
  }
}

TEST_F(StateFileRanges, APeriodicCoordinateFarOutsideTheBoxIsRefused) {
  const std::string m = error_of("x,y,vx,vy,radius,mass", "1,1,0,0,0.2,1\n1,25,0,0,0.2,1\n", Boundary::periodic);
  EXPECT_CONTAINS(m, file() + ":3: column y: 25 is more than 1 box length outside [0, 10]");
  // One box length outside is folded into the box.
  const auto path = dir_.write("near.csv", "x,y,vx,vy,radius,mass\n1,1,0,0,0.2,1\n1,-5,0,0,0.2,1\n");
  Config c;
  c.initial.positions = InitialPositions::file;
  c.initial.file = path.string();
  c.system.box_length = 10.0;
  c.system.boundary = Boundary::periodic;
  EXPECT_NEAR(make_initial_state<2>(c).position(1, 0.0)[1], 5.0, 1e-15);
}

TEST_F(StateFileRanges, TheBoxAndTheSkinAreCheckedAgainstTheSmallestRadiusOfTheFile) {
  const std::string h = "x,y,vx,vy,radius,mass";
  const std::string box = error_of(h, "1,1,0,0,0.2,1\n5,5,0,0,1e-6,1\n");
  EXPECT_CONTAINS(box, "system.box_length = 10 is more than 1e+06 times the smallest radius 1e-06 (" + file() + ":3)");
  const std::string skin = error_of(h, "1,1,0,0,0.2,1\n5,5,0,0,0.1,1\n", Boundary::walls, 1e-8);
  EXPECT_CONTAINS(skin, "engine.skin = 1e-08: must be from 1e-07 to 100");
  EXPECT_CONTAINS(skin, file() + ":3");
}

TEST(ValueRanges, APeriodicBoxWithNoRoomForASkinIsRefusedWhenTheDefaultsAreResolved) {
  TempDir dir;
  const auto path = dir.write("two.csv", "x,y,vx,vy,radius,mass\n0.2,0.2,1,0.3,0.2,1\n0.6,0.6,-1,0.5,0.2,1\n");
  Config c;
  c.initial.positions = InitialPositions::file;
  c.initial.file = path.string();
  c.system.boundary = Boundary::periodic;
  c.collision.outcome = CollisionOutcome::bounce;
  c.system.box_length = 0.8000000000000002;  // 4 radii and 2 units in the last place
  const State<2> s = make_initial_state<2>(c);
  try {
    resolve_defaults(c, s);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "system.box_length = 0.8000000000000002: a periodic box must be longer than 4 times");
    EXPECT_CONTAINS(e.what(), "at least 0.80000060606");
  }
  c.system.box_length = 0.8000007;
  EXPECT_NO_THROW(resolve_defaults(c, make_initial_state<2>(c)));
}

// ---- guards: an error, never a loop without end ---------------------------------------------

struct ByKey {
  bool operator()(int a, int b) const { return a < b; }
};

TEST(ValueRanges, TheCalendarRefusesAnEventAtATimeThatIsNotFinite) {
  BucketQueue<ByKey> queue{ByKey{}};
  queue.reset(3);
  queue.update(0, 1.0);
  EXPECT_THROW(queue.update(1, std::numeric_limits<double>::quiet_NaN()), std::logic_error);
  EXPECT_THROW(queue.update(2, std::numeric_limits<double>::infinity()), std::logic_error);
  EXPECT_EQ(queue.top(), 0);
  EXPECT_EQ(queue.size(), 1u);
}

TEST(ValueRanges, ACheckpointedEventAtInfinityIsACorruptCheckpoint) {
  EventCalendar saved;
  saved.reset(1);
  saved.refile(0, {Event{2.0, 0, 0, 1, 0, EventKind::list_rebuild}});
  ByteWriter w;
  saved.save(w);
  std::string bytes = w.take();
  const double inf = std::numeric_limits<double>::infinity();
  std::memcpy(bytes.data() + sizeof(std::uint32_t), &inf, sizeof inf);  // the first event's time
  EventCalendar restored;
  restored.reset(1);
  ByteReader r(bytes, "calendar");
  EXPECT_THROW(restored.restore(r, [](const Event&) {}), CheckpointError);
}

// A core whose events never advance the time, as when the intervals between events fall
// below the resolution of the simulated time.
struct StuckCore {
  EngineCounters count;
  EngineCounters& counters() { return count; }
  std::optional<Event> next_event() { return Event{1.0, 0, 1, 0, 0, EventKind::list_rebuild}; }
  EventRecord handle(const Event& e) { return {.time = e.time, .kind = EventKind::list_rebuild, .cluster = 0}; }
};

TEST(ValueRanges, AnEventLoopWhoseTimeStopsAdvancingEndsWithAnError) {
  Config c;
  c.system.n = 4;
  State<2> s = make_initial_state<2>(c);
  StuckCore core;
  RunObserver<2> quiet;
  try {
    run_event_loop(core, s, StopCriteria{}, quiet);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), "the simulated time stopped advancing at t = 1");
  }
  EXPECT_EQ(core.count.events, kMaxEventsAtInstantPerSphere * 4 + kMaxEventsAtInstantFloor + 1);
  // With a wall-clock limit the limit ends it, as it ends any run.
  StuckCore limited;
  StopCriteria stop;
  stop.wall_seconds = 0.05;
  EXPECT_EQ(run_event_loop(limited, s, stop, quiet).reason, StopReason::wall_seconds);
}

TEST(ValueRanges, ACellGridOverABoxThatIsNotFiniteIsAnError) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(GridGeometry<2>(Box<2>{inf, Boundary::walls}, 1.0, 10), std::logic_error);
  EXPECT_THROW(GridGeometry<3>(Box<3>{10.0, Boundary::walls}, std::nan(""), 10), std::logic_error);
}

// The rigid-body engine at subnormal speeds: wall contacts at +infinity are never filed
// (the calendar would refuse them), and the run ends with no more events.
TEST(ValueRanges, RigidBodiesAtSubnormalSpeedsRunToTheirEnd) {
  TempDir dir;
  const auto path = dir.write("slow.csv", "x,y,vx,vy,radius,mass\n1,1,1e-310,0,0.2,1\n3,1,-1e-310,0,0.2,1\n");
  Config c;
  c.initial.positions = InitialPositions::file;
  c.initial.file = path.string();
  c.system.box_length = 10.0;
  c.engine.kind = EngineKind::rigid_body;
  State<2> s = make_initial_state<2>(c);
  const Config resolved = resolve_defaults(c, s);
  RunObserver<2> quiet;
  const RunResult r = make_engine<2>(resolved)->run(s, stop_criteria(resolved), quiet);
  EXPECT_EQ(r.reason, StopReason::no_more_events);
  EXPECT_EQ(s.time, 0.0);
  EXPECT_TRUE(std::isfinite(s.position(0, s.time)[0]));
}

}  // namespace
}  // namespace ballagg
