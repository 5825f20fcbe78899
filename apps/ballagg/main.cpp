// The ballagg command line. Exit status (docs/hardening.md): 0 success; 2 bad input
// (one line on stderr, nothing written) or an output file that cannot be written (one
// line naming it, nothing half-written); 1 any other failure; 128 + N after signal N.
// The commands and options are registered in command_line.cpp; here the chosen one is run.
#include <csignal>
#include <iostream>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "ballagg/config/config.hpp"
#include "ballagg/io/hdf5_handle.hpp"
#include "ballagg/io/output_error.hpp"
#include "ballagg/run/checkpointer.hpp"
#include "ballagg/run/resolved_config.hpp"
#include "ballagg/run/simulation.hpp"
#include "command_line.hpp"
#include "end_of_run_report.hpp"

int main(int argc, char** argv) {
  ballagg::hdf5::no_library_exit_handler();  // every file is closed by its owner
  // A write beyond the file-size limit (ulimit -f) fails with EFBIG, reported like a full
  // disk, instead of ending the program by SIGXFSZ with its temporary files left behind.
  // ffmpeg (render --video) inherits it.
  std::signal(SIGXFSZ, SIG_IGN);
  ballagg::cli::CommandLine cl;
  if (const std::optional<int> status = ballagg::cli::parse_command_line(cl, argc, argv)) return *status;

  try {
    if (*cl.analyze.command) return ballagg::cli::run_analyze_command(cl.analyze);
    if (*cl.sweep.command) return ballagg::cli::run_sweep_command(cl.sweep);
    if (*cl.plot.command) return ballagg::cli::run_plot_command(cl.plot);
    if (*cl.render.command) return ballagg::cli::run_render_command(cl.render);
    if (*cl.verify.command) return ballagg::cli::run_verify_command(cl.verify);
    if (*cl.show) {
      const ballagg::Config c = ballagg::load_config(cl.show_args.file, cl.show_args.overrides);
      std::cout << ballagg::to_toml_text(ballagg::resolved_config(c));
      return 0;
    }
    std::string dir;
    if (!cl.resume_dir.empty()) {
      dir = ballagg::resume_simulation(cl.resume_dir, cl.run_options);
    } else {
      ballagg::Config c = ballagg::load_config(cl.run_args.file, cl.run_args.overrides);
      if (cl.seed) c.initial.seed = *cl.seed;
      dir = ballagg::run_simulation(c, cl.run_options);
    }
    if (!cl.run_options.quiet) fmt::print("{}", ballagg::cli::run_report_of(dir));
    fmt::print("results in {}\n", dir);
    return 0;
  } catch (const ballagg::RunInterrupted& e) {
    fmt::print(stderr, "ballagg: {}\n", e.what());
    return 128 + e.signal();
  } catch (const ballagg::InputError& e) {
    fmt::print(stderr, "ballagg: error: {}\n", e.what());
    return ballagg::cli::kBadInput;
  } catch (const ballagg::OutputError& e) {
    fmt::print(stderr, "ballagg: error: {}\n", e.what());
    return ballagg::cli::kBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "ballagg: failed: {}\n", e.what());
    return 1;
  }
}
