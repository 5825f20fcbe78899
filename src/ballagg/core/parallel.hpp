#pragma once
// OpenMP thread queries that also compile without OpenMP (one thread).
#ifdef _OPENMP
#include <omp.h>
#endif

namespace ballagg {

inline int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
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
