#pragma once
// Running the ballagg binary from a test: each argument quoted for the shell, its status,
// stdout and stderr captured; a run that hangs is killed after a minute (status 124).
// Used by test_cli, test_sweep, test_snapshots, test_render and test_bad_input.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <functional>
#include <thread>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef BALLAGG_BINARY
#error "BALLAGG_BINARY must name the ballagg executable"
#endif

#include "file_text.hpp"

namespace ballagg::testing {

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

// Starts the binary with `args` in the background, stdout and stderr to `log`, for a test
// that signals it. Returns its process id (-1 if it could not start).
inline pid_t start_ballagg(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<std::string> all{BALLAGG_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, all[0].c_str(), &files, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&files);
  return pid;
}

// Its exit status, or 128 + N if signal N ended it. A process still running after
// `seconds` is killed (SIGKILL: status 137).
inline int exit_status(pid_t pid, double seconds = 60.0) {
  int status = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Polls `ready` every 200 us for at most `seconds`; returns whether it became true.
inline bool wait_until(const std::function<bool()>& ready, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!ready()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return true;
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
