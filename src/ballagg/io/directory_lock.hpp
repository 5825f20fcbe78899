#pragma once
// The lock of a directory that one process writes (a run directory, a sweep directory):
// an advisory lock (flock) on DIR/.ballagg.lock, held while the directory is written and
// released when the process ends in any way, kill -9 included (the kernel drops it). A
// second writer is refused at once, with one line naming the holder, instead of
// interleaving its files with the first one's (docs/outputs.md, "One writer at a time").
#include <string>

namespace ballagg {

inline constexpr const char* kLockFile = ".ballagg.lock";

class DirectoryLock {
 public:
  // Takes the lock of `dir`, which must exist. Throws InputError "DIR: another ballagg
  // process (pid N) is writing this directory ..." when another process holds it, or one
  // naming the reason when the lock file cannot be created.
  explicit DirectoryLock(const std::string& dir);
  DirectoryLock(DirectoryLock&& other) noexcept;
  DirectoryLock& operator=(DirectoryLock&&) = delete;
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  // Removes the lock file and releases the lock.
  ~DirectoryLock();

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace ballagg
