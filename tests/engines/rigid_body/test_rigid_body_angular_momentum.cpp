// The rigid-body engine's total angular momentum (lx, ly, lz of timeseries.csv,
// angular_momentum_final of summary.json): spin plus orbital about the box centre, with
// every body's centre of mass followed from where the state puts it in the box. With walls
// and in a periodic box alike it is conserved by free flight and by collisions inside the
// box, and in a periodic box also while a body wraps through a face.
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/io/state_csv.hpp"

#include "file_text.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

struct AngularMomentum {
  std::vector<double> time;
  std::vector<std::array<double, 3>> rows;  // lx, ly, lz of timeseries.csv
  std::array<double, 3> final;              // summary.json
  int clusters_at_end = 0;
};

using testing::slurp;

// A 3D rigid-body run of the state file `text` in a box of side 10.
AngularMomentum run_from(const std::string& text, Boundary boundary, const std::string& stop_time = "inf") {
  const TempDir dir;
  Config c = parse_config_text("", "test", {"system.dimension=3", "engine.kind=\"rigid-body\"",
                                            "output.timeseries_interval=0.25", "output.checkpoint_every=0",
                                            "stop.time=" + stop_time});
  c.system.box_length = 10.0;
  c.system.volume_fraction.reset();
  c.system.boundary = boundary;
  c.initial.positions = InitialPositions::file;
  c.initial.file = dir.write("in.csv", text).string();
  run_simulation(c, {(dir / "run").string(), true, false, false});
  AngularMomentum out;
  std::istringstream csv(slurp(dir / "run" / "timeseries.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find(",lx,ly,lz"), std::string::npos) << line;
  while (std::getline(csv, line)) {
    std::vector<double> v;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    out.time.push_back(v.front());
    out.rows.push_back({v[v.size() - 3], v[v.size() - 2], v[v.size() - 1]});
    out.clusters_at_end = static_cast<int>(v[1]);
  }
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir / "run" / "summary.json"));
  for (int a = 0; a < 3; ++a) out.final[a] = summary["angular_momentum_final"][a].get<double>();
  return out;
}

void expect_every_row_is(const AngularMomentum& l, const std::array<double, 3>& expected, double tolerance) {
  ASSERT_FALSE(l.rows.empty());
  for (std::size_t k = 0; k < l.rows.size(); ++k)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(l.rows[k][a], expected[a], tolerance) << "t = " << l.time[k] << ", axis " << a;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(l.final[a], expected[a], tolerance) << "summary, axis " << a;
}

TEST(RigidBodyAngularMomentum, PeriodicBoxGivesTheWallsValueBeforeAndAfterSticking) {
  // Two spheres meeting at x = 5, off-centre by 0.2 in y. About the box centre (5, 5, 5):
  // (-2, 0.1, 0) x (1, 0, 0) + (2, -0.1, 0) x (-2, 0, 0) = (0, 0, -0.1) + (0, 0, -0.2).
  const std::string text = "x,y,z,vx,vy,vz,radius,mass\n3,5.1,5,1,0,0,0.2,1\n7,4.9,5,-1,0,0,0.2,2\n";
  for (Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    SCOPED_TRACE(to_string(boundary));
    const AngularMomentum l = run_from(text, boundary);
    EXPECT_EQ(l.clusters_at_end, 1);  // they stuck (spin 0.23 of rotational energy)
    expect_every_row_is(l, {0.0, 0.0, -0.3}, 1e-12);
  }
}

TEST(RigidBodyAngularMomentum, ConservedWhileASpinningBodyWrapsThroughPeriodicFaces) {
  // A spinning dimer (centre (9.5, 6, 5), moving (1, 0.5, 0)) wraps through x = 10 at
  // t = 0.5 and through y = 10 at t = 8; a sphere at rest out of its way. L about the box centre:
  // orbital 2 (4.5, 1, 0) x (1, 0.5, 0) = (0, 0, 2.5), spin I_zz w_z with
  // I_zz = 2 (2/5 0.2^2) + 2 0.2^2 = 0.112 and w_z = 0.3.
  const std::string text =
      "x,y,z,vx,vy,vz,radius,mass,cluster,wx,wy,wz\n"
      "9.3,6,5,1,0.5,0,0.2,1,0,0,0,0.3\n"
      "9.7,6,5,1,0.5,0,0.2,1,0,0,0,0.3\n"
      "2,2,2,0,0,0,0.2,1,1,0,0,0\n";
  const AngularMomentum l = run_from(text, Boundary::periodic, "9");
  EXPECT_EQ(l.time.back(), 9.0);
  expect_every_row_is(l, {0.0, 0.0, 2.5 + 0.112 * 0.3}, 1e-12);
}

TEST(RigidBodyAngularMomentum, StartingBodiesInTheBoxKeepTheFoldedPositionsBitForBit) {
  Config c = testing::small_config(3, 400, 0.2, Boundary::periodic, 17);
  c.engine.kind = EngineKind::rigid_body;
  const State<3> rigid = make_initial_state<3>(c);
  c.engine.kind = EngineKind::ed;
  const State<3> ed = make_initial_state<3>(c);
  EXPECT_EQ(state_csv_text(rigid), state_csv_text(ed));
  // ... with every body's centre of mass (here: its sphere) in the box.
  for (int i = 0; i < rigid.n_spheres(); ++i) {
    const Vec<3> x = rigid.unwrapped_position(i, 0.0);
    EXPECT_TRUE((x.array() >= 0.0).all() && (x.array() < rigid.box.length).all()) << x.transpose();
  }
}

}  // namespace
}  // namespace ballagg
