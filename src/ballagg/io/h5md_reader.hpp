#pragma once
// Reads the trajectory.h5md files of H5mdWriter back: the particles, the number of frames,
// any one frame. Errors are InputError naming the file (`ballagg render` reports them).
#include <memory>
#include <string>
#include <vector>

#include "ballagg/io/frame.hpp"

namespace ballagg {

template <int D>
class H5mdReader {
 public:
  explicit H5mdReader(const std::string& path);
  ~H5mdReader();
  H5mdReader(H5mdReader&&) noexcept;

  int frames() const;
  const Particles<D>& particles() const;
  Frame<D> frame(int k) const;
  // The time of every frame, in file order (without reading the frames).
  std::vector<double> times() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ballagg
