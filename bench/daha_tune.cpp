// Records the minimisation problems of time-stepping runs, and replays them with other DAHA
// parameters: the tool behind the tuned defaults of [ts] (docs/time_stepping.md,
// "Parameters"); bench/daha_tune.py searches with it.
//
//   ballagg_daha_tune record OUT.txt [CONFIG.toml] [--set KEY=VALUE ...] [--every K]
//       runs the simulation (engine.kind = "ts") and writes every K-th problem to OUT.txt
//   ballagg_daha_tune replay FILE ... [--set ts.KEY=VALUE ...] [--verbose]
//       solves every problem of the files with the [ts] parameters given (defaults
//       otherwise) and prints: problems, DAHA iterations, problems not converged, work
//       (iterations times problem size, summed), the work spent on those not converged,
//       seconds; --verbose adds a line per problem
//
// The file is text: per problem a line "problem D variables pairs n_spheres range
// positions", the inverse masses, then one line per pair (a b base... sigma lambda attract
// within_range guard), then the positions of the all-pairs attraction, if any.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "ballagg/config/config.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/simulation.hpp"

namespace {

using namespace ballagg;

template <int D>
void write_problem(std::ostream& out, const DahaProblem<D>& p) {
  out << fmt::format("problem {} {} {} {} {} {}\n", D, p.inverse_mass.size(), p.pairs.size(), p.n_spheres, p.range,
                     p.position.size());
  for (double w : p.inverse_mass) out << fmt::format("{} ", w);
  out << "\n";
  for (const DahaPair<D>& q : p.pairs) {
    out << q.a << ' ' << q.b;
    for (int k = 0; k < D; ++k) out << fmt::format(" {}", q.base[k]);
    out << fmt::format(" {} {} {} {} {}\n", q.sigma, q.lambda, int(q.attract), int(q.attract_within_range), int(q.guard));
  }
  for (const Vec<D>& x : p.position) {
    for (int k = 0; k < D; ++k) out << fmt::format("{} ", x[k]);
    out << "\n";
  }
}

template <int D>
DahaProblem<D> read_problem(std::istream& in, std::size_t n_vars, std::size_t n_pairs, int n_spheres, double range,
                            std::size_t n_positions) {
  DahaProblem<D> p;
  p.n_spheres = n_spheres;
  p.range = range;
  p.inverse_mass.resize(n_vars);
  for (double& w : p.inverse_mass) in >> w;
  p.pairs.resize(n_pairs);
  for (DahaPair<D>& q : p.pairs) {
    int attract, within, guard;
    in >> q.a >> q.b;
    for (int k = 0; k < D; ++k) in >> q.base[k];
    in >> q.sigma >> q.lambda >> attract >> within >> guard;
    q.attract = attract;
    q.attract_within_range = within;
    q.guard = guard;
  }
  p.position.resize(n_positions);
  for (Vec<D>& x : p.position)
    for (int k = 0; k < D; ++k) in >> x[k];
  return p;
}

template <int D>
class FileSink final : public DahaProblemSink<D> {
 public:
  FileSink(std::ostream& out, int every) : out_(out), every_(every) {}
  void record(const DahaProblem<D>& problem) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (seen_++ % every_ == 0) write_problem(out_, problem);
  }

 private:
  std::ostream& out_;
  int every_;
  std::int64_t seen_ = 0;
  std::mutex mutex_;
};

template <int D>
void record(const Config& given, std::ostream& out, int every) {
  State<D> s = make_initial_state<D>(given);
  const Config c = resolve_defaults(given, s);
  FileSink<D> sink(out, every);
  RunObserver<D> none;
  const RunResult r = make_time_stepping_engine<D>(c.ts, &sink)->run(s, stop_criteria(c), none);
  std::cerr << fmt::format("recorded every {}th of {} minimisations ({} steps, {:.1f} s)\n", every,
                           r.count("minimisations"), r.counters.steps, r.wall_seconds);
}

// What replaying costs: work counts pair and variable updates (iterations times the size of
// the problem), the measure the search minimises, free of the machine's noise.
struct Totals {
  std::int64_t problems = 0, iterations = 0, failed = 0;
  double work = 0.0, failed_work = 0.0;
};

template <int D>
void solve(DahaProblem<D> p, const DahaParameters& params, Totals& t, bool verbose) {
  std::vector<Vec<D>> u;
  double deepest = 0.0;
  int guards = 0;
  for (const DahaPair<D>& q : p.pairs) {
    deepest = std::max(deepest, 1.0 - q.base.norm() / q.sigma);
    guards += q.guard;
  }
  const double size = static_cast<double>(p.pairs.size() + p.inverse_mass.size());
  const DahaResult r = minimise(p, params, u);
  ++t.problems;
  t.iterations += r.iterations;
  t.work += r.iterations * size;
  if (!r.converged) {
    ++t.failed;
    t.failed_work += r.iterations * size;
  }
  if (verbose)
    fmt::print("variables {} pairs {} guards {} deepest {:.3f} iterations {} converged {} residual {:.3g}\n",
               p.inverse_mass.size(), p.pairs.size(), guards, deepest, r.iterations, int(r.converged),
               r.residual_overlap);
}

int usage() {
  std::cerr << "usage: ballagg_daha_tune record OUT.txt [CONFIG.toml] [--set KEY=VALUE ...] [--every K]\n"
               "       ballagg_daha_tune replay FILE ... [--set ts.KEY=VALUE ...] [--verbose]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string mode = argv[1];
  std::vector<std::string> files, overrides;
  int every = 1;
  bool verbose = false;
  for (int k = 2; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--set" && k + 1 < argc) overrides.push_back(argv[++k]);
    else if (a == "--every" && k + 1 < argc) every = std::max(1, std::stoi(argv[++k]));
    else if (a == "--verbose") verbose = true;
    else files.push_back(a);
  }
  try {
    if (mode == "record") {
      if (files.empty() || files.size() > 2) return usage();
      Config c = load_config(files.size() == 2 ? files[1] : "", overrides);
      if (c.engine.kind != EngineKind::ts) throw InputError("record needs engine.kind = \"ts\"");
      std::ofstream out(files[0]);
      if (c.system.dimension == 2) record<2>(c, out, every);
      else record<3>(c, out, every);
      return 0;
    }
    if (mode != "replay" || files.empty()) return usage();
    const DahaParameters params = load_config("", overrides).ts.daha;
    Totals t;
    const auto started = std::chrono::steady_clock::now();
    for (const std::string& f : files) {
      std::ifstream in(f);
      if (!in) throw InputError(fmt::format("{}: cannot be read", f));
      std::string tag;
      int d, n_spheres;
      std::size_t n_vars, n_pairs, n_positions;
      double range;
      while (in >> tag >> d >> n_vars >> n_pairs >> n_spheres >> range >> n_positions) {
        if (d == 2) solve(read_problem<2>(in, n_vars, n_pairs, n_spheres, range, n_positions), params, t, verbose);
        else solve(read_problem<3>(in, n_vars, n_pairs, n_spheres, range, n_positions), params, t, verbose);
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    fmt::print("problems {} iterations {} failed {} work {:.6g} failed_work {:.6g} seconds {:.3f}\n", t.problems,
               t.iterations, t.failed, t.work, t.failed_work, seconds);
    return 0;
  } catch (const InputError& e) {
    std::cerr << "ballagg_daha_tune: error: " << e.what() << "\n";
    return 2;
  }
}
