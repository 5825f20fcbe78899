#pragma once
// The tables of a sweep directory (docs/sweeps.md), from the runs' summary.json and
// analysis files: runs.csv (one row per run: its variant and grid values, every
// indicator), sweep.csv (one row per grid point: mean and standard deviation of the mean
// of each indicator over its realizations), sweep_box_counting.csv and
// sweep_pair_distribution.csv (the curves N(eps) and P(r), averaged likewise). Runs
// stopped by stop.wall_seconds are listed in runs.csv but left out of the means (counted
// in sweep.csv's runs_cut).
#include <string>
#include <vector>

#include "ballagg/sweep/sweep_spec.hpp"

namespace ballagg {

// Mean and standard deviation of the mean, sqrt(sum (x - mean)^2 / (n (n - 1))), of the
// finite values (NaN for the deviation of fewer than two).
struct MeanAndError {
  double mean = 0.0, error = 0.0;
  int count = 0;
};
MeanAndError mean_and_error(const std::vector<double>& values);

// Reads the finished runs under out_dir/runs and writes the four tables into out_dir.
void write_sweep_tables(const std::string& out_dir, const SweepSpec& spec, const std::vector<SweepPoint>& points,
                        const std::vector<SweepRun>& runs);

}  // namespace ballagg
