#include "verify_command.hpp"

#include <fmt/format.h>

#include "ballagg/run/verify_run.hpp"

namespace ballagg::cli {

void add_verify_command(CLI::App& app, VerifyCommand& v) {
  v.command = app.add_subcommand("verify", "Check a finished run: overlaps, connected clusters, mass and momentum "
                                           "budgets, summary against the final state");
  v.command->add_option("run_dir", v.run_dir, "Run directory")->required();
}

int run_verify_command(const VerifyCommand& v) {
  const Verification r = verify_run(v.run_dir);
  for (const std::string& n : r.notes) fmt::print(stderr, "ballagg verify: note: {}\n", n);
  for (const std::string& line : r.violations) fmt::print("{}\n", line);
  if (!r.violations.empty()) return 1;
  fmt::print("{}: all {} checks hold\n", v.run_dir, r.checks);
  return 0;
}

}  // namespace ballagg::cli
