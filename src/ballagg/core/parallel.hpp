#pragma once
// OpenMP thread queries that also compile without OpenMP (one thread).
#ifdef _OPENMP
#include <omp.h>
#endif

#include <cstdint>

namespace ballagg {

// Loops over fewer items than this run on one thread. Opening a parallel region costs a
// few microseconds when every core is free, but up to a scheduler time slice (milliseconds)
// when another process holds a core: the region waits for its last thread. A test of 400
// discs ran 10 times slower on two threads than on one while a run used the other core.
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

}  // namespace ballagg
