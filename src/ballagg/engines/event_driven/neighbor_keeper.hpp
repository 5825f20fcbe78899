#pragma once
// When the neighbour lists of a cluster expire. Each sphere lists the spheres of other
// clusters whose bins are within sigma + skin of its own: a sphere's bin is where it was
// put on the cell grid at its cluster's last rebuild. As long as every sphere stays within
// skin / 2 of its bin (its drift), a pair absent from the lists is at least sigma apart, so
// it cannot touch. A cluster therefore rebuilds its lists (and re-bins its spheres) when
// its drift may reach skin / 2.
//
// The test is between bins, not between present places. A sphere that has drifted d
// from its bin and turns back (a wall, a bounce, a merge) may later be skin / 2 from its
// bin on the other side: it comes up to d + skin / 2 closer to a partner than it was when
// the partner rebuilt. It never strays more than skin / 2 from its bin, so the test
// measures from there.
//
// The drift is bounded per cluster by a drift bound (the template parameter Bound), which
// keeps one Record per cluster and answers:
//   Record reset(c, t)                     the cluster binned anew at t
//   Record folded(record, c, t)            c's motion is about to change at t
//   Record restarted(slack)                a new reference instant, drift so far `slack`
//   double drift(record, c, t)             bound on how far c's spheres are from their bins
//   double rebuild_time(record, c, skin)   when that bound may reach skin / 2
//   void save(w, record), Record restore(r)
// TranslationDrift (clusters that only translate, the event-driven engine) and
// RotationDrift (rigid bodies that also spin) are the two.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/spatial/cell_grid.hpp"

namespace ballagg {

// In a periodic box the bins of a listed pair must have one nearest image: sigma + skin
// below L / 2. The skin is kept so that 2 R_max + kPeriodicReachInSkins skin, that reach
// with half a skin to spare, stays below L / 2 by the margin kPeriodicSkinMargin; the
// configuration's check of the box size (docs/hardening.md) is written for this limit.
inline constexpr double kPeriodicReachInSkins = 1.5;
inline constexpr double kPeriodicSkinMargin = 0.99;

// The requested skin (> 0), or the engine's default, shrunk to what a periodic box allows:
// kPeriodicSkinMargin (L / 2 - 2 R_max) / kPeriodicReachInSkins. The event-driven engine
// divides first, the rigid-body engine multiplies first; the two may differ in the last
// bit, and each engine keeps the rounding its results are computed with.
enum class SkinLimitRounding { divide_first, multiply_first };
template <int D>
double fitted_skin(const State<D>& s, double requested, double fallback, SkinLimitRounding rounding) {
  double skin = requested > 0.0 ? requested : fallback;
  if (!s.box.periodic()) return skin;
  const double space = 0.5 * s.box.length - 2.0 * s.max_radius();
  const double limit = rounding == SkinLimitRounding::divide_first
                           ? kPeriodicSkinMargin * (space / kPeriodicReachInSkins)
                           : kPeriodicSkinMargin * space / kPeriodicReachInSkins;
  return std::min(skin, limit);
}

// The width of the grid's cells for this skin and spheres of radius at most
// `largest_radius`. A listed pair's bins are closer than sigma + skin, and every query is
// made from a sphere's bin: a cell that wide holds every partner in the 3^D cells around.
inline double binning_cell_size(double largest_radius, double skin) { return 2.0 * largest_radius + skin; }
template <int D>
double binning_cell_size(const State<D>& s, double skin) {
  return binning_cell_size(s.max_radius(), skin);
}

// Calls found(j) for every sphere j of another cluster than ci whose bin lies within
// ri + radius_of(j) + skin of `bin` (the bin of the querying sphere, of radius ri), and for
// which wanted(j) holds. The grid tags each sphere with its cluster, so ci is skipped
// there; bins farther than ri + R_max + skin are rejected before anything else is read,
// and wanted(j) is asked before radius_of(j).
template <int D, class Wanted, class RadiusOf, class Found>
void for_each_foreign_near(const CellGrid<D>& grid, const State<D>& s, double skin, int ci, const Vec<D>& bin,
                           double ri, Wanted&& wanted, RadiusOf&& radius_of, Found&& found) {
  const double widest = ri + s.max_radius() + skin;
  grid.for_each_near_image(bin, ci, [&](int j, const Vec<D>& bin_j) {
    const double gap2 = (bin - bin_j).squaredNorm();
    if (gap2 >= widest * widest) return;
    if (!wanted(j)) return;
    const double reach = ri + radius_of(j) + skin;
    if (gap2 < reach * reach) found(j);
  });
}

// Whether the pair with bins bin_i and bin_j (any images: the shortest is taken) and radii
// ri and rj belongs in the lists.
template <int D>
bool bins_within_reach(const Box<D>& box, const Vec<D>& bin_i, const Vec<D>& bin_j, double ri, double rj,
                       double skin) {
  const double reach = ri + rj + skin;
  return box.separation(bin_i, bin_j).squaredNorm() < reach * reach;
}

// The skin, each cluster's drift record and its list expiry.
template <class Bound>
class NeighborKeeper {
 public:
  using Record = typename Bound::Record;

  NeighborKeeper(Bound bound, double skin) : bound_(std::move(bound)), skin_(skin) {}

  const Bound& bound() const { return bound_; }
  double skin() const { return skin_; }
  void set_skin(double skin) { skin_ = skin; }

  // m clusters, none binned yet and none expiring.
  void assign(int m) {
    drift_.assign(m, Record{});
    rebuild_at_.assign(m, kNever);
  }

  double drift(int c, double t) const { return bound_.drift(drift_[c], c, t); }
  // Must be called just before cluster c's motion changes at t.
  void fold(int c, double t) { drift_[c] = bound_.folded(drift_[c], c, t); }
  // Cluster c's spheres binned anew at t.
  void reset(int c, double t) { drift_[c] = bound_.reset(c, t); }
  // Cluster c starts a new reference instant at which its spheres may be `slack` from
  // their bins (a merge: the drift so far carries over).
  void restart(int c, double slack) { drift_[c] = bound_.restarted(slack); }

  // When c's lists may expire, from its drift record and motion now.
  double rebuild_time(int c) const { return bound_.rebuild_time(drift_[c], c, skin_); }
  // rebuild_time(c) as of c's last prediction (renew_expiry).
  double expiry(int c) const { return rebuild_at_[c]; }
  const double* expiry_address(int c) const { return &rebuild_at_[c]; }
  double renew_expiry(int c) { return rebuild_at_[c] = rebuild_time(c); }

  void save(ByteWriter& w) const {
    for (const Record& d : drift_) bound_.save(w, d);
    w.put_vector(rebuild_at_);
  }
  // Reads what save() wrote for m clusters.
  void restore(ByteReader& r, int m) {
    drift_.resize(m);
    for (Record& d : drift_) d = bound_.restore(r);
    rebuild_at_ = r.get_vector<double>("rebuild times", m);
    if (static_cast<int>(rebuild_at_.size()) != m) r.fail("rebuild times for another number of clusters");
  }

 private:
  Bound bound_;
  double skin_;
  std::vector<Record> drift_;
  std::vector<double> rebuild_at_;
};

}  // namespace ballagg
