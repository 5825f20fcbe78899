#include "sweep_command.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "ballagg/run/checkpointer.hpp"

namespace ballagg::cli {

void add_sweep_command(CLI::App& app, SweepCommand& s) {
  s.command = app.add_subcommand("sweep", "Run a parameter grid times realizations, in parallel (and under mpirun), "
                                          "and tabulate means and errors");
  s.command->add_option("sweep_file", s.file, "Sweep file (TOML: [sweep], [grid], [[variants]])")->required();
  s.command->add_option("--out", s.options.out_dir, "Sweep directory (default: out/<sweep file name>)");
  s.command->add_flag("--resume", s.options.resume, "Continue the sweep in --out: finished runs are not redone");
  s.command->add_option("--jobs,-j", s.options.jobs, "Runs at once per process (default: the cores; 1 under mpirun)")
      ->check(CLI::Range(1, 4096));
  s.command->add_option("--threads", s.options.threads_per_run, "OpenMP threads of each run (default 1)")
      ->check(CLI::Range(1, 4096));
  s.command->add_flag("--quiet,-q", s.options.quiet, "No progress lines (the last line, the runs done, stays)");
}

int run_sweep_command(SweepCommand& s) {
  const Communicator world;
  const SweepSpec spec = load_sweep(s.file);
  if (s.options.out_dir.empty()) s.options.out_dir = (std::filesystem::path("out") / std::filesystem::path(s.file).stem()).string();
  // Signals stop the runs under way, and the sweep after writing its tables (sweep_runner.hpp).
  const InterruptFlag interrupts;
  const SweepOutcome outcome = run_sweep(spec, s.options, world);
  const std::string tables = (std::filesystem::path(s.options.out_dir) / "sweep.csv").string();
  if (outcome.signal != 0) {
    if (world.rank() == 0) {
      const long long done = outcome.ran + outcome.skipped;
      fmt::print(stderr,
                 "ballagg: sweep interrupted by {}: {} of {} runs done ({} by this command), {} failed; tables of the "
                 "runs done in {}; continue with: ballagg sweep {} --out {} --resume\n",
                 signal_name(outcome.signal), done, outcome.total, outcome.ran, outcome.failed, tables, s.file,
                 s.options.out_dir);
    }
    return 128 + outcome.signal;
  }
  if (world.rank() == 0) {
    fmt::print("sweep: {} runs done, {} already finished, {} failed; tables in {}\n", outcome.ran, outcome.skipped,
               outcome.failed, tables);
  }
  return outcome.failed > 0 ? 1 : 0;
}

}  // namespace ballagg::cli
