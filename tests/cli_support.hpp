#pragma once
// Running the ballagg binary from a test: each argument quoted for the shell, its status,
// stdout and stderr captured; a run that hangs is killed after a minute (status 124).
// Used by test_cli, test_sweep, test_snapshots, test_render and test_bad_input.
#include <sys/wait.h>

#include <chrono>
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
  double seconds = 0.0;  // wall time of the command (run_ballagg_in only)
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

// Runs `ballagg args...` with `cwd` as its working directory (relative arguments are
// relative to it), its output captured in files of `scratch` (another directory, so that
// `cwd` holds only what the command writes), killed after `limit_seconds` (status 124).
inline Outcome run_ballagg_in(const std::filesystem::path& cwd, const std::vector<std::string>& args,
                              const std::filesystem::path& scratch, int limit_seconds) {
  const std::filesystem::path out = scratch / ".stdout", err = scratch / ".stderr";
  std::string command = "cd " + quoted(cwd.string()) + " && exec timeout -k 2 " + std::to_string(limit_seconds) + " " +
                        quoted(BALLAGG_BINARY);
  for (const std::string& a : args) command.append(" ").append(quoted(a));
  command.append(" >").append(quoted(out.string())).append(" 2>").append(quoted(err.string())).append(" </dev/null");
  const auto start = std::chrono::steady_clock::now();
  const int raw = std::system(command.c_str());
  Outcome o;
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.out = slurp(out);
  o.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return o;
}

}  // namespace ballagg::testing
