#pragma once
// An output file that could not be written: a full disk (ENOSPC), a file-size limit
// (EFBIG), a directory that cannot be written or has gone. The message is one line naming
// the file and the reason; the command line exits with status 2, as for bad input, and no
// half-written file is left (every output goes through a temporary name, atomic_file.hpp).
// docs/hardening.md.
#include <cstring>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace ballagg {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "PATH: cannot write: REASON", REASON the text of the errno value `error`.
[[noreturn]] inline void throw_output_error(const std::string& path, int error) {
  throw OutputError(fmt::format("{}: cannot write: {}", path, std::strerror(error)));
}

}  // namespace ballagg
