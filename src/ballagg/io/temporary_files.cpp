#include "ballagg/io/temporary_files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <climits>
#include <cstring>

namespace ballagg {
namespace {

// A slot is free, being written (not to be read), or holding a path.
enum SlotState : int { kFree = 0, kWriting = 1, kHolding = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};

std::array<Slot, kMaxRegisteredTemporaries> g_slots;

}  // namespace

void UnreferencedTemporary::hold(const std::string& path) {
  release();
  if (path.size() >= PATH_MAX) return;
  for (int k = 0; k < kMaxRegisteredTemporaries; ++k) {
    int expected = kFree;
    if (!g_slots[k].state.compare_exchange_strong(expected, kWriting)) continue;
    std::memcpy(g_slots[k].path, path.c_str(), path.size() + 1);
    g_slots[k].state.store(kHolding);
    slot_ = k;
    return;
  }
}

void UnreferencedTemporary::release() {
  if (slot_ < 0) return;
  g_slots[slot_].state.store(kFree);
  slot_ = -1;
}

void remove_unreferenced_temporaries() noexcept {
  for (Slot& s : g_slots)
    if (s.state.load() == kHolding) ::unlink(s.path);
}

}  // namespace ballagg
