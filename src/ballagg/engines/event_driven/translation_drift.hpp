#pragma once
// The drift bound of clusters that only translate (the event-driven engine): how far a
// cluster's spheres may be from where they were binned is slack + |d|, where d is the
// cluster's displacement since a reference instant (walls and periodic wraps included)
// and slack covers what happened before it. A rebuild sets both to zero; a merge starts a
// new reference with the drift so far as slack. Displacement rather than path length means
// a big cluster rattling between walls, or bouncing to and fro, does not rebuild its lists
// for nothing. (A drift bound of NeighborKeeper, neighbor_keeper.hpp.)
//
// Given the cell grid the spheres are binned in, a cluster of one sphere keeps no record:
// its displacement since it was binned is the way from its bin to where it is, and it has
// no slack (only a merge gives slack, and a merge makes an aggregate). A gas of monomers
// then costs no record per cluster.
#include <cmath>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/spatial/cell_grid.hpp"

namespace ballagg {

template <int D>
class TranslationDrift {
 public:
  // A record per cluster slot, kept by the million: its vector is stored without Eigen's
  // 16-byte alignment, which would pad a 2D record from 24 to 32 bytes (the arithmetic,
  // and so every result, is that of Vec).
  struct Record {
    // Since the reference instant.
    Eigen::Matrix<double, D, 1, Eigen::DontAlign> displacement_at_anchor = Vec<D>::Zero();
    double slack = 0.0;  // drift before the reference instant
  };
  static_assert(sizeof(Record) == (D + 1) * sizeof(double), "one record per cluster: no padding");

  // `bins`: the grid the spheres are binned in, or nullptr (every cluster keeps a record).
  explicit TranslationDrift(const State<D>& s, const CellGrid<D>* bins = nullptr) : s_(&s), bins_(bins) {}

  // Whether cluster c needs a record: without one, its record is bin_record(c).
  bool keeps_record(int c) const { return bins_ == nullptr || s_->clusters[c].size() > 1; }
  // The record of a cluster of one sphere, from its bin: its displacement from the bin at
  // the anchor time, no slack. The way from the bin is taken at the present (the state's
  // time), where it is the nearest image (the drift stays below L / 2), and carried back
  // to the anchor time along the velocity: since its anchor time a sphere in a periodic box
  // may have crossed the box. A dead cluster's record is zero.
  Record bin_record(int c) const {
    const Cluster<D>& k = s_->clusters[c];
    if (!k.alive()) return {};
    const int i = k.members.front();
    const double now = s_->time;
    const Vec<D> from_bin = s_->box.separation(s_->unwrapped_position(i, now), bins_->binned(i));
    return {from_bin - (now - k.anchor_time) * k.velocity, 0.0};
  }

  // The displacement of cluster c's centre since the record's reference instant, at t.
  Vec<D> displacement(const Record& r, int c, double t) const {
    const Cluster<D>& k = s_->clusters[c];
    return r.displacement_at_anchor + (t - k.anchor_time) * k.velocity;
  }
  double drift(const Record& r, int c, double t) const { return r.slack + displacement(r, c, t).norm(); }
  Record folded(const Record& r, int c, double t) const { return {displacement(r, c, t), r.slack}; }
  Record reset(int c, double t) const {
    const Cluster<D>& k = s_->clusters[c];
    return {-(t - k.anchor_time) * k.velocity, 0.0};
  }
  Record restarted(double slack) const { return {Vec<D>::Zero(), slack}; }

  // When the drift reaches skin / 2: the exit root tau of |d0 + V tau| = skin / 2 - slack
  // (tau from the anchor time). The cluster is within reach now, so the two roots bracket
  // the present and the later one is the exit.
  double rebuild_time(const Record& r, int c, double skin) const {
    const Cluster<D>& k = s_->clusters[c];
    const double a = k.velocity.squaredNorm();
    if (a == 0.0) return kNever;
    const Vec<D> d0 = r.displacement_at_anchor;
    const double reach = 0.5 * skin - r.slack;
    const crossing::Quadratic q{a, d0.dot(k.velocity), d0.squaredNorm() - reach * reach};
    const double disc = crossing::discriminant(q);
    if (reach <= 0.0 || disc < 0.0) return k.anchor_time;
    return k.anchor_time + crossing::exit(q, std::sqrt(disc));
  }

  void save(ByteWriter& w, const Record& r) const {
    w.put(Vec<D>(r.displacement_at_anchor));
    w.put(r.slack);
  }
  Record restore(ByteReader& r) const {
    Record d;
    d.displacement_at_anchor = r.get<Vec<D>>("drift");
    d.slack = r.get<double>("drift slack");
    return d;
  }

 private:
  const State<D>* s_;
  const CellGrid<D>* bins_;
};

}  // namespace ballagg
