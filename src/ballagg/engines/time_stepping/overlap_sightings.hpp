#pragma once
// The largest relative overlap a step leaves (counters' max_residual_overlap), from what
// the step's contact passes see, without a pass of its own over every moved sphere.
//
// The pass that follows a sphere's last move sees every pair of it at its final distance;
// a pair seen earlier, when a later pass moved one of its spheres again, is out of date
// (and may have come apart since, unseen): a sighting counts only if it is from the last
// pass that moved either of its spheres.
#include <cstdint>
#include <vector>

namespace ballagg {

class OverlapSightings {
 public:
  // For a run over n spheres, on up to max_threads() threads.
  void reset(int n_spheres);
  // Sphere i is moved before the next pass (one thread per sphere).
  void moved(int i) { last_pass_[i] = pass_; }
  const std::vector<std::int32_t>& last_passes() const { return last_pass_; }
  // Opens a pass (the outdated records dropped when they have piled up); returns its number.
  std::int32_t begin_pass();
  // A pair the pass saw overlapping by `overlap` (from the calling thread).
  void seen(std::int32_t i, std::int32_t j, std::int32_t pass, double overlap);
  // The largest overlap that is still up to date; clears the step's records (moved_in_step:
  // every sphere the step moved).
  double residual(const std::vector<int>& moved_in_step);

 private:
  struct Sighting {
    std::int32_t i, j, pass;
    double overlap;
  };
  void forget_outdated();

  std::vector<std::int32_t> last_pass_;  // per sphere: the pass that saw it last moved (-1: none)
  std::int32_t pass_ = 0;                // the next pass of the step
  std::size_t forget_at_ = 0;            // records beyond which the outdated are dropped
  std::vector<std::vector<Sighting>> sightings_;  // per thread
};

}  // namespace ballagg
