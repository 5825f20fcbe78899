// The rigid-body engine's neighbour lists: which pairs are listed, building them, and a
// body's list rebuild (its lists expire when NeighborKeeper says so).
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

namespace ballagg {

template <int D>
void RigidBodyCore<D>::build_spatial() {
  const int n = s_.n_spheres();
  const int m = static_cast<int>(s_.clusters.size());
  const double t = s_.time;
  grid_radius_ = binned_radius();
  grid_ = std::make_unique<CellGrid<D>>(grid_geometry(), n);
  pose_time_.assign(m, std::numeric_limits<double>::quiet_NaN());
  pose_.resize(m);
  keeper_.assign(m);
  lists_.reset(n, m);
  calendar_.reset(m);
  for (int i = 0; i < n; ++i) {
    grid_->insert(i, s_.box.wrap(unwrapped_position(i, t)));
    grid_->set_tag(i, body_of(i));
  }
  for (int c : s_.alive_clusters()) keeper_.reset(c, t);
  for (int i = 0; i < n; ++i)
    for_each_foreign_near(i, [&](int j) { return j > i; }, [&](int j) { lists_.add_pair(i, j, s_.spheres.cluster.data()); });
  for (int c : s_.alive_clusters()) keeper_.renew_expiry(c);
  for (int c : s_.alive_clusters()) predict(c, /*skip_lower_bodies=*/true);
}

template <int D>
void RigidBodyCore<D>::drop_out_of_reach(int i) {
  for (auto p = static_cast<std::ptrdiff_t>(lists_.partners(i).size()) - 1; p >= 0; --p) {
    const int j = lists_.partners(i)[p];
    if (!bins_within_reach(i, j)) lists_.remove_pair(i, j, s_.spheres.cluster.data());
  }
}

template <int D>
EventRecord RigidBodyCore<D>::rebuild(int c, double t) {
  const std::int32_t* cluster = s_.spheres.cluster.data();
  for (int i : s_.clusters[c].members) grid_->move(i, s_.box.wrap(unwrapped_position(i, t)));
  for (auto e = static_cast<std::ptrdiff_t>(lists_.exposed(c).size()) - 1; e >= 0; --e)
    drop_out_of_reach(lists_.exposed(c)[e]);
  keeper_.reset(c, t);
  // Predictions already filed stay valid (exact contact times, or searches that look at
  // the lists when they run). The pairs that came into reach need predictions, and so
  // do the rotating partners, whose last search may have stopped at the old expiry.
  pairs_.clear();
  for (int i : s_.clusters[c].members) {
    for_each_foreign_near(i, [&](int j) { return !lists_.listed(i, j); }, [&](int j) {
      lists_.add_pair(i, j, cluster);
      pairs_.push_back({body_of(j), i, j});
    });
  }
  const bool rotating = !bodies_.translates(s_, c);
  for (int i : lists_.exposed(c))
    for (int j : lists_.partners(i))
      if (rotating || !bodies_.translates(s_, body_of(j))) pairs_.push_back({body_of(j), i, j});
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  batch_.clear();
  if (keeper_.renew_expiry(c) < kNever) batch_.push_back({keeper_.expiry(c), c, 0, s_.clusters[c].stamp, 0, EventKind::list_rebuild});
  predict_pairs(c, t);
  calendar_.file(c, batch_);
  count_.queue_peak = std::max<std::int64_t>(count_.queue_peak, calendar_.size());
  count_.rebuilt_spheres += s_.clusters[c].size();
  ++count_.list_rebuilds;
  return {.time = t, .kind = EventKind::list_rebuild, .cluster = c};
}

template void RigidBodyCore<2>::build_spatial();
template void RigidBodyCore<3>::build_spatial();
template void RigidBodyCore<2>::drop_out_of_reach(int);
template void RigidBodyCore<3>::drop_out_of_reach(int);
template EventRecord RigidBodyCore<2>::rebuild(int, double);
template EventRecord RigidBodyCore<3>::rebuild(int, double);

}  // namespace ballagg
