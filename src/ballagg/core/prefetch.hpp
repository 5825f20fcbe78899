#pragma once
// A hint to start loading the cache line holding *p, so that several independent memory
// accesses overlap instead of queuing one behind the other.
//
// GCC deletes a loop whose only statements are __builtin_prefetch calls (the hints do not
// change what the program computes), so on x86 the instruction is issued from an asm
// statement, which it must keep. It changes no result, only when data arrives.
#include <cstddef>

namespace ballagg {

inline void prefetch(const void* p) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

// How many entries ahead the loops over a list of scattered ids (a giant cluster's members,
// the spheres a solution moves) ask for the data of the id they will reach: far enough for
// a load from memory to arrive before it is needed, near enough to stay in the cache (the
// gain levels off beyond this distance).
inline constexpr std::size_t kPrefetchAhead = 16;

// Prefetches entry `ahead` of a list of ids in each of the arrays (anything indexable whose
// entries are contiguous), when the list has one: called at entry k of a loop over the list
// with ahead = k + kPrefetchAhead.
template <class Ids, class... Arrays>
inline void prefetch_entries(const Ids& ids, std::size_t ahead, const Arrays&... arrays) {
  if (ahead >= ids.size()) return;
  const auto id = ids[ahead];
  (prefetch(&arrays[id]), ...);
}

// Calls f(id) for every id of the list in order, asking for each id's entries in the
// arrays kPrefetchAhead ids before f reaches it.
template <class Ids, class F, class... Arrays>
inline void for_each_prefetched(const Ids& ids, F&& f, const Arrays&... arrays) {
  for (std::size_t k = 0; k < ids.size(); ++k) {
    prefetch_entries(ids, k + kPrefetchAhead, arrays...);
    f(ids[k]);
  }
}

}  // namespace ballagg
