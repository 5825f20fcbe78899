#!/usr/bin/python3
"""Time-stepping (ts) and event-driven (ed) engines side by side, to a single cluster.

For each volume fraction and N, runs both engines (several seeds, paper's set-up: 2D,
lattice start, speed 1, walls) and prints a Markdown table with the median wall times,
the TS work counters and the fitted growth exponents of both engines.

Usage: bench/ts_vs_ed.py [--vfs 0.1 0.2 0.3] [--sizes 10000 100000] [--seeds 3]
                         [--repeats K] [--dt-factor 0.005] [--fixed-step N_REF] [--ts-only]
                         [--model rigid] [--set KEY=VALUE ...]

--repeats K runs every seed of N <= 10^5 K times and keeps its median wall time (a run of
10^4 takes 0.2 s, and on a shared VM single samples of it move the exponent by +-0.03;
larger N run once per seed). The work counters are the same in every repeat.

--fixed-step N_REF keeps the step the same in physical time at every N: dt_factor is
scaled by sqrt(N_REF / N) (L grows as sqrt(N) in 2D), so every N gets the step that
--dt-factor gives at N_REF (docs/performance.md, "Why the exponent is missed").
Only the Python standard library is used.
"""
import argparse
import math
import os
import sys
from types import SimpleNamespace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ed_scaling import BINARY, fit_exponent, run_once  # noqa: E402


REPEAT_MAX_N = 100000  # --repeats applies up to this N


def median_run(engine, vf, n, args, extra):
    ns = SimpleNamespace(vf=vf, boundary="walls", engine=engine, set=extra)
    repeats = args.repeats if n <= REPEAT_MAX_N else 1

    def seed_run(seed):  # the run of median wall time among the repeats of one seed
        runs = sorted((run_once(2, n, seed, ns) for _ in range(repeats)), key=lambda s: s["wall_seconds"])
        return runs[len(runs) // 2]

    runs = sorted((seed_run(seed) for seed in range(1, args.seeds + 1)), key=lambda s: s["wall_seconds"])
    return runs[len(runs) // 2]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--vfs", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    p.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--repeats", type=int, default=1,
                   help=f"runs per seed for N <= {REPEAT_MAX_N} (the median is kept)")
    p.add_argument("--dt-factor", type=float, default=0.005)
    p.add_argument("--fixed-step", type=int, metavar="N_REF",
                   help="scale dt_factor by sqrt(N_REF / N): the same step in physical time at every N")
    p.add_argument("--ts-only", action="store_true", help="skip the ed runs")
    p.add_argument("--model", default="rigid")
    p.add_argument("--set", action="append", default=[])
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    def ts_extra(n):
        dt_factor = args.dt_factor * (math.sqrt(args.fixed_step / n) if args.fixed_step else 1.0)
        return [f"ts.dt_factor={dt_factor:.9g}", f"ts.model={args.model}"] + args.set
    print(f"command: bench/ts_vs_ed.py {' '.join(sys.argv[1:])}".rstrip())
    repeats = f" (each of {args.repeats} runs up to N = {REPEAT_MAX_N})" if args.repeats > 1 else ""
    print(f"2D, walls, lattice start, speed 1, median of {args.seeds} seeds{repeats}; ts model {args.model}, "
          f"dt_factor {args.dt_factor}" + (f" at N = {args.fixed_step}, scaled by sqrt({args.fixed_step} / N)"
                                           if args.fixed_step else "") + "\n")
    print("| Vf | N | ed (s) | ts (s) | ts / ed | ts steps | minimisations | DAHA iterations | placed at contact |"
          " ts max residual overlap |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for vf in args.vfs:
        ed_times, ts_times = [], []
        for n in args.sizes:
            ed = None if args.ts_only else median_run("ed", vf, n, args, args.set)
            ts = median_run("ts", vf, n, args, ts_extra(n))
            ts_times.append(ts["wall_seconds"])
            ed_cell, ratio = "-", "-"
            if ed:
                ed_times.append(ed["wall_seconds"])
                ed_cell, ratio = f"{ed['wall_seconds']:.3f}", f"{ts['wall_seconds'] / ed['wall_seconds']:.2f}"
            print(f"| {vf} | {n} | {ed_cell} | {ts['wall_seconds']:.3f} | "
                  f"{ratio} | {ts['steps']} | {ts['minimisations']} | "
                  f"{ts['daha_iterations']} | {ts['placed_at_contact']} | {ts['max_residual_overlap']:.2g} |", flush=True)
        if len(args.sizes) > 1:
            ed_exponent = f"{fit_exponent(args.sizes, ed_times):.3f}" if ed_times else "-"
            print(f"| {vf} | exponent | {ed_exponent} | {fit_exponent(args.sizes, ts_times):.3f}"
                  " | | | | | | |", flush=True)


if __name__ == "__main__":
    main()
