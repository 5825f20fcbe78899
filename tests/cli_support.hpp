#pragma once
// Running the ballagg binary from a test: each argument quoted for the shell, its status,
// stdout and stderr captured; a run that hangs is killed after a minute (status 124).
// Used by test_cli, test_sweep, test_snapshots and test_render.
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

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write(const std::filesystem::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

inline std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct Outcome {
  int status = -1;
  std::string out, err;
};

// Runs `launcher ballagg args...` with its output captured in files of `scratch` (then
// removed). `launcher` is a shell prefix such as "mpirun -np 2", empty for a plain run.
inline Outcome run_ballagg(const std::vector<std::string>& args, const std::filesystem::path& scratch,
                           const std::string& launcher = "") {
  std::string command = "timeout -k 5 60 ";
  if (!launcher.empty()) command.append(launcher).append(" ");
  command += quoted(BALLAGG_BINARY);
  for (const std::string& a : args) command.append(" ").append(quoted(a));
  const std::filesystem::path out = scratch / ".stdout", err = scratch / ".stderr";
  command.append(" >").append(quoted(out.string())).append(" 2>").append(quoted(err.string()));
  command.append(" </dev/null");
  const int raw = std::system(command.c_str());
  Outcome o;
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.out = slurp(out);
  o.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return o;
}

}  // namespace ballagg::testing
