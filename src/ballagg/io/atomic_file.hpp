#pragma once
// One output file written under a temporary name next to it (.NAME.tmp) and renamed into
// place when complete, so that neither a reader nor a crash ever sees it half-written.
// Written with POSIX calls so that a failure keeps its errno: every failure (cannot
// create, a short write, fsync, close, rename) throws OutputError naming the final path
// and the reason ("DIR/final.csv: cannot write: No space left on device"), after removing
// the temporary file.
#include <cstdint>
#include <string>
#include <string_view>

#include "ballagg/io/output_error.hpp"
#include "ballagg/io/temporary_files.hpp"

namespace ballagg {

class AtomicFile {
 public:
  // Creates (or empties) the temporary file of `path`.
  explicit AtomicFile(std::string path);
  // Continues the temporary file of `path` left by an interrupted run, cut back to `size`
  // bytes (the caller has checked that it holds as many).
  AtomicFile(std::string path, std::uint64_t size);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Unless committed or kept: removes the temporary file.
  ~AtomicFile();

  void write(std::string_view bytes);
  // Overwrites bytes already written (a header completed at the end), leaving the position
  // where write() continues unchanged.
  void write_at(std::uint64_t offset, std::string_view bytes);
  // Forces what was written to the disk (fsync), for a file that must survive a crash.
  void sync();
  // Closes the file and renames it to its path.
  void commit();
  // The destructor leaves the temporary file (a checkpoint refers to it).
  void keep() {
    keep_ = true;
    registered_.release();
  }

  const std::string& path() const { return path_; }
  const std::string& temporary() const { return temporary_; }

 private:
  [[noreturn]] void fail(int error);

  std::string path_, temporary_;
  int fd_ = -1;
  bool keep_ = false;
  UnreferencedTemporary registered_;  // until committed or kept: a forced quit removes it
};

}  // namespace ballagg
