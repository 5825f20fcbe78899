#!/usr/bin/env bash
# The reproduction of Degond et al. 2023, Table 1 (docs/validation.md): ED against the
# time-stepping method, ten realizations per point, N = 100 ... 10^6, then the
# figures. Extra arguments go to the five sweeps (e.g. --resume after a stop, --jobs 4 on
# a bigger machine).
# Usage: bench/reproduce_table1.sh [sweep options]
set -euo pipefail
cd "$(dirname "$0")/.."
B=build/bin/ballagg
export OMP_NUM_THREADS=1   # the sweeps run concurrent single-threaded runs
$B sweep bench/paper_table1_sweep.toml --out out/paper_table1 --jobs 2 --quiet "$@"
$B sweep bench/paper_table1_per_sphere.toml --out out/paper_table1_per_sphere --jobs 2 --quiet "$@"
$B sweep bench/paper_table1_large.toml --out out/paper_table1_large --jobs 2 --quiet "$@"
$B sweep bench/paper_table1_vf03.toml --out out/paper_table1_vf03 --jobs 2 --quiet "$@"
$B sweep bench/paper_table1_1e6.toml --out out/paper_table1_1e6 --jobs 2 --quiet "$@"
$B plot out/paper_table1 out/paper_table1_per_sphere out/paper_table1_large out/paper_table1_vf03 \
  out/paper_table1_1e6 --out docs/figures/table1
