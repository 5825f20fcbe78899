// The geometry of a state file read for a run (initial/sphere_layout_check.hpp): glued
// spheres must not overlap, and each cluster's spheres must form one contact graph, within
// the tolerances `ballagg verify` applies to a run of the same engine.
#include <string>

#include <gtest/gtest.h>

#include "ballagg/initial/sphere_layout_check.hpp"
#include "ballagg/io/state_csv.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

// make_initial_state<D> of the state file `text` in a box of side 10.
template <int D>
State<D> start_from(const std::string& text, Boundary boundary, EngineKind engine = EngineKind::ed,
                    TsModel model = TsModel::rigid) {
  const TempDir dir;
  Config c;
  c.system.dimension = D;
  c.system.box_length = 10.0;
  c.system.boundary = boundary;
  c.engine.kind = engine;
  c.ts.model = model;
  c.initial.positions = InitialPositions::file;
  c.initial.file = dir.write("in.csv", text).string();
  return make_initial_state<D>(c);
}

template <int D>
std::string refusal(const std::string& text, Boundary boundary, EngineKind engine = EngineKind::ed,
                    TsModel model = TsModel::rigid) {
  try {
    start_from<D>(text, boundary, engine, model);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

const std::string kHeader2 = "x,y,vx,vy,radius,mass,cluster\n";

TEST(SphereLayoutCheck, IdenticalRowsOfOneClusterAreRefusedNamingBothLines) {
  const std::string m = refusal<2>(kHeader2 + "1,1,0.1,0,0.5,1,0\n5,5,0,0,0.5,1,1\n1,1,0.1,0,0.5,1,0\n", Boundary::walls);
  EXPECT_CONTAINS(m, "in.csv:2: this sphere overlaps the sphere of line 4 of the same cluster (0) by 1 of their contact");
  EXPECT_EQ(m.find('\n'), std::string::npos);
}

TEST(SphereLayoutCheck, GluedSpheresOverlappingBeyondTheToleranceAreRefused) {
  // Overlap 1e-6 of sigma: above the event-driven engines' 1e-9, below ts's eps_c = 1e-3.
  const std::string text = kHeader2 + "1,1,0,0,0.5,1,3\n1.999999,1,0,0,0.5,1,3\n";
  for (EngineKind engine : {EngineKind::ed, EngineKind::ed_naive, EngineKind::rigid_body})
    EXPECT_CONTAINS(refusal<2>(text, Boundary::walls, engine), "in.csv:2: this sphere overlaps the sphere of line 3");
  EXPECT_EQ(start_from<2>(text, Boundary::walls, EngineKind::ts).n_clusters(), 1);
  // Touching (up to round-off) is no overlap.
  EXPECT_EQ(start_from<2>(kHeader2 + "1,1,0,0,0.5,1,3\n2,1,0,0,0.5,1,3\n", Boundary::walls).n_clusters(), 1);
}

TEST(SphereLayoutCheck, ClusterWhoseSpheresDoNotTouchIsRefusedNamingTheSphereAndTheClustersFirst) {
  // Spheres 1 and 2 touch; 3 is a diameter away from them (cluster id 9 listed second).
  const std::string text = kHeader2 + "5,5,0,0,0.5,1,4\n1,1,0,0,0.5,1,9\n2,1,0,0,0.5,1,9\n4,1,0,0,0.5,1,9\n";
  for (Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    const std::string m = refusal<2>(text, boundary);
    EXPECT_CONTAINS(m, "in.csv:5: this sphere of cluster 9 is not joined to the sphere of line 3, the cluster's first");
    EXPECT_CONTAINS(m, "(1 + 1e-09)");
  }
}

TEST(SphereLayoutCheck, ChainsConnectThroughOtherSpheresAndAcrossPeriodicFaces) {
  // A chain 9.5 -> 0.5 -> 1.5 across the face x = 0, listed end first: one cluster.
  const State<2> s = start_from<2>(kHeader2 + "1.5,5,0,0,0.5,1,0\n9.5,5,0,0,0.5,1,0\n0.5,5,0,0,0.5,1,0\n", Boundary::periodic);
  EXPECT_EQ(s.n_clusters(), 1);
  // With walls the same spheres are two pieces.
  EXPECT_CONTAINS(refusal<2>(kHeader2 + "1.5,5,0,0,0.5,1,0\n9.5,5,0,0,0.5,1,0\n0.5,5,0,0,0.5,1,0\n", Boundary::walls),
                  "in.csv:3: this sphere of cluster 0 is not joined");
}

TEST(SphereLayoutCheck, TimeSteppingLinksMayOpenAsItsModelAllows) {
  // A gap of 0.05 sigma: beyond ts.eps_c (rigid), within eps_c + bond_stretch (almost
  // rigid), not checked for the non-rigid model (its links open without bound).
  const std::string text = kHeader2 + "1,1,0,0,0.5,1,0\n2.05,1,0,0,0.5,1,0\n";
  EXPECT_CONTAINS(refusal<2>(text, Boundary::walls, EngineKind::ts, TsModel::rigid), "not joined");
  EXPECT_EQ(start_from<2>(text, Boundary::walls, EngineKind::ts, TsModel::almost_rigid).n_clusters(), 1);
  EXPECT_EQ(start_from<2>(text, Boundary::walls, EngineKind::ts, TsModel::non_rigid).n_clusters(), 1);
}

TEST(SphereLayoutCheck, ClusterIdsNeedNotBeSmallNumbers) {
  const std::string text = "x,y,z,vx,vy,vz,radius,mass,cluster\n"
                           "1,1,1,0,0,0,0.5,1,-70000000000\n"
                           "2,1,1,0,0,0,0.5,1,-70000000000\n"
                           "5,5,5,0,0,0,0.5,1,123456789012\n"
                           "5,6,5,0,0,0,0.5,1,123456789012\n";
  EXPECT_EQ(start_from<3>(text, Boundary::periodic).n_clusters(), 2);
  EXPECT_CONTAINS(refusal<3>(text + "1,3,1,0,0,0,0.5,1,-70000000000\n", Boundary::periodic),
                  "in.csv:6: this sphere of cluster -70000000000 is not joined to the sphere of line 2");
}

TEST(SphereLayoutCheck, WhatEveryRunOfAnEngineLeavesReadsBack) {
  // The final state of a run of each engine passes the check of the same engine.
  for (EngineKind engine : {EngineKind::ed, EngineKind::rigid_body, EngineKind::ts}) {
    Config c = testing::small_config(3, 300, 0.15, Boundary::periodic, 5);
    c.engine.kind = engine;
    c.stop.clusters = 30;
    State<3> s = make_initial_state<3>(c);
    RunObserver<3> none;
    make_engine<3>(resolve_defaults(c, s))->run(s, stop_criteria(c), none);
    ASSERT_LT(s.n_clusters(), 300);
    const SphereTable<3> t = parse_state_csv<3>(state_csv_text(s), "final.csv");
    EXPECT_NO_THROW(check_sphere_layout(s.box, t, layout_tolerance(c))) << to_string(engine);
  }
}

}  // namespace
}  // namespace ballagg
