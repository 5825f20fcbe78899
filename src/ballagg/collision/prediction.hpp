#pragma once
// Predictions shared by the event-driven engines. Each is a pure function of the current
// motion of the clusters involved (anchor, anchor time, velocity), never of the moment the
// prediction is made: the fast engine and the naive reference engine therefore compute
// bit-identical event times and follow the same merge sequence.
#include <algorithm>
#include <cmath>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// With periodic faces, a pair meets through whichever image its relative trajectory
// reaches first, which need not be the nearest image at the time of the prediction. The
// walk over images gives up after this many boxes crossed (a trajectory that passes that
// many images without touching one is treated as never touching).
inline constexpr int kMaxImagesWalked = 10000;

// Where a sphere with body-frame offset `offset` in cluster k is at time t, not folded
// into the box: the arithmetic of State::unwrapped_position, for callers that keep the
// sphere's fields elsewhere.
template <int D>
Vec<D> position_in(const Cluster<D>& k, const Vec<D>& offset, double t) {
  const Vec<D> origin = k.anchor + (t - k.anchor_time) * k.velocity;
  return origin + offset;
}

// Absolute time at which two spheres of different clusters first touch, or kNever: sphere
// i at `offset_i` in cluster ci, sphere j at `offset_j` in cluster cj, sigma = R_i + R_j.
// `now` is the present time and `limit` a time after which the answer is not needed
// (kNever may then be returned for a contact through a farther image than the one the
// pair is in now). `horizon` is the time of an event the caller already has and keeps
// unless an earlier one comes: a contact certainly later is returned as kNever through
// any image (contact_time_within). The value returned for a contact before `limit` and
// `horizon` does not depend on `now`, `limit` or `horizon`: both event-driven engines
// compute it bit for bit alike.
template <int D>
double predicted_contact(const Box<D>& box, const Cluster<D>& ci, const Vec<D>& offset_i, const Cluster<D>& cj,
                         const Vec<D>& offset_j, double sigma, double now, double limit, double horizon = kNever) {
  const double t0 = std::max(ci.anchor_time, cj.anchor_time);
  const Vec<D> dx = position_in(ci, offset_i, t0) - position_in(cj, offset_j, t0);
  const Vec<D> dv = ci.velocity - cj.velocity;
  // The horizon from t0, widened so that a contact discarded is later than it after
  // rounding too (tolerance::kHorizonMargin).
  const double span =
      horizon == kNever ? kNever
                        : horizon - t0 + tolerance::kHorizonMargin * (std::abs(horizon) + std::abs(t0));
  const auto contact = [&](const Vec<D>& image) {
    return span == kNever ? contact_time<D>(image, dv, sigma) : contact_time_within<D>(image, dv, sigma, span);
  };
  if (!box.periodic()) return t0 + contact(dx);

  // Walk the images k L in the order the relative position dx + dv t passes through the
  // boxes of side L around them, from the box it is in now. A contact with image k happens
  // inside its box (sigma < L / 2), so the first image with a contact is the earliest.
  const double length = box.length;
  Vec<D> k;
  for (int a = 0; a < D; ++a) k[a] = round_to_integer((dx[a] + dv[a] * (now - t0)) / length);
  for (int step = 0; step < kMaxImagesWalked; ++step) {
    const Vec<D> image = dx - length * k;
    const double dt = contact(image);
    if (dt < kNever) return t0 + dt;
    double exit = kNever;
    int axis = -1;
    for (int a = 0; a < D; ++a) {
      if (dv[a] == 0.0) continue;
      const double face = dv[a] > 0.0 ? 0.5 * length : -0.5 * length;
      const double t = (face - image[a]) / dv[a];
      if (t < exit) exit = t, axis = a;
    }
    if (axis < 0 || t0 + exit > std::min(limit, horizon)) return kNever;
    k[axis] += dv[axis] > 0.0 ? 1.0 : -1.0;
  }
  return kNever;
}

// The same for spheres i and j of the state.
template <int D>
double predicted_contact(const State<D>& s, int i, int j, double now, double limit = kNever,
                         double horizon = kNever) {
  return predicted_contact(s.box, s.cluster_of(i), s.spheres.offset[i], s.cluster_of(j), s.spheres.offset[j],
                           s.spheres.radius[i] + s.spheres.radius[j], now, limit, horizon);
}

struct WallContact {
  double time = kNever;
  int axis = -1;
};

// First time a sphere of cluster c touches a wall it is moving towards (rule 2.2 applies
// to the whole cluster). The cluster's body-frame bounding box gives this in O(D).
template <int D>
WallContact next_wall_contact(const State<D>& s, int c) {
  WallContact w;
  if (s.box.periodic()) return w;
  const Cluster<D>& k = s.clusters[c];
  const ClusterExtent<D> e = s.extent(c);
  for (int a = 0; a < D; ++a) {
    const double v = k.velocity[a];
    double gap;
    if (v > 0.0) {
      gap = s.box.length - (k.anchor[a] + e.hi[a]);
    } else if (v < 0.0) {
      gap = k.anchor[a] + e.lo[a];
    } else {
      continue;
    }
    const double t = k.anchor_time + std::max(gap, 0.0) / std::abs(v);
    if (t < w.time) w = {t, a};
  }
  return w;
}

// Spheres i and j touch at time t (within the contact tolerance).
template <int D>
bool touching(const State<D>& s, int i, int j, double t) {
  const double sigma = (s.spheres.radius[i] + s.spheres.radius[j]) * (1.0 + tolerance::kContact);
  return s.box.separation(s.unwrapped_position(i, t), s.unwrapped_position(j, t)).squaredNorm() <= sigma * sigma;
}

}  // namespace ballagg
