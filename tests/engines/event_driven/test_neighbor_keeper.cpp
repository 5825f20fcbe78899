// A cluster of one sphere keeps no drift record when the keeper knows the cell grid: its
// drift is the way from its bin to where it is. That drift, and the time it reaches half
// the skin, are those of a record kept through the same rebuilds, wall reflections and
// periodic wraps; an aggregate keeps its record and its merge slack; a checkpoint holds
// the same records either way.
#include <gtest/gtest.h>

#include <cmath>

#include "ballagg/collision/resolve.hpp"
#include "ballagg/engines/event_driven/neighbor_keeper.hpp"
#include "ballagg/engines/event_driven/translation_drift.hpp"
#include "ballagg/spatial/cell_grid.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::vec;

constexpr double kSkin = 0.8;
// Bins and records give the same drift up to the rounding of positions of order the box.
constexpr double kSameDrift = 1e-12;

struct Keepers {
  explicit Keepers(State<2>& s)
      : grid(s.box, binning_cell_size(s, kSkin), s.n_spheres()),
        from_bins(TranslationDrift<2>(s, &grid), kSkin), from_records(TranslationDrift<2>(s), kSkin), s_(s) {
    const int m = static_cast<int>(s.clusters.size());
    from_bins.assign(m, false);
    from_records.assign(m);
    for (int i = 0; i < s.n_spheres(); ++i) grid.insert(i, s.position(i, s.time));
    for (int c : s.alive_clusters()) rebuild(c, s.time);
  }
  void rebuild(int c, double t) {
    for (int i : s_.clusters[c].members) grid.move(i, s_.position(i, t));
    from_bins.reset(c, t);
    from_records.reset(c, t);
  }
  void expect_same(int c, double t) {
    EXPECT_NEAR(from_bins.drift(c, t), from_records.drift(c, t), kSameDrift) << "cluster " << c << ", t = " << t;
    EXPECT_NEAR(from_bins.rebuild_time(c), from_records.rebuild_time(c), kSameDrift) << "cluster " << c;
  }

  CellGrid<2> grid;
  NeighborKeeper<TranslationDrift<2>> from_bins, from_records;
  State<2>& s_;
};

// Sphere 0 (R = 0.5, at x = 9.2, moving at (1, 0.3)) meets the wall x = 10 at t = 0.3 and
// comes back; through periodic faces its centre crosses x = 10 at t = 0.8 and wraps.
TEST(NeighborKeeper, AMonomerDriftsFromItsBinAsARecordWouldHaveIt) {
  for (Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    const bool walls = boundary == Boundary::walls;
    SCOPED_TRACE(walls ? "walls" : "periodic");
    State<2> s = testing::make_state<2>(10, boundary, {{vec<2>(9.2, 5), vec<2>(1.0, 0.3)}, {vec<2>(2, 2), vec<2>(-0.5, 0.2)}});
    Keepers k(s);
    const int c = s.spheres.cluster[0];
    k.expect_same(c, 0.3);
    if (walls) {
      k.from_bins.fold(c, 0.3);
      k.from_records.fold(c, 0.3);
      reflect_cluster(s, c, 0, 0.3);
    }
    for (double t : {0.35, 0.5, 0.9, 1.0}) k.expect_same(c, t);
    const Vec<2> moved = walls ? vec<2>(0.3 - 0.7, 0.3) : vec<2>(1.0, 0.3);  // by t = 1
    EXPECT_NEAR(k.from_bins.drift(c, 1.0), moved.norm(), kSameDrift);
    k.rebuild(c, 1.0);
    EXPECT_NEAR(k.from_bins.drift(c, 1.0), 0.0, kSameDrift);
    k.expect_same(c, 1.25);
    k.expect_same(s.spheres.cluster[1], 1.25);
  }
}

TEST(NeighborKeeper, AnAggregateKeepsItsRecordAndSlackAndCheckpointsAreAlike) {
  State<2> s = testing::make_state<2>(
      10, Boundary::walls,
      {{vec<2>(3, 3), vec<2>(0.4, 0), 0.5, 1.0, 0}, {vec<2>(4, 3), vec<2>(0.4, 0), 0.5, 1.0, 0}, {vec<2>(7, 7), vec<2>(0, -1)}});
  Keepers k(s);
  const int aggregate = s.spheres.cluster[0], monomer = s.spheres.cluster[2];
  k.from_bins.restart(aggregate, 0.125);
  k.from_records.restart(aggregate, 0.125);
  EXPECT_EQ(k.from_bins.drift(aggregate, 1.0), k.from_records.drift(aggregate, 1.0));  // the same record
  EXPECT_NEAR(k.from_bins.drift(aggregate, 1.0), 0.125 + 0.4 * (1.0 - s.clusters[aggregate].anchor_time), kSameDrift);
  k.expect_same(monomer, 0.25);

  ByteWriter bins, records;
  k.from_bins.save(bins);
  k.from_records.save(records);
  EXPECT_EQ(bins.bytes().size(), records.bytes().size());
  // A keeper restored from either file drifts as the saved ones do.
  NeighborKeeper<TranslationDrift<2>> restored(TranslationDrift<2>(s, &k.grid), kSkin);
  ByteReader r(records.bytes(), "keeper");
  restored.restore(r, static_cast<int>(s.clusters.size()), false);
  for (int c : {aggregate, monomer}) EXPECT_NEAR(restored.drift(c, 0.5), k.from_records.drift(c, 0.5), kSameDrift);
}

}  // namespace
}  // namespace ballagg
