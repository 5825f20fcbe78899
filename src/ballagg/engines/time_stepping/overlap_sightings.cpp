#include "ballagg/engines/time_stepping/overlap_sightings.hpp"

#include <algorithm>

#include "ballagg/core/parallel.hpp"

namespace ballagg {
namespace {

// Records of overlaps that a thread keeps allocated from one step to the next; beyond,
// the memory is given back (the first steps of a large run see millions of overlaps, the
// later ones a few).
constexpr std::size_t kSightingsKept = std::size_t{1} << 16;

}  // namespace

void OverlapSightings::reset(int n_spheres) {
  last_pass_.assign(n_spheres, -1);
  pass_ = 0;
  forget_at_ = kSightingsKept;
  sightings_.assign(max_threads(), {});
}

std::int32_t OverlapSightings::begin_pass() {
  forget_outdated();
  fit_to_team(sightings_);
  return pass_++;
}

void OverlapSightings::seen(std::int32_t i, std::int32_t j, std::int32_t pass, double overlap) {
  sightings_[thread_index()].push_back({i, j, pass, overlap});
}

// A sighting is out of date once a later pass moved one of its spheres. Many rounds of a
// step each see many overlaps, most soon out of date: they are dropped whenever the
// records have doubled since the last time.
void OverlapSightings::forget_outdated() {
  std::size_t total = 0;
  for (const auto& seen : sightings_) total += seen.size();
  if (total <= forget_at_) return;
  total = 0;
  for (auto& seen : sightings_) {
    std::erase_if(seen, [&](const Sighting& k) { return k.pass < std::max(last_pass_[k.i], last_pass_[k.j]); });
    total += seen.size();
  }
  forget_at_ = std::max(2 * total, kSightingsKept);
}

double OverlapSightings::residual(const std::vector<int>& moved_in_step) {
  double largest = 0.0;
  for (std::vector<Sighting>& seen : sightings_) {
    for (const Sighting& k : seen)
      if (k.pass == std::max(last_pass_[k.i], last_pass_[k.j])) largest = std::max(largest, k.overlap);
    if (seen.capacity() > kSightingsKept) std::vector<Sighting>().swap(seen);
    seen.clear();
  }
  for (int i : moved_in_step) last_pass_[i] = -1;
  pass_ = 0;
  forget_at_ = kSightingsKept;
  return largest;
}

}  // namespace ballagg
