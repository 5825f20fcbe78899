#pragma once
// When the neighbour lists of a cluster expire. Each sphere lists the spheres of other
// clusters within sigma + skin of it, found on a cell grid that holds every sphere where it
// was binned. A pair absent from the lists was farther apart than sigma + skin at the later
// of its two clusters' last rebuilds; as long as each of its spheres has moved less than
// skin / 2 since it was binned (its drift), the pair is still apart. So a cluster rebuilds
// its lists (and re-bins its spheres) when its drift may reach skin / 2.
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

// A sphere is at most skin / 2 from where it was binned, and a listed pair is closer than
// sigma + skin: the grid must find every sphere binned within sigma + kBinnedReachInSkins
// skin of a sphere's present place (one skin of list reach, half a skin of the partner's
// drift). The grid's cells are therefore 2 R_max + kBinnedReachInSkins skin wide.
inline constexpr double kBinnedReachInSkins = 1.5;

// In a periodic box every listed pair must be closer than half the box (one image of each
// partner), so the grid's reach 2 R_max + kBinnedReachInSkins skin is kept below L / 2
// with this margin.
inline constexpr double kPeriodicSkinMargin = 0.99;

// The requested skin (> 0), or the engine's default, shrunk to what a periodic box allows:
// kPeriodicSkinMargin (L / 2 - 2 R_max) / kBinnedReachInSkins. The event-driven engine
// divides first, the rigid-body engine multiplies first; the two may differ in the last
// bit, and each engine keeps the rounding its results are computed with.
enum class SkinLimitRounding { divide_first, multiply_first };
template <int D>
double fitted_skin(const State<D>& s, double requested, double fallback, SkinLimitRounding rounding) {
  double skin = requested > 0.0 ? requested : fallback;
  if (!s.box.periodic()) return skin;
  const double space = 0.5 * s.box.length - 2.0 * s.max_radius();
  const double limit = rounding == SkinLimitRounding::divide_first
                           ? kPeriodicSkinMargin * (space / kBinnedReachInSkins)
                           : kPeriodicSkinMargin * space / kBinnedReachInSkins;
  return std::min(skin, limit);
}

// The width of the grid's cells for this skin and spheres of radius at most
// `largest_radius`.
inline double binning_cell_size(double largest_radius, double skin) {
  return 2.0 * largest_radius + kBinnedReachInSkins * skin;
}
template <int D>
double binning_cell_size(const State<D>& s, double skin) {
  return binning_cell_size(s.max_radius(), skin);
}

// Calls found(j) for every sphere j of another cluster than ci that within_reach(j) puts
// in reach of the sphere at x (folded into the box: `folded`) whose radius is ri, and for
// which wanted(j) holds (asked first: the exact distance is dearer). The grid tags each
// sphere with its cluster, so ci is skipped there; spheres binned farther than
// ri + R_max + kBinnedReachInSkins skin away are rejected at once.
template <int D, class Wanted, class WithinReach, class Found>
void for_each_foreign_near(const CellGrid<D>& grid, const State<D>& s, double skin, int ci, const Vec<D>& folded,
                           double ri, Wanted&& wanted, WithinReach&& within_reach, Found&& found) {
  const double binned_reach = ri + s.max_radius() + kBinnedReachInSkins * skin;
  grid.for_each_near_image(folded, ci, [&](int j, const Vec<D>& binned) {
    if ((folded - binned).squaredNorm() >= binned_reach * binned_reach) return;
    if (!wanted(j)) return;
    if (within_reach(j)) found(j);
  });
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
