#pragma once
// A hint to start loading the cache line holding *p, so that several independent memory
// accesses overlap instead of queuing one behind the other.
//
// GCC deletes a loop whose only statements are __builtin_prefetch calls (the hints do not
// change what the program computes), so on x86 the instruction is issued from an asm
// statement, which it must keep. It changes no result, only when data arrives.
namespace ballagg {

inline void prefetch(const void* p) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

}  // namespace ballagg
