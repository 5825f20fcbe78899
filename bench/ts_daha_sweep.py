#!/usr/bin/python3
"""How the DAHA parameters of the time-stepping engine perform on whole runs.

Runs the paper's set-up (2D, lattice, speed 1, walls) to a single cluster for each
parameter set given (each a list of KEY=VALUE settings of [ts]), at several volume
fractions, and prints the total DAHA iterations, the groups placed at contact (failed
minimisations), the largest overlap left and the wall time. Use it to re-tune the
defaults after a change of the minimiser (docs/time_stepping.md, "Parameters").

Usage: bench/ts_daha_sweep.py [--n 900] [--vfs 0.1 0.2 0.3] [--dt-factor 0.01]
                              [--params "alpha=0.5 gamma=1" ...]
The defaults are always included as the first set. Only the standard library is used.
"""
import argparse
import os
import sys
from types import SimpleNamespace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ed_scaling import BINARY, run_once  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--n", type=int, default=900)
    p.add_argument("--vfs", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    p.add_argument("--dt-factor", type=float, default=0.01)
    p.add_argument("--model", default="rigid")
    p.add_argument("--params", action="append", default=[])
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    print(f"command: bench/ts_daha_sweep.py {' '.join(sys.argv[1:])}".rstrip())
    print(f"2D, N = {args.n}, walls, lattice, speed 1, dt_factor {args.dt_factor}, model {args.model}, seed 1\n")
    print("| parameters | Vf | DAHA iterations | minimisations | placed at contact | max residual overlap | wall time (s) |")
    print("|---|---|---|---|---|---|---|")
    for params in [""] + args.params:
        extra = [f"ts.dt_factor={args.dt_factor}", f"ts.model={args.model}"] + [f"ts.{kv}" for kv in params.split()]
        for vf in args.vfs:
            s = run_once(2, args.n, 1, SimpleNamespace(vf=vf, boundary="walls", engine="ts", set=extra))
            print(f"| {params or 'defaults'} | {vf} | {s['daha_iterations']} | {s['minimisations']} | "
                  f"{s['placed_at_contact']} | {s['max_residual_overlap']:.2g} | {s['wall_seconds']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
