#pragma once
// OpenMP thread queries that also compile without OpenMP (one thread).
#ifdef _OPENMP
#include <omp.h>
#endif

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ballagg {

// Loops over fewer items than this run on one thread. Opening a parallel region costs a
// few microseconds when every core is free, but up to a scheduler time slice (milliseconds)
// when another process holds a core: the region waits for its last thread. A small loop
// gains less from a second thread than that wait can cost.
inline constexpr std::int64_t kParallelLoopMin = 4096;

inline int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// The number of threads of the current team (1 outside a parallel region).
inline int team_size() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

inline int thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// Storage kept per thread from one region to the next, indexed by thread_index(): made to
// hold an entry for every thread of the next team before it starts. The team may grow
// between two regions of a run (core/adaptive_team.hpp).
template <class PerThread>
void fit_to_team(std::vector<PerThread>& per_thread) {
  const std::size_t threads = static_cast<std::size_t>(max_threads());
  if (per_thread.size() < threads) per_thread.resize(threads);
}

}  // namespace ballagg
