#include "plot_command.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "plot_script.hpp"

namespace ballagg::cli {

void add_plot_command(CLI::App& app, PlotCommand& p) {
  p.command = app.add_subcommand("plot", "Draw the figures of sweeps (PNG, matplotlib), their points together");
  p.command->add_option("sweep_dirs", p.sweep_dirs, "Sweep directories (with sweep.csv)")->required();
  p.command->add_option("--out", p.out_dir, "Where to write the PNG files (default: the first SWEEP_DIR/figures)");
}

int run_plot_command(const PlotCommand& p) {
  for (const std::string& dir : p.sweep_dirs)
    if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("{}: not a sweep directory", dir));
  const char* env = std::getenv("BALLAGG_PYTHON");
  const std::string python = env != nullptr && *env != '\0' ? env : "/usr/bin/python3";
  std::vector<std::string> args = {python, "-"};
  if (!p.out_dir.empty()) args.insert(args.end(), {"--out", p.out_dir});
  args.insert(args.end(), p.sweep_dirs.begin(), p.sweep_dirs.end());

  // The script goes to the interpreter's standard input ("python3 -"): no temporary file.
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) throw std::runtime_error(fmt::format("cannot create a pipe: {}", std::strerror(errno)));
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error(fmt::format("cannot start {}: {}", python, std::strerror(errno)));
  if (child == 0) {
    dup2(pipe_fds[0], STDIN_FILENO);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(python.c_str(), argv.data());
    fmt::print(stderr, "ballagg: error: cannot run {}: {} (install python3-matplotlib: scripts/setup)\n", python,
               std::strerror(errno));
    _exit(2);
  }
  close(pipe_fds[0]);
  const std::string script = kPlotScript;
  std::size_t written = 0;
  while (written < script.size()) {
    const ssize_t n = write(pipe_fds[1], script.data() + written, script.size() - written);
    if (n <= 0) break;  // the interpreter is gone: its status says why
    written += static_cast<std::size_t>(n);
  }
  close(pipe_fds[1]);
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace ballagg::cli
