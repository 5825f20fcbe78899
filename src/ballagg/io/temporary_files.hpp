#pragma once
// The temporary files of the process that nothing refers to: output files being written
// (.NAME.tmp, io/atomic_file.hpp) and trajectories no checkpoint refers to yet. A forced
// quit (a second SIGINT, SIGTERM or SIGHUP, run/checkpointer.hpp) removes them from its
// signal handler, so that quitting never leaves one behind; a temporary file a checkpoint
// refers to is not registered (the resumed run continues it).
#include <string>

namespace ballagg {

// How many can be registered at once (a sweep's concurrent runs have a few each). Beyond,
// a file is not registered: a forced quit then leaves it, as it would without us.
inline constexpr int kMaxRegisteredTemporaries = 256;

// Registers a path while alive, until release().
class UnreferencedTemporary {
 public:
  UnreferencedTemporary() = default;
  explicit UnreferencedTemporary(const std::string& path) { hold(path); }
  ~UnreferencedTemporary() { release(); }
  UnreferencedTemporary(const UnreferencedTemporary&) = delete;
  UnreferencedTemporary& operator=(const UnreferencedTemporary&) = delete;
  // Registers `path` (after releasing what was held).
  void hold(const std::string& path);
  // The file is renamed into place, removed, or referred to by a checkpoint.
  void release();

 private:
  int slot_ = -1;
};

// Removes every registered file. Async-signal-safe (unlink only).
void remove_unreferenced_temporaries() noexcept;

}  // namespace ballagg
