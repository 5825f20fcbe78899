#pragma once
// Running the ballagg binary from a test: arguments quoted for the shell, standard output
// and error captured, a hung command killed after a minute (status 124).
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef BALLAGG_BINARY
#error "BALLAGG_BINARY must name the ballagg executable"
#endif

namespace ballagg::testing {

struct CommandOutcome {
  int status = -1;
  std::string out, err;
};

inline std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `prefix ballagg args...` with its output in scratch files under `scratch`.
inline CommandOutcome run_ballagg(const std::filesystem::path& scratch, const std::vector<std::string>& args,
                                  const std::string& prefix = "") {
  std::string command = "timeout -k 5 60 " + prefix + " " + shell_quoted(BALLAGG_BINARY);
  for (const std::string& a : args) command.append(" ").append(shell_quoted(a));
  const std::filesystem::path out = scratch / ".stdout", err = scratch / ".stderr";
  command.append(" >").append(shell_quoted(out.string())).append(" 2>").append(shell_quoted(err.string()));
  command.append(" </dev/null");
  const int raw = std::system(command.c_str());
  CommandOutcome o;
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.out = read_file(out);
  o.err = read_file(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return o;
}

}  // namespace ballagg::testing
