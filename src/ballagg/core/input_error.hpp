#pragma once
// Bad input: a configuration, an input file, a command-line argument or a checkpoint that
// cannot be used. The message is one line for the user; the command line exits with
// status 2. Every layer may throw it, so it lives at the bottom.
#include <stdexcept>

namespace ballagg {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ballagg
