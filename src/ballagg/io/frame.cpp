#include "ballagg/io/frame.hpp"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include "ballagg/spatial/walls.hpp"

namespace ballagg {

template <int D>
Particles<D> particles_of(const State<D>& s) {
  return {s.box, s.spheres.radius, s.spheres.mass};
}

template <int D>
struct LayoutCopies<D>::Spares {
  std::mutex mutex;
  std::vector<std::unique_ptr<SphereLayout<D>>> copies;
};

template <int D>
LayoutCopies<D>::LayoutCopies() : spares_(std::make_shared<Spares>()) {}

template <int D>
std::shared_ptr<const SphereLayout<D>> LayoutCopies<D>::of(const State<D>& s) {
  const std::uint64_t version = s.layout_version();
  if (last_ && last_->version == version) return last_;
  last_.reset();  // the previous copy is a spare once no frame holds it either
  std::unique_ptr<SphereLayout<D>> copy;
  {
    std::lock_guard lock(spares_->mutex);
    if (!spares_->copies.empty()) {
      copy = std::move(spares_->copies.back());
      spares_->copies.pop_back();
    }
  }
  if (!copy) copy = std::make_unique<SphereLayout<D>>();
  copy->version = version;
  copy->offset = s.spheres.offset;  // reuses the copy's memory: a memcpy
  copy->cluster = s.spheres.cluster;
  // The last holder (the run's thread or a writer's) gives the copy back to the spares;
  // the spares outlive this object while a frame holds a copy.
  last_ = std::shared_ptr<const SphereLayout<D>>(copy.release(), [spares = spares_](const SphereLayout<D>* p) {
    std::unique_ptr<SphereLayout<D>> back(const_cast<SphereLayout<D>*>(p));
    std::lock_guard lock(spares->mutex);
    spares->copies.push_back(std::move(back));
  });
  return last_;
}

template <int D>
void capture_source(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls, FrameSource<D>& out,
                    LayoutCopies<D>& layouts) {
  out.time = t;
  out.step = step;
  out.n_clusters = s.n_clusters();
  out.largest_cluster = s.largest_cluster();
  out.kinetic_energy = s.running_kinetic_energy();
  out.box = s.box;
  out.layout = layouts.of(s);
  // Only live clusters are read and stored: late in a run they are few.
  if (out.slot.size() != s.clusters.size()) out.slot.resize(s.clusters.size());
  out.origin.resize(s.alive_clusters().size());
  out.velocity.resize(s.alive_clusters().size());
  out.angular_velocity.resize(s.spin.empty() ? 0 : s.alive_clusters().size());
  std::int32_t k = 0;
  for (int c : s.alive_clusters()) {
    out.slot[c] = k;
    out.origin[k] = s.origin(c, t);
    out.velocity[k] = s.clusters[c].velocity;
    if (!s.spin.empty()) out.angular_velocity[k] = s.spin[c].angular_velocity;
    if (mirror_at_walls && !s.box.periodic()) {
      const WallCorrection<D> w = wall_correction(s, c, t);
      out.origin[k] += w.shift;
      out.velocity[k] = w.velocity;
    }
    ++k;
  }
}

template <int D>
std::size_t FrameSource<D>::bytes() const {
  const std::size_t shared =
      layout ? layout->offset.capacity() * sizeof(Vec<D>) + layout->cluster.capacity() * sizeof(std::int32_t) : 0;
  return shared + slot.capacity() * sizeof(std::int32_t) + (origin.capacity() + velocity.capacity()) * sizeof(Vec<D>) +
         angular_velocity.capacity() * sizeof(Spin<D>);
}

template <int D>
void FrameAssembler<D>::start(const FrameSource<D>& source) {
  source_ = &source;
  label_.assign(source.origin.size(), -1);
  next_label_ = 0;
  assembled_ = 0;
}

template <int D>
template <class Real>
void FrameAssembler<D>::assemble(int begin, int end, Real* position, Real* velocity, std::int32_t* image,
                                 std::int32_t* cluster) {
  const FrameSource<D>& src = *source_;
  if (begin != assembled_ || end < begin || end > src.size())
    throw std::logic_error("FrameAssembler: spheres assembled out of order");
  const std::vector<Vec<D>>& offset = src.layout->offset;
  const std::vector<std::int32_t>& cluster_of = src.layout->cluster;
  const bool periodic = src.box.periodic();
  const bool rotating = !src.angular_velocity.empty();
  const double length = src.box.length;
  for (int i = begin; i < end; ++i) {
    const int c = src.slot[cluster_of[i]];
    const std::size_t at = static_cast<std::size_t>(i - begin) * D;
    // The same sum as State::position, so the last frame equals final.csv bit for bit.
    const Vec<D> x = src.origin[c] + offset[i];
    const Vec<D> folded = src.box.wrap(x);
    Vec<D> v = src.velocity[c];
    if (rotating) v += cross(src.angular_velocity[c], offset[i]);
    for (int a = 0; a < D; ++a) {
      position[at + a] = static_cast<Real>(folded[a]);
      velocity[at + a] = static_cast<Real>(v[a]);
    }
    if (periodic)
      for (int a = 0; a < D; ++a) image[at + a] = static_cast<std::int32_t>(std::lround((x[a] - folded[a]) / length));
    // Labels in order of each cluster's first sphere.
    std::int32_t& l = label_[c];
    if (l < 0) l = next_label_++;
    cluster[i - begin] = l;
  }
  assembled_ = end;
}

template <int D>
void assemble_frame(const FrameSource<D>& src, Frame<D>& f) {
  const int n = src.size();
  f.time = src.time;
  f.step = src.step;
  f.n_clusters = src.n_clusters;
  f.largest_cluster = src.largest_cluster;
  f.kinetic_energy = src.kinetic_energy;
  f.position.resize(n);
  f.velocity.resize(n);
  f.cluster.resize(n);
  f.image.resize(src.box.periodic() ? n : 0);
  if (n == 0) return;
  FrameAssembler<D> assembler;
  assembler.start(src);
  // A vector of Vec<D> (or Image<D>) is D contiguous values per element.
  assembler.assemble(0, n, f.position.data()->data(), f.velocity.data()->data(),
                     f.image.empty() ? nullptr : f.image.data()->data(), f.cluster.data());
}

template <int D>
Frame<D> capture_frame(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls) {
  FrameSource<D> source;
  LayoutCopies<D> layouts;
  capture_source(s, t, step, mirror_at_walls, source, layouts);
  Frame<D> f;
  assemble_frame(source, f);
  return f;
}

template Particles<2> particles_of<2>(const State<2>&);
template Particles<3> particles_of<3>(const State<3>&);
template class LayoutCopies<2>;
template class LayoutCopies<3>;
template void capture_source<2>(const State<2>&, double, std::int64_t, bool, FrameSource<2>&, LayoutCopies<2>&);
template void capture_source<3>(const State<3>&, double, std::int64_t, bool, FrameSource<3>&, LayoutCopies<3>&);
template struct FrameSource<2>;
template struct FrameSource<3>;
template class FrameAssembler<2>;
template class FrameAssembler<3>;
template void FrameAssembler<2>::assemble<float>(int, int, float*, float*, std::int32_t*, std::int32_t*);
template void FrameAssembler<2>::assemble<double>(int, int, double*, double*, std::int32_t*, std::int32_t*);
template void FrameAssembler<3>::assemble<float>(int, int, float*, float*, std::int32_t*, std::int32_t*);
template void FrameAssembler<3>::assemble<double>(int, int, double*, double*, std::int32_t*, std::int32_t*);
template void assemble_frame<2>(const FrameSource<2>&, Frame<2>&);
template void assemble_frame<3>(const FrameSource<3>&, Frame<3>&);
template Frame<2> capture_frame<2>(const State<2>&, double, std::int64_t, bool);
template Frame<3> capture_frame<3>(const State<3>&, double, std::int64_t, bool);

}  // namespace ballagg
