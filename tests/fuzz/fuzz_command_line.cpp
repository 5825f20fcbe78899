// libFuzzer target: the command-line parser (every command and option of ballagg, as
// registered for the real program), without running the chosen command. The input is
// split at NUL bytes into argv[1..]. Any argv must parse, or stop with --help/--version
// (status 0) or one line of bad input (status 2); never a crash or an exception. Run with
// -close_fd_mask=3 (make fuzz): the help and error texts are not what is tested, and
// libFuzzer keeps the sanitizers' reports on its own copy of stderr.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "command_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"ballagg"};
  std::string current;
  for (std::size_t k = 0; k < size; ++k) {
    if (data[k] == 0) {
      args.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[k]));
    }
  }
  if (!current.empty() || size == 0) args.push_back(current);
  if (args.size() > 64) return 0;  // a longer command line tests nothing new
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  ballagg::cli::CommandLine cl;
  const std::optional<int> status = ballagg::cli::parse_command_line(cl, static_cast<int>(argv.size()), argv.data());
  if (status && *status != 0 && *status != ballagg::cli::kBadInput) std::abort();
  return 0;
}
