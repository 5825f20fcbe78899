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
  p.command = app.add_subcommand(
      "plot", "Draw the figures of sweeps (their points together) or of runs (matplotlib: PNG, PDF or SVG)");
  p.command->add_option("DIR", p.dirs, "Sweep directories (with sweep.csv) or run directories (with timeseries.csv)")
      ->type_name("DIR");
  p.command->add_option("--out", p.out_dir, "Where to write the figures (default: the first DIR/figures)");
  // The values are checked by the script, which a user may also run on its own.
  p.command->add_option("--format", p.format, "png (default), pdf or svg");
  p.command->add_option("--dpi", p.dpi, "Dots per inch of a PNG (default 300)")->type_name("N");
  p.command->add_option("--size", p.size, "Size of one panel in inches (default 3.4x2.6: one journal column)")
      ->type_name("WIDTHxHEIGHT");
  p.command->add_option("--style", p.style, "A matplotlib style file applied on top of the defaults")->type_name("FILE");
  p.command->add_option("--script", p.script, "Run this plotting script instead of the built-in one (an edited copy)")
      ->type_name("FILE");
  CLI::Option* print = p.command->add_flag("--print-script", p.print_script,
                                           "Write the built-in plotting script to standard output, to copy and edit");
  for (const char* other : {"DIR", "--out", "--format", "--dpi", "--size", "--style", "--script"})
    print->excludes(p.command->get_option(other));
}

int run_plot_command(const PlotCommand& p) {
  if (p.print_script) {
    fmt::print("{}", kPlotScript);
    return 0;
  }
  if (p.dirs.empty()) throw InputError("plot: no directory given (usage: ballagg plot [OPTIONS] DIR..., see ballagg plot --help)");
  for (const std::string& dir : p.dirs)
    if (!std::filesystem::is_directory(dir))
      throw InputError(fmt::format("{}: not a sweep directory nor a run directory ({})", dir,
                                   std::filesystem::exists(dir) ? "not a directory" : "no such directory"));
  if (!p.script.empty() && !std::filesystem::is_regular_file(p.script))
    throw InputError(fmt::format("--script {}: no such file (write the built-in one with: ballagg plot --print-script > FILE)",
                                 p.script));
  const char* env = std::getenv("BALLAGG_PYTHON");
  const std::string python = env != nullptr && *env != '\0' ? env : "/usr/bin/python3";
  std::vector<std::string> args = {python, p.script.empty() ? "-" : p.script};
  for (const auto& [name, value] : {std::pair{"--out", &p.out_dir}, std::pair{"--format", &p.format},
                                    std::pair{"--dpi", &p.dpi}, std::pair{"--size", &p.size}, std::pair{"--style", &p.style}})
    if (!value->empty()) args.insert(args.end(), {name, *value});
  // "--": a directory named like an option stays a directory.
  args.push_back("--");
  args.insert(args.end(), p.dirs.begin(), p.dirs.end());

  // The built-in script goes to the interpreter's standard input ("python3 -"): no
  // temporary file. A --script file is read by the interpreter itself.
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
  const std::string script = p.script.empty() ? kPlotScript : "";
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
