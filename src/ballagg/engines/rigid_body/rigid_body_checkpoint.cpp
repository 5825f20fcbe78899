// The rigid-body engine in a checkpoint: what it saves, and the core restored from it.
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

#include <cmath>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {

template <int D>
RigidBodyCore<D>::RigidBodyCore(State<D>& state, const RigidBodySettings& settings, std::string_view saved)
    : s_(state), settings_(settings), keeper_(RotationDrift<D>(state, bodies_), 0.0), resumed_(true) {
  keep_what_the_law_reads(s_, settings_.collision);
  const int n = s_.n_spheres();
  const int m = static_cast<int>(s_.clusters.size());
  ByteReader r(saved, "checkpoint of the rigid-body engine");
  count_.restore(r);
  loop_ = r.get<EventLoopState>("loop state");
  keeper_.set_skin(r.get<double>("skin"));
  if (!(std::isfinite(keeper_.skin()) && keeper_.skin() > 0.0)) r.fail("neighbour-list skin not a positive number");
  if (r.get<std::int32_t>("sphere count") != n || r.get<std::int32_t>("cluster count") != m)
    r.fail("saved for another number of spheres or clusters");
  s_.spin.resize(m);
  for (ClusterSpin<D>& w : s_.spin) {
    w.angular_velocity = r.get<Spin<D>>("angular velocity");
    w.angular_momentum = r.get<Spin<D>>("angular momentum");
  }
  bodies_.restore(r, m, n);
  grid_radius_ = binned_radius();
  // The grid the run was saved with, so that the resumed run visits the cells as the
  // saved one did: a whole number of cells a side, as wide as the largest radius and the
  // skin need and no more numerous than grid_geometry() makes them (a grid saved with
  // fewer cells per sphere is read as well).
  const double cell_size = r.get<double>("cell size");
  const double per_side = std::round(s_.box.length / cell_size);
  if (!(cell_size >= binning_cell_size(grid_radius_, keeper_.skin()) && per_side >= 1.0 &&
        per_side <= grid_geometry().per_side() && s_.box.length / per_side == cell_size))
    r.fail("cell grid for another largest radius or skin");
  const GridGeometry<D> saved_cells(s_.box, typename GridGeometry<D>::CellsPerSide{static_cast<int>(per_side)});
  grid_ = std::make_unique<CellGrid<D>>(saved_cells, n);
  grid_->restore(r);
  lists_.reset(n, m);
  lists_.restore(r);
  calendar_.reset(m);
  // Each coalescence takes one sphere id away (the last), and stale events may still name
  // it: they are never handled (valid() asks for an id below the sphere count first).
  const std::int64_t ids = n + (settings_.law.coagulation == Coagulation::sphere ? std::max<std::int64_t>(count_.merges, 0) : 0);
  calendar_.restore(r, [&](const Event& e) {
    const bool ok = e.kind == EventKind::collision        ? e.a >= 0 && e.a < e.b && e.b < ids
                    : e.kind == EventKind::wall           ? e.a >= 0 && e.a < ids && e.b >= 0 && e.b < 2 * D
                    : e.kind == EventKind::contact_search ? e.a >= 0 && e.a < m && e.b >= -2 * D && e.b < m && e.b != e.a
                    : e.kind == EventKind::list_rebuild && e.a >= 0 && e.a < m;
    if (!ok) r.fail("an event that names no sphere, body or wall");
  });
  pose_time_ = r.get_vector<double>("pose times", m);
  pose_.resize(m);
  for (Pose& p : pose_) {
    p.rotation = r.get<Rotation<D>>("pose");
    p.angular_velocity = r.get<Spin<D>>("pose");
  }
  keeper_.restore(r, m);
  serial_ = r.get_vector<std::int64_t>("body serials", m);
  partner_ = r.get_vector<std::int64_t>("body partners", m);
  next_serial_ = r.get<std::int64_t>("next serial");
  empty_ = r.get_vector<std::int32_t>("empty clusters", m);
  for (std::int32_t c : empty_)
    if (c < 0 || c >= m || s_.clusters[c].alive()) r.fail("an empty cluster that is not empty");
  merged_sphere_ = r.get_vector<char>("merged spheres", n);
  free_mass_ = r.get<double>("free mass");
  total_mass_ = r.get<double>("total mass");
  spans_box_ = r.get<std::uint8_t>("spans box") != 0;
  if (static_cast<int>(pose_time_.size()) != m || static_cast<int>(serial_.size()) != m || static_cast<int>(partner_.size()) != m ||
      static_cast<int>(merged_sphere_.size()) != n)
    r.fail("per-body or per-sphere arrays of another length");
  r.expect_end();
}

template <int D>
void RigidBodyCore<D>::save(ByteWriter& w) const {
  const int m = static_cast<int>(s_.clusters.size());
  count_.save(w);
  w.put(loop_);
  w.put(keeper_.skin());
  w.put<std::int32_t>(s_.n_spheres());
  w.put<std::int32_t>(m);
  for (const ClusterSpin<D>& c : s_.spin) w.put(c.angular_velocity), w.put(c.angular_momentum);
  bodies_.save(w);
  w.put(grid_->cell_size());
  grid_->save(w);
  lists_.save(w);
  calendar_.save(w);
  w.put_vector(pose_time_);
  for (const Pose& p : pose_) w.put(p.rotation), w.put(p.angular_velocity);
  keeper_.save(w);
  w.put_vector(serial_);
  w.put_vector(partner_);
  w.put(next_serial_);
  w.put_vector(empty_);
  w.put_vector(merged_sphere_);
  w.put(free_mass_);
  w.put(total_mass_);
  w.put<std::uint8_t>(spans_box_);
}


template RigidBodyCore<2>::RigidBodyCore(State<2>&, const RigidBodySettings&, std::string_view);
template RigidBodyCore<3>::RigidBodyCore(State<3>&, const RigidBodySettings&, std::string_view);
template void RigidBodyCore<2>::save(ByteWriter&) const;
template void RigidBodyCore<3>::save(ByteWriter&) const;

}  // namespace ballagg
