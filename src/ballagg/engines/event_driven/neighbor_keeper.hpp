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
//   bool keeps_record(c), Record bin_record(c)   (optional) whether c needs a record, and
//                                          if not, what it holds (TranslationDrift: a
//                                          single sphere's drift follows from its bin)
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
#include "ballagg/core/sparse_records.hpp"
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

  // m clusters, none binned yet and none expiring. `keep_expiries`: whether each cluster's
  // expiry is kept for others to read (expiry(c)); without, a cluster's expiry is only
  // the value renew_expiry returns, which is all that `ed` reads in a box with walls (its
  // predictions read a partner's expiry only to end the walk over periodic images), and
  // 8 bytes per cluster are saved.
  void assign(int m, bool keep_expiries = true) {
    keeps_expiries_ = keep_expiries;
    records_.reset(static_cast<std::size_t>(m));
    if (keep_expiries) rebuild_at_.assign(m, kNever);
    else std::vector<double>().swap(rebuild_at_);
  }

  double drift(int c, double t) const { return bound_.drift(record(c), c, t); }
  // Must be called just before cluster c's motion changes at t.
  void fold(int c, double t) {
    if (keeps_record(c)) records_.store(c, bound_.folded(record(c), c, t));
  }
  // Cluster c's spheres binned anew at t.
  void reset(int c, double t) {
    if (keeps_record(c)) records_.store(c, bound_.reset(c, t));
    else records_.forget(c);
  }
  // Cluster c starts a new reference instant at which its spheres may be `slack` from
  // their bins (a merge: the drift so far carries over).
  void restart(int c, double slack) { records_.store(c, bound_.restarted(slack)); }
  // Cluster c has no spheres left (merged away).
  void forget(int c) { records_.forget(c); }

  // When c's lists may expire, from its drift record and motion now.
  double rebuild_time(int c) const { return bound_.rebuild_time(record(c), c, skin_); }
  // rebuild_time(c) as of c's last prediction (renew_expiry). Requires the expiries kept.
  double expiry(int c) const { return rebuild_at_[c]; }
  const double* expiry_address(int c) const { return &rebuild_at_[c]; }
  double renew_expiry(int c) {
    const double t = rebuild_time(c);
    if (keeps_expiries_) rebuild_at_[c] = t;
    return t;
  }

  // A cluster without a record is saved with the one it stands for (bin_record); without
  // the expiries kept, the file holds each cluster's rebuild_time (for a live cluster, what
  // a keeper that keeps them holds between events). The file is the same either way.
  void save(ByteWriter& w) const {
    const int m = static_cast<int>(records_.ids());
    for (int c = 0; c < m; ++c) bound_.save(w, record(c));
    if (keeps_expiries_) {
      w.put_vector(rebuild_at_);
      return;
    }
    std::vector<double> expiries(static_cast<std::size_t>(m));
    for (int c = 0; c < m; ++c) expiries[c] = rebuild_time(c);
    w.put_vector(expiries);
  }
  // Reads what save() wrote for m clusters; the expiries are kept if keep_expiries (as
  // for assign()). A cluster that keeps no record reads and drops its saved one: the grid,
  // restored before, holds what it stood for.
  void restore(ByteReader& r, int m, bool keep_expiries = true) {
    keeps_expiries_ = keep_expiries;
    records_.reset(static_cast<std::size_t>(m));
    for (int c = 0; c < m; ++c) {
      const Record d = bound_.restore(r);
      if (keeps_record(c)) records_.store(c, d);
    }
    std::vector<double> expiries = r.get_vector<double>("rebuild times", m);
    if (static_cast<int>(expiries.size()) != m) r.fail("rebuild times for another number of clusters");
    if (keep_expiries) rebuild_at_ = std::move(expiries);
    else std::vector<double>().swap(rebuild_at_);
  }

 private:
  bool keeps_record(int c) const {
    if constexpr (requires { bound_.keeps_record(c); }) return bound_.keeps_record(c);
    else return true;
  }
  Record record(int c) const {
    if (const Record* r = records_.find(c)) return *r;
    if constexpr (requires { bound_.bin_record(c); }) return bound_.bin_record(c);
    else return Record{};
  }

  Bound bound_;
  double skin_;
  SparseRecords<Record> records_;  // per cluster that keeps_record
  std::vector<double> rebuild_at_;  // per cluster, if kept
  bool keeps_expiries_ = true;
};

}  // namespace ballagg
