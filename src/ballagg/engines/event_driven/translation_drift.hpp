#pragma once
// The drift bound of clusters that only translate (the event-driven engine): how far a
// cluster's spheres may be from where they were binned is slack + |d|, where d is the
// cluster's displacement since a reference instant (walls and periodic wraps included)
// and slack covers what happened before it. A rebuild sets both to zero; a merge starts a
// new reference with the drift so far as slack. Displacement rather than path length means
// a big cluster rattling between walls, or bouncing to and fro, does not rebuild its lists
// for nothing. (A drift bound of NeighborKeeper, neighbor_keeper.hpp.)
#include <cmath>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"

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

  explicit TranslationDrift(const State<D>& s) : s_(&s) {}

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
};

}  // namespace ballagg
