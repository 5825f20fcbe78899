#pragma once
// The drift bound of rigid bodies that translate and spin (the rigid-body engine): how far
// a body's spheres may be from where they were binned is at most
//     slack + |d| + reach min(2, turned),
// slack + |d| the bound of the centre (TranslationDrift), `turned` a bound on the angle the
// body has turned since then, and reach min(2, turned) the chord its farthest sphere can
// have swept (never more than the diameter 2 reach). A single sphere sits at its body's
// centre and only translates. (A drift bound of NeighborKeeper,
// engines/event_driven/neighbor_keeper.hpp.)
#include <algorithm>
#include <cmath>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/event_driven/translation_drift.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"

namespace ballagg {

// The farthest a sphere's turn can carry it, in units of its distance from the centre:
// the chord of half a turn, the diameter.
inline constexpr double kLargestChord = 2.0;

template <int D>
class RotationDrift {
 public:
  struct Record : TranslationDrift<D>::Record {
    double angle_at_anchor = 0.0;  // bound on the rotation since the reference instant
  };

  RotationDrift(const State<D>& s, const RigidBodies<D>& bodies) : centre_(s), s_(&s), bodies_(&bodies) {}

  // Bound on body c's angular speed (0 for a single sphere, which does not move by turning).
  double spin_bound(int c) const {
    return s_->clusters[c].size() == 1 ? 0.0 : (*bodies_)[c].rotation.max_angular_speed();
  }

  double drift(const Record& r, int c, double t) const {
    return centre_.drift(r, c, t) + (*bodies_)[c].reach * std::min(kLargestChord, turned(r, c, t));
  }
  Record folded(const Record& r, int c, double t) const { return {centre_.folded(r, c, t), turned(r, c, t)}; }
  Record reset(int c, double t) const {
    const double dt = t - s_->clusters[c].anchor_time;
    return {{-dt * s_->clusters[c].velocity, 0.0}, -dt * spin_bound(c)};
  }
  Record restarted(double slack) const { return {centre_.restarted(slack), 0.0}; }

  // When body c's drift may reach skin / 2. Two bounds of the drift, both valid: from
  // now on, the centre moving at most |V| tau and the farthest sphere turning at most
  // Omega tau (linear); and the exact displacement of the centre with the whole chord
  // 2 reach (the exit root of |d0 + V tau| = skin / 2 - slack - 2 reach). The drift stays
  // below skin / 2 until the later of the two crossings.
  double rebuild_time(const Record& d, int c, double skin) const {
    const Cluster<D>& k = s_->clusters[c];
    const double now = s_->time;
    const double room = 0.5 * skin - d.slack;
    const double reach = (*bodies_)[c].reach, omega = spin_bound(c);
    double linear = -kNever;
    const double used = centre_.displacement(d, c, now).norm() + reach * std::min(kLargestChord, turned(d, c, now));
    const double rate = k.velocity.norm() + reach * omega;
    if (rate > 0.0) linear = now + (room - used) / rate;
    else if (used < room) linear = kNever;
    double chord = -kNever;
    const double rest = room - kLargestChord * reach;
    if (rest > 0.0) {
      const double a = k.velocity.squaredNorm();
      const Vec<D> d0 = d.displacement_at_anchor;
      const crossing::Quadratic q{a, d0.dot(k.velocity), d0.squaredNorm() - rest * rest};
      const double disc = crossing::discriminant(q);
      if (a == 0.0) chord = q.c < 0.0 ? kNever : -kNever;
      else if (disc >= 0.0) chord = k.anchor_time + crossing::exit(q, std::sqrt(disc));
    }
    const double t = std::max(linear, chord);
    return t == kNever ? kNever : std::max(t, now);
  }

  void save(ByteWriter& w, const Record& r) const {
    centre_.save(w, r);
    w.put(r.angle_at_anchor);
  }
  Record restore(ByteReader& r) const {
    // Braced: the centre's fields are read before the angle.
    return Record{centre_.restore(r), r.get<double>("drift angle")};
  }

 private:
  double turned(const Record& r, int c, double t) const {
    return r.angle_at_anchor + spin_bound(c) * (t - s_->clusters[c].anchor_time);
  }

  TranslationDrift<D> centre_;  // the bound of the centre's displacement
  const State<D>* s_;
  const RigidBodies<D>* bodies_;
};

}  // namespace ballagg
