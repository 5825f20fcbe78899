// The state file format (initial.file, final.csv): parsing, errors that name the file line,
// assembling a state from the spheres (overlaps, walls, glued clusters, periodic unwrapping)
// and the exact text round trip.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/chunked_text.hpp"
#include "ballagg/io/state_csv.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::Box;
using ballagg::Boundary;
using ballagg::InputError;
using ballagg::SphereTable;
using ballagg::State;
using ballagg::testing::vec;

using ballagg::testing::TempDir;

namespace {

template <int D>
std::string parse_error(const std::string& text, const std::string& source = "in.csv") {
  try {
    ballagg::parse_state_csv<D>(text, source);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError for:\n" << text;
  return {};
}

template <int D>
std::string assemble_error(const std::string& text, double box_length, Boundary boundary) {
  const SphereTable<D> t = ballagg::parse_state_csv<D>(text, "in.csv");
  try {
    ballagg::assemble_state<D>(Box<D>{box_length, boundary}, t);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError for:\n" << text;
  return {};
}

template <int D>
State<D> assemble(const std::string& text, double box_length, Boundary boundary) {
  return ballagg::assemble_state<D>(Box<D>{box_length, boundary}, ballagg::parse_state_csv<D>(text, "in.csv"));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Parsing

TEST(StateCsv, Parses2DColumnsInTheDocumentedOrder) {
  const SphereTable<2> t = ballagg::parse_state_csv<2>(
      "x,y,vx,vy,radius,mass\n1,2,0.5,-0.5,0.25,3\n4.5,6e-1,0,0,1,1\n", "a.csv");
  ASSERT_EQ(t.radius.size(), 2u);
  EXPECT_EQ(t.position[0], vec<2>(1, 2));
  EXPECT_EQ(t.velocity[0], vec<2>(0.5, -0.5));
  EXPECT_EQ(t.radius[0], 0.25);
  EXPECT_EQ(t.mass[0], 3.0);
  EXPECT_EQ(t.position[1], vec<2>(4.5, 0.6));
  EXPECT_TRUE(t.cluster.empty());
  EXPECT_EQ(t.line, (std::vector<int>{2, 3}));
  EXPECT_EQ(t.source, "a.csv");
}

TEST(StateCsv, ColumnsMayComeInAnyOrder3D) {
  const SphereTable<3> t = ballagg::parse_state_csv<3>(
      "cluster,mass,vz,z,radius,vy,y,vx,x\n7,2,-3,3,0.5,-2,2,-1,1\n", "b.csv");
  ASSERT_EQ(t.radius.size(), 1u);
  EXPECT_EQ(t.position[0], vec<3>(1, 2, 3));
  EXPECT_EQ(t.velocity[0], vec<3>(-1, -2, -3));
  EXPECT_EQ(t.radius[0], 0.5);
  EXPECT_EQ(t.mass[0], 2.0);
  EXPECT_EQ(t.cluster, (std::vector<std::int64_t>{7}));
}

TEST(StateCsv, CommentsBlankLinesAndSpacesAreSkippedAndLinesCounted) {
  const std::string text =
      "# a state\n"
      "\n"
      " x , y ,vx,vy,radius,mass,cluster\n"
      "# first sphere\n"
      "1, 1, 0, 0, 0.5, 1, -4\n"
      "   \n"
      "\t3,1,0,0,0.5,1,-4\t\n";
  const SphereTable<2> t = ballagg::parse_state_csv<2>(text, "c.csv");
  ASSERT_EQ(t.radius.size(), 2u);
  EXPECT_EQ(t.line, (std::vector<int>{5, 7}));
  EXPECT_EQ(t.position[1], vec<2>(3, 1));
  EXPECT_EQ(t.cluster, (std::vector<std::int64_t>{-4, -4}));
}

TEST(StateCsv, CrlfLineEndingsAreAccepted) {
  const SphereTable<2> t =
      ballagg::parse_state_csv<2>("x,y,vx,vy,radius,mass,cluster\r\n1,2,3,4,0.5,1,0\r\n\r\n5,6,7,8,0.5,2,1\r\n", "d.csv");
  ASSERT_EQ(t.radius.size(), 2u);
  EXPECT_EQ(t.mass[1], 2.0);
  EXPECT_EQ(t.cluster, (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(t.line, (std::vector<int>{2, 4}));
}

TEST(StateCsv, LastLineWithoutNewlineIsRead) {
  const SphereTable<2> t = ballagg::parse_state_csv<2>("x,y,vx,vy,radius,mass\n1,2,3,4,0.5,1", "e.csv");
  ASSERT_EQ(t.radius.size(), 1u);
  EXPECT_EQ(t.velocity[0], vec<2>(3, 4));
}

TEST(StateCsv, ReadStateCsvReadsAFile) {
  TempDir dir;
  const fs::path p = dir.path() / "s.csv";
  std::ofstream(p) << "x,y,z,vx,vy,vz,radius,mass\n1,2,3,0,0,0,0.5,1\n";
  const SphereTable<3> t = ballagg::read_state_csv<3>(p.string());
  ASSERT_EQ(t.radius.size(), 1u);
  EXPECT_EQ(t.source, p.string());
  EXPECT_EQ(t.position[0], vec<3>(1, 2, 3));
}

// ---------------------------------------------------------------------------------------
// Parse errors

TEST(StateCsv, UnknownColumnNamesLineAndExpectedColumns) {
  const std::string m = parse_error<2>("# header next\nx,y,vx,vy,rad,mass\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "unknown column 'rad'");
  EXPECT_CONTAINS(m, "x,y,vx,vy,radius,mass,cluster");
}

TEST(StateCsv, ZColumnIn2DIsAnErrorThatMentionsTheDimension) {
  const std::string m = parse_error<2>("x,y,z,vx,vy,vz,radius,mass\n1,2,3,0,0,0,0.5,1\n");
  EXPECT_CONTAINS(m, "in.csv:1");
  EXPECT_CONTAINS(m, "'z'");
  EXPECT_CONTAINS(m, "system.dimension = 2");
}

TEST(StateCsv, DuplicateColumnNamesLineAndColumn) {
  const std::string m = parse_error<2>("\nx,y,vx,vy,radius,mass,x\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "column 'x' appears twice");
}

TEST(StateCsv, MissingColumnNamesLineAndColumn) {
  const std::string m = parse_error<3>("x,y,z,vx,vy,vz,mass\n");
  EXPECT_CONTAINS(m, "in.csv:1");
  EXPECT_CONTAINS(m, "missing column 'radius'");
  EXPECT_CONTAINS(m, "x,y,z,vx,vy,vz,radius,mass,cluster");
}

TEST(StateCsv, MissingZColumnIn3DIsReported) {
  const std::string m = parse_error<3>("x,y,vx,vy,radius,mass\n");
  EXPECT_CONTAINS(m, "in.csv:1");
  EXPECT_CONTAINS(m, "missing column 'z'");
}

TEST(StateCsv, WrongFieldCountNamesLine) {
  std::string m = parse_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n2,2,0,0,0.5\n");
  EXPECT_CONTAINS(m, "in.csv:3");
  EXPECT_CONTAINS(m, "5 fields");
  EXPECT_CONTAINS(m, "header has 6");
  m = parse_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1,9\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "7 fields");
}

TEST(StateCsv, NonNumericFieldNamesLineAndColumn) {
  for (const std::string bad : {"abc", "1.5x", "", "0x10", "1 2", "+-1"}) {
    SCOPED_TRACE("'" + bad + "'");
    const std::string m = parse_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n\n2,2,0," + bad + ",0.5,1\n");
    EXPECT_CONTAINS(m, "in.csv:4");
    EXPECT_CONTAINS(m, "column vy");
    EXPECT_CONTAINS(m, "is not a number");
  }
}

TEST(StateCsv, NonFiniteFieldIsAnError) {
  for (const std::string bad : {"nan", "inf", "-inf", "NaN", "1e999"}) {
    const std::string m = parse_error<2>("x,y,vx,vy,radius,mass\n" + bad + ",1,0,0,0.5,1\n");
    SCOPED_TRACE(bad);
    EXPECT_CONTAINS(m, "in.csv:2");
    EXPECT_CONTAINS(m, "column x");
  }
}

TEST(StateCsv, RadiusAndMassMustBePositive) {
  std::string m = parse_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0,1\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "radius");
  EXPECT_CONTAINS(m, "must be > 0");
  m = parse_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,-0.5,1\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "radius");
  m = parse_error<3>("x,y,z,vx,vy,vz,radius,mass\n1,1,1,0,0,0,0.5,1\n1,1,4,0,0,0,0.5,0\n");
  EXPECT_CONTAINS(m, "in.csv:3");
  EXPECT_CONTAINS(m, "mass");
  EXPECT_CONTAINS(m, "must be > 0");
  m = parse_error<3>("x,y,z,vx,vy,vz,radius,mass\n1,1,1,0,0,0,0.5,-2\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "mass");
}

TEST(StateCsv, NonIntegerClusterIdIsAnError) {
  for (const std::string bad : {"1.5", "a", "", "1e3", "99999999999999999999"}) {
    const std::string m = parse_error<2>("x,y,vx,vy,radius,mass,cluster\n1,1,0,0,0.5,1," + bad + "\n");
    SCOPED_TRACE(bad);
    EXPECT_CONTAINS(m, "in.csv:2");
    EXPECT_CONTAINS(m, "column cluster");
    EXPECT_CONTAINS(m, "not an integer");
  }
}

TEST(StateCsv, EmptyFileIsAnError) {
  for (const std::string text : {"", "\n\n", "# only a comment\n", "\r\n"}) {
    const std::string m = parse_error<2>(text);
    EXPECT_CONTAINS(m, "in.csv");
    EXPECT_CONTAINS(m, "empty file");
    EXPECT_CONTAINS(m, "x,y,vx,vy,radius,mass");
  }
}

TEST(StateCsv, HeaderOnlyIsAnErrorNamingTheHeaderLine) {
  const std::string m = parse_error<2>("# c\nx,y,vx,vy,radius,mass\n# nothing else\n\n");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "no spheres");
}

TEST(StateCsv, ParseErrorsAreOneLine) {
  const std::vector<std::string> messages = {
      parse_error<2>(""), parse_error<2>("x,y\n"), parse_error<2>("x,y,vx,vy,radius,mass\n1,1\n"),
      parse_error<2>("x,y,vx,vy,radius,mass\r\n1,b,0,0,1,1\r\n"), parse_error<2>("x,y,vx,vy,radius,mass,q\r\n")};
  for (const std::string& m : messages) {
    EXPECT_FALSE(m.empty());
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.find('\r'), std::string::npos) << m;
  }
}

TEST(StateCsv, MissingFileIsAnErrorNamingTheFile) {
  TempDir dir;
  const std::string missing = (dir.path() / "nope.csv").string();
  try {
    ballagg::read_state_csv<2>(missing);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), missing);
    EXPECT_CONTAINS(e.what(), "cannot read");
  }
}

TEST(StateCsv, DirectoryIsAnUnreadableFileNotAnEmptyOne) {
  TempDir dir;
  try {
    ballagg::read_state_csv<2>(dir.path().string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), dir.path().string());
    EXPECT_CONTAINS(e.what(), "cannot read");
  }
}

// ---------------------------------------------------------------------------------------
// assemble_state

TEST(StateCsv, AssembledStateHasTheFileSpheres) {
  const State<2> s = assemble<2>("x,y,vx,vy,radius,mass\n1,1,0.5,0,0.5,2\n3,1,-0.5,0,0.25,1\n", 5.0, Boundary::walls);
  ASSERT_EQ(s.n_spheres(), 2);
  EXPECT_EQ(s.n_clusters(), 2);
  EXPECT_EQ(s.position(0, 0.0), vec<2>(1, 1));
  EXPECT_EQ(s.position(1, 0.0), vec<2>(3, 1));
  EXPECT_EQ(s.velocity(0), vec<2>(0.5, 0));
  EXPECT_EQ(s.spheres.radius[1], 0.25);
  EXPECT_EQ(s.spheres.mass[0], 2.0);
}

TEST(StateCsv, OverlappingSpheresNameBothLines) {
  const std::string m = assemble_error<2>(
      "x,y,vx,vy,radius,mass\n# spheres\n1,1,0,0,0.5,1\n4,4,0,0,0.5,1\n1.9,1,0,0,0.5,1\n", 10.0, Boundary::walls);
  EXPECT_CONTAINS(m, "in.csv:3");
  EXPECT_CONTAINS(m, "line 5");
  EXPECT_CONTAINS(m, "overlap");
}

TEST(StateCsv, OverlapAcrossAPeriodicFaceIsDetected) {
  const std::string m = assemble_error<3>(
      "x,y,z,vx,vy,vz,radius,mass\n0.2,5,5,0,0,0,0.5,1\n9.9,5,5,0,0,0,0.5,1\n", 10.0, Boundary::periodic);
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "line 3");
  EXPECT_CONTAINS(m, "overlap");
}

TEST(StateCsv, TouchingSpheresAreNotAnOverlap) {
  const State<2> s = assemble<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n2,1,0,0,0.5,1\n", 10.0, Boundary::walls);
  EXPECT_EQ(s.n_spheres(), 2);
}

TEST(StateCsv, SphereOutsideTheWallsIsAnError) {
  std::string m = assemble_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n9.7,5,0,0,0.5,1\n", 10.0, Boundary::walls);
  EXPECT_CONTAINS(m, "in.csv:3");
  EXPECT_CONTAINS(m, "does not fit");
  EXPECT_CONTAINS(m, "[0, 10]");
  m = assemble_error<3>("x,y,z,vx,vy,vz,radius,mass\n5,5,-1,0,0,0,0.5,1\n", 10.0, Boundary::walls);
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "does not fit");
}

TEST(StateCsv, SphereOutsideAPeriodicBoxIsFoldedIn) {
  const State<2> s = assemble<2>("x,y,vx,vy,radius,mass\n12,-1,0,0,0.5,1\n", 10.0, Boundary::periodic);
  EXPECT_NEAR(s.position(0, 0.0)[0], 2.0, 1e-12);
  EXPECT_NEAR(s.position(0, 0.0)[1], 9.0, 1e-12);
}

TEST(StateCsv, GluedSpheresWithDifferentVelocitiesNameBothLines) {
  const std::string m = assemble_error<2>(
      "x,y,vx,vy,radius,mass,cluster\n1,1,1,0,0.5,1,3\n5,5,0,0,0.5,1,4\n2,1,1,0.5,0.5,1,3\n", 10.0, Boundary::walls);
  EXPECT_CONTAINS(m, "in.csv:4");
  EXPECT_CONTAINS(m, "in.csv:2");
  EXPECT_CONTAINS(m, "glued");
  EXPECT_EQ(m.find('\n'), std::string::npos);
}

TEST(StateCsv, GluedSpheresMoveAsOneCluster) {
  const State<2> s = assemble<2>(
      "x,y,vx,vy,radius,mass,cluster\n1,1,1,-1,0.5,1,8\n5,5,0,0,0.5,1,2\n2,1,1,-1,0.5,3,8\n", 10.0, Boundary::walls);
  EXPECT_EQ(s.n_clusters(), 2);
  EXPECT_EQ(s.largest_cluster(), 2);
  EXPECT_EQ(s.spheres.cluster[0], s.spheres.cluster[2]);
  EXPECT_NE(s.spheres.cluster[0], s.spheres.cluster[1]);
  EXPECT_EQ(s.cluster_of(0).mass, 4.0);
  EXPECT_EQ(s.velocity(2), vec<2>(1, -1));
}

TEST(StateCsv, PeriodicBoxShorterThanFourLargestRadiiIsAnError) {
  const std::string m =
      assemble_error<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n0.5,0.5,0,0,1,1\n", 3.9, Boundary::periodic);
  EXPECT_CONTAINS(m, "system.box_length = 3.9");
  EXPECT_CONTAINS(m, "4 times the largest radius (1)");
  // The same spheres fit in a box longer than 4 R_max.
  EXPECT_NO_THROW(assemble<2>("x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n3,3,0,0,1,1\n", 4.1, Boundary::periodic));
}

TEST(StateCsv, GluedPairStraddlingAPeriodicFaceIsUnwrapped) {
  // Two touching spheres glued across the face x = 0 = L.
  const State<2> s = assemble<2>(
      "x,y,vx,vy,radius,mass,cluster\n9.7,5,0.25,0,0.3,1,0\n0.3,5,0.25,0,0.3,1,0\n", 10.0, Boundary::periodic);
  ASSERT_EQ(s.n_clusters(), 1);
  const ballagg::Vec<2> rel = s.unwrapped_position(1, 0.0) - s.unwrapped_position(0, 0.0);
  EXPECT_NEAR(rel[0], 0.6, 1e-12);
  EXPECT_NEAR(rel[1], 0.0, 1e-12);
  EXPECT_NEAR((s.spheres.offset[1] - s.spheres.offset[0])[0], 0.6, 1e-12);
  // The body extent is that of the pair, not of the whole box.
  const auto& k = s.extent(s.spheres.cluster[0]);
  EXPECT_NEAR(k.hi[0] - k.lo[0], 1.2, 1e-12);
  // Folded positions are those of the file.
  EXPECT_NEAR(s.position(0, 0.0)[0], 9.7, 1e-12);
  EXPECT_NEAR(s.position(1, 0.0)[0], 0.3, 1e-12);
}

TEST(StateCsv, GluedChainLongerThanHalfThePeriodicBoxIsUnwrappedAlongTheChain) {
  // Seven spheres along x from 7 to 13 (folded: 7, 8, 9, 0, 1, 2, 3) in a box of 10,
  // listed out of order; the one at 12 also sits across the y face. The minimum image of
  // the far ends would be 4 apart, not 6: only following the chain gives the true shape.
  // Relative to the first sphere listed (x = 1, unwrapped 11) they are at -4 ... +2.
  const std::string text =
      "x,y,vx,vy,radius,mass,cluster\n"
      "1,9.8,0,1,0.5,1,5\n"
      "8,9.8,0,1,0.5,1,5\n"
      "3,9.8,0,1,0.5,1,5\n"
      "0,9.8,0,1,0.5,1,5\n"
      "5,4,0,0,0.5,1,6\n"
      "7,9.8,0,1,0.5,1,5\n"
      "9,9.8,0,1,0.5,1,5\n"
      "2,0.3,0,1,0.5,1,5\n";  // this one is also across the y face: 9.8 + 0.5 = 10.3
  State<2> s = assemble<2>(text, 10.0, Boundary::periodic);
  ASSERT_EQ(s.n_clusters(), 2);
  const int root = 0;  // x = 1
  const double expected_dx[] = {0, -3, 2, -1, 0, -4, -2, 1};
  for (int i : {0, 1, 2, 3, 5, 6, 7}) {
    const ballagg::Vec<2> rel = s.unwrapped_position(i, 0.0) - s.unwrapped_position(root, 0.0);
    EXPECT_NEAR(rel[0], expected_dx[i], 1e-12) << "sphere " << i;
  }
  const ballagg::Vec<2> rel7 = s.unwrapped_position(7, 0.0) - s.unwrapped_position(root, 0.0);
  EXPECT_NEAR(rel7[1], 0.5, 1e-12);
  const auto& k = s.extent(s.spheres.cluster[0]);
  EXPECT_NEAR(k.hi[0] - k.lo[0], 7.0, 1e-12);
  EXPECT_NEAR(k.hi[1] - k.lo[1], 1.5, 1e-12);
  EXPECT_EQ(ballagg::testing::worst_overlap(s) <= 1e-12, true);
}

TEST(StateCsv, GluedClusterAcrossACornerIn3DIsUnwrapped) {
  const std::string text =
      "x,y,z,vx,vy,vz,radius,mass,cluster\n"
      "9.6,9.6,9.6,1,1,1,0.4,1,0\n"
      "0.4,9.6,9.6,1,1,1,0.4,1,0\n"
      "0.4,0.4,9.6,1,1,1,0.4,1,0\n"
      "0.4,0.4,0.4,1,1,1,0.4,1,0\n";
  const State<3> s = assemble<3>(text, 10.0, Boundary::periodic);
  ASSERT_EQ(s.n_clusters(), 1);
  const ballagg::Vec<3> expected[] = {vec<3>(0, 0, 0), vec<3>(0.8, 0, 0), vec<3>(0.8, 0.8, 0), vec<3>(0.8, 0.8, 0.8)};
  for (int i = 0; i < 4; ++i) {
    const ballagg::Vec<3> rel = s.unwrapped_position(i, 0.0) - s.unwrapped_position(0, 0.0);
    EXPECT_NEAR((rel - expected[i]).norm(), 0.0, 1e-12) << "sphere " << i;
  }
}

TEST(StateCsv, AssembleErrorsUseSphereIndexWithoutLineNumbers) {
  SphereTable<2> t;
  t.position = {vec<2>(1, 1), vec<2>(1.5, 1)};
  t.velocity = {vec<2>(0, 0), vec<2>(0, 0)};
  t.radius = {0.5, 0.5};
  t.mass = {1, 1};
  try {
    ballagg::assemble_state<2>(Box<2>{10.0, Boundary::walls}, t);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "sphere 0");
    EXPECT_CONTAINS(e.what(), "sphere 1");
  }
}

// ---------------------------------------------------------------------------------------
// Round trip: state -> text -> parse -> assemble -> the same text

namespace {

// A state with glued clusters: a small random system run until a quarter of its clusters
// remain, so positions and velocities are arbitrary doubles and clusters may straddle
// periodic faces.
template <int D>
State<D> aggregated_state(Boundary boundary, std::uint64_t seed) {
  const ballagg::Config c = ballagg::testing::small_config(D, 60, D == 2 ? 0.3 : 0.15, boundary, seed);
  State<D> s = ballagg::make_initial_state<D>(c);
  ballagg::StopCriteria stop;
  stop.clusters = 15;
  ballagg::testing::run_engine(s, "ed", {}, stop);
  return s;
}

template <int D>
void expect_round_trip(const State<D>& s) {
  const std::string text = ballagg::state_csv_text(s);
  const SphereTable<D> t = ballagg::parse_state_csv<D>(text, "final.csv");
  ASSERT_EQ(static_cast<int>(t.radius.size()), s.n_spheres());
  const State<D> back = ballagg::assemble_state<D>(s.box, t);
  EXPECT_EQ(back.n_clusters(), s.n_clusters());
  EXPECT_EQ(back.largest_cluster(), s.largest_cluster());
  EXPECT_EQ(ballagg::state_csv_text(back), text);
}

}  // namespace

TEST(StateCsv, RoundTripIsExact2DWalls) {
  const State<2> s = aggregated_state<2>(Boundary::walls, 3);
  ASSERT_LT(s.n_clusters(), s.n_spheres());
  expect_round_trip(s);
}

TEST(StateCsv, RoundTripIsExact2DPeriodic) {
  const State<2> s = aggregated_state<2>(Boundary::periodic, 4);
  ASSERT_LT(s.n_clusters(), s.n_spheres());
  expect_round_trip(s);
}

TEST(StateCsv, RoundTripIsExact3DWalls) {
  const State<3> s = aggregated_state<3>(Boundary::walls, 5);
  ASSERT_LT(s.n_clusters(), s.n_spheres());
  expect_round_trip(s);
}

TEST(StateCsv, RoundTripIsExact3DPeriodic) {
  const State<3> s = aggregated_state<3>(Boundary::periodic, 6);
  ASSERT_LT(s.n_clusters(), s.n_spheres());
  expect_round_trip(s);
}

TEST(StateCsv, RoundTripOfAHandBuiltStraddlingCluster) {
  using ballagg::testing::Ball;
  const State<2> s = ballagg::testing::make_state<2>(
      10.0, Boundary::periodic,
      {Ball<2>{vec<2>(9.7, 5), vec<2>(0.1, 0.3), 0.3, 1.0, 1}, Ball<2>{vec<2>(0.3, 5), vec<2>(0.1, 0.3), 0.3, 1.0, 1},
       Ball<2>{vec<2>(0.3, 5.6), vec<2>(0.1, 0.3), 0.3, 1.0, 1}, Ball<2>{vec<2>(5, 5), vec<2>(-1, 0), 0.4, 2.0, 7}});
  expect_round_trip(s);
}

// Assembling from a table that is given away (its positions become the offsets in place)
// gives the state that assembling from a copy gives, bit for bit: glued clusters whose
// first sphere lies beyond L/2 (its own body position moves by a period, the others' are
// taken relative to where it was) and single spheres on both sides of L/2.
TEST(StateCsv, AssemblingFromAGivenTableEqualsAssemblingFromACopy) {
  const SphereTable<2> t = ballagg::parse_state_csv<2>(
      "x,y,vx,vy,radius,mass,cluster\n"
      "9.7,5,0.1,0.3,0.3,1,4\n0.3,5,0.1,0.3,0.3,1,4\n0.3,5.6,0.1,0.3,0.3,1,4\n"
      "7.5,8.5,-1,0,0.4,2,9\n2.5,1.5,0.5,0.5,0.3,1,11\n6,9.7,0,1,0.3,1,12\n6,0.3,0,1,0.3,1,12\n",
      "in.csv");
  for (const Boundary boundary : {Boundary::periodic, Boundary::walls}) {
    const Box<2> box{10.0, boundary};
    const State<2> copied = ballagg::assemble_state<2>(box, t);
    SphereTable<2> given = t;
    const State<2> consumed = ballagg::assemble_state<2>(box, std::move(given));
    EXPECT_EQ(consumed.spheres.offset, copied.spheres.offset);
    EXPECT_EQ(consumed.spheres.cluster, copied.spheres.cluster);
    EXPECT_EQ(ballagg::state_csv_text(consumed), ballagg::state_csv_text(copied));
    EXPECT_EQ(consumed.n_clusters(), 4);
    if (boundary == Boundary::walls) continue;
    // The glued pair across y = 0 = L sits next to its first sphere, beyond L/2.
    EXPECT_NEAR((consumed.spheres.offset[6] - consumed.spheres.offset[5])[1], 0.6, 1e-12);
    EXPECT_NEAR((consumed.spheres.offset[1] - consumed.spheres.offset[0])[0], 0.6, 1e-12);
  }
}

TEST(StateCsv, WrittenTextHasHeaderAndClusterIdsInOrderOfFirstSphere) {
  using ballagg::testing::Ball;
  const State<2> s = ballagg::testing::make_state<2>(
      10.0, Boundary::walls,
      {Ball<2>{vec<2>(5, 5), vec<2>(0, 0), 0.5, 1.0, 9}, Ball<2>{vec<2>(1, 1), vec<2>(0.5, 0), 0.5, 1.0, 3},
       Ball<2>{vec<2>(6, 5), vec<2>(0, 0), 0.5, 1.0, 9}});
  EXPECT_EQ(ballagg::state_csv_text(s),
            "x,y,vx,vy,radius,mass,cluster\n"
            "5,5,0,0,0.5,1,0\n"
            "1,1,0.5,0,0.5,1,1\n"
            "6,5,0,0,0.5,1,0\n");
}

// final.csv is written as it is formatted: in chunks of whole lines of about
// kTextChunkBytes, which together are the text.
TEST(StateCsv, StreamedInChunksOfWholeLines) {
  class Chunks final : public ballagg::ByteSink {
   public:
    void write(std::string_view bytes) override { list.emplace_back(bytes); }
    std::vector<std::string> list;
  };
  const State<2> s =
      ballagg::make_initial_state<2>(ballagg::testing::small_config(2, 3000, 0.2, Boundary::walls, 11));
  Chunks chunks;
  ballagg::write_state_csv(s, chunks);
  ASSERT_GE(chunks.list.size(), 3u);
  std::string joined;
  for (const std::string& c : chunks.list) {
    EXPECT_EQ(c.back(), '\n');
    EXPECT_LT(c.size(), ballagg::kTextChunkBytes + 256);  // a chunk and at most one line
    joined += c;
  }
  EXPECT_EQ(joined, ballagg::state_csv_text(s));
}
