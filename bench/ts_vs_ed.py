#!/usr/bin/python3
"""Time-stepping (ts) and event-driven (ed) engines side by side, to a single cluster.

For each volume fraction and N, runs both engines (several seeds, paper's set-up: 2D,
lattice start, speed 1, walls) and prints a Markdown table with the median wall times,
the TS work counters and the fitted growth exponents of both engines.

Usage: bench/ts_vs_ed.py [--vfs 0.1 0.2 0.3] [--sizes 10000 100000] [--seeds 3]
                         [--repeats K] [--repeat-max-n N] [--show-runs] [--dt-factor 0.005]
                         [--fixed-step N_REF] [--ts-only] [--model rigid] [--set KEY=VALUE ...]
                         [--engines ed-naive ed ts] [--naive-max-n N]

--engines ed-naive ed ts is the paper's comparison (Figs 6-7): TS against the O(N^2)
event-driven method of its Appendix A (ed-naive) and against our ed. It prints a table
of the median wall times of the engines named, the ratios of ts to each, and each
engine's cost exponent p of t ~ N^p with its standard error: a least-squares line
through log t against log N over every seed's run (the median of its repeats), so that
the scatter between seeds enters the error. --naive-max-n leaves ed-naive out above N
(it costs about N^3.5: 26 s at N = 1600).

--repeats K runs every seed of N <= --repeat-max-n (default 10^5) K times and keeps its
median wall time (a run of 10^4 takes 0.2 s, and on a shared VM single samples of it move
the exponent by +-0.03; larger N run once per seed). The work counters are the same in
every repeat. The repeats are made in rounds, every size and seed once a round, so that
the VM's drift during a reading (its speed changes by 20-50 % over minutes) reaches every
size alike. With --repeat-max-n 1000000 a reading of 10^4 ... 10^6, 5 repeats and 3 seeds,
takes about 10 minutes (progress goes to stderr). --show-runs prints every run's wall time
after the table, so that a reading can be checked run by run.

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


REPEAT_MAX_N = 100000  # --repeats applies up to this N unless --repeat-max-n says otherwise
ENGINES = ["ed-naive", "ed", "ts"]  # the order of the columns of the --engines table


def collect_runs(args, engines, ts_extra):
    """Every run, keyed (engine, vf, n, seed). The repeats are made in rounds, each round
    running every size and seed once, so that a VM that slows down or speeds up during a
    reading (it does, by 20-50 % over minutes) moves every size alike instead of one."""
    runs = {}
    rounds = max(args.repeats, 1)
    naive_max_n = getattr(args, "naive_max_n", None)
    for r in range(rounds):
        for vf in args.vfs:
            for n in args.sizes:
                if r > 0 and n > args.repeat_max_n:
                    continue
                for engine in engines:
                    if engine == "ed-naive" and naive_max_n is not None and n > naive_max_n:
                        continue
                    ns = SimpleNamespace(vf=vf, boundary="walls", engine=engine,
                                         set=ts_extra(n) if engine == "ts" else args.set)
                    for seed in range(1, args.seeds + 1):
                        runs.setdefault((engine, vf, n, seed), []).append(run_once(2, n, seed, ns))
                    print(f"round {r + 1} of {rounds}: {engine} Vf {vf} N {n} done", file=sys.stderr, flush=True)
    return runs


def median_run(runs, engine, vf, n, seeds, log):
    """The median over seeds of each seed's median run (by wall time)."""
    def seed_run(seed):
        kept = sorted(runs[(engine, vf, n, seed)], key=lambda s: s["wall_seconds"])
        log.append(f"{engine} Vf {vf} N {n} seed {seed}: " + " ".join(f"{k['wall_seconds']:.3f}" for k in kept))
        return kept[len(kept) // 2]

    per_seed = sorted((seed_run(seed) for seed in range(1, seeds + 1)), key=lambda s: s["wall_seconds"])
    return per_seed[len(per_seed) // 2]


def fit_exponent_with_error(ns, times):
    """The slope p of the least-squares line log t = p log N + c through the points (ns[k],
    times[k]) and its standard error, sqrt(residual variance / sum (log N - mean)^2);
    None for the error with fewer than three points or a single N."""
    xs = [math.log(n) for n in ns]
    ys = [math.log(t) for t in times]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    if len(xs) < 3:
        return slope, None
    residual = sum((y - my - slope * (x - mx)) ** 2 for x, y in zip(xs, ys)) / (len(xs) - 2)
    return slope, math.sqrt(residual / sxx)


def seed_times(runs, engine, vf, n, seeds):
    """Each seed's wall time at (engine, vf, n): the median of its repeats."""
    times = []
    for seed in range(1, seeds + 1):
        kept = sorted(run["wall_seconds"] for run in runs[(engine, vf, n, seed)])
        times.append(kept[len(kept) // 2])
    return times


def timing_table(args, runs, engines):
    """The --engines table: median wall times, ts's ratios to the others, exponents."""
    naive_max_n = getattr(args, "naive_max_n", None)
    ratios = [e for e in engines if e != "ts"] if "ts" in engines else []
    lines = ["| Vf | N | " + " | ".join(f"{e} (s)" for e in engines) + "".join(f" | ts / {e}" for e in ratios) + " |",
             "|---|---|" + "---|" * (len(engines) + len(ratios))]
    for vf in args.vfs:
        points = {e: ([], []) for e in engines}
        for n in args.sizes:
            median = {}
            for e in engines:
                if (e, vf, n, 1) not in runs:
                    continue
                times = seed_times(runs, e, vf, n, args.seeds)
                median[e] = sorted(times)[len(times) // 2]
                points[e][0].extend([n] * len(times))
                points[e][1].extend(times)
            cells = [f"{median[e]:.4g}" if e in median else "-" for e in engines]
            cells += [f"{median['ts'] / median[e]:.3g}" if e in median else "-" for e in ratios]
            lines.append(f"| {vf} | {n} | " + " | ".join(cells) + " |")
        exponents = []
        for e in engines:
            ns, times = points[e]
            if len(set(ns)) < 2:
                exponents.append("-")
                continue
            p, error = fit_exponent_with_error(ns, times)
            exponents.append(f"{p:.2f}" + (f" ± {error:.2f}" if error is not None else ""))
        lines.append(f"| {vf} | exponent | " + " | ".join(exponents) + " |" + " |" * len(ratios))
    if naive_max_n is not None and "ed-naive" in engines:
        lines.append(f"\ned-naive run up to N = {naive_max_n} only")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--vfs", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    p.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--repeats", type=int, default=1,
                   help="runs per seed for N <= --repeat-max-n (the median is kept)")
    p.add_argument("--repeat-max-n", type=int, default=REPEAT_MAX_N, metavar="N",
                   help=f"the largest N that --repeats applies to (default {REPEAT_MAX_N})")
    p.add_argument("--show-runs", action="store_true", help="print every run's wall time after the table")
    p.add_argument("--dt-factor", type=float, default=0.005)
    p.add_argument("--fixed-step", type=int, metavar="N_REF",
                   help="scale dt_factor by sqrt(N_REF / N): the same step in physical time at every N")
    p.add_argument("--ts-only", action="store_true", help="skip the ed runs")
    p.add_argument("--model", default="rigid")
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--engines", nargs="+", choices=ENGINES,
                   help="the timing table of these engines (the paper's Figs 6-7: ed-naive ed ts)")
    p.add_argument("--naive-max-n", type=int, metavar="N", help="with --engines: run ed-naive up to N only")
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    def ts_extra(n):
        dt_factor = args.dt_factor * (math.sqrt(args.fixed_step / n) if args.fixed_step else 1.0)
        return [f"ts.dt_factor={dt_factor:.9g}", f"ts.model={args.model}"] + args.set
    print(f"command: bench/ts_vs_ed.py {' '.join(sys.argv[1:])}".rstrip())
    repeats = f" (each of {args.repeats} runs up to N = {args.repeat_max_n})" if args.repeats > 1 else ""
    print(f"2D, walls, lattice start, speed 1, median of {args.seeds} seeds{repeats}; ts model {args.model}, "
          f"dt_factor {args.dt_factor}" + (f" at N = {args.fixed_step}, scaled by sqrt({args.fixed_step} / N)"
                                           if args.fixed_step else "") + "\n")
    if args.engines:
        engines = [e for e in ENGINES if e in args.engines]
        runs = collect_runs(args, engines, ts_extra)
        print(timing_table(args, runs, engines), flush=True)
        return
    print("| Vf | N | ed (s) | ts (s) | ts / ed | ts steps | minimisations | DAHA iterations | placed at contact |"
          " ts max residual overlap |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    runs = collect_runs(args, ["ts"] if args.ts_only else ["ed", "ts"], ts_extra)
    log = []  # every run's wall time, sorted per seed (--show-runs)
    for vf in args.vfs:
        ed_times, ts_times = [], []
        for n in args.sizes:
            ed = None if args.ts_only else median_run(runs, "ed", vf, n, args.seeds, log)
            ts = median_run(runs, "ts", vf, n, args.seeds, log)
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
    if args.show_runs:
        print("\nwall times (s), sorted, per seed:\n" + "\n".join(log))


if __name__ == "__main__":
    main()
