#!/usr/bin/python3
"""Wall time of the event-driven engine against N, to a single cluster.

Runs build/bin/ballagg for each dimension and N (several seeds), reads summary.json,
and prints a Markdown table with the median wall time, events, events per second,
and the growth exponent fitted on log(wall time) vs log(N).

Usage: bench/ed_scaling.py [--dims 2 3] [--sizes 1000 3000 ...] [--seeds 3]
                           [--vf 0.2] [--boundary walls] [--engine ed] [--set KEY=VALUE ...]
Only the Python standard library is used.
"""
import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")


def machine():
    """CPU model, cores and kernel, for the tables of docs/performance.md."""
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def run_once(dim, n, seed, args):
    with tempfile.TemporaryDirectory() as out:
        cmd = [BINARY, "run", "-q", "--out", out, "--seed", str(seed),
               "--set", f"system.dimension={dim}", "--set", f"system.n={n}",
               "--set", f"system.volume_fraction={args.vf}", "--set", f"system.boundary={args.boundary}",
               "--set", f"engine.kind={args.engine}", "--set", "output.xyz=false"]
        for extra in args.set:
            cmd += ["--set", extra]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)


def fit_exponent(ns, times):
    xs = [math.log(n) for n in ns]
    ys = [math.log(t) for t in times]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dims", type=int, nargs="+", default=[2, 3])
    p.add_argument("--sizes", type=int, nargs="+", default=[1000, 3000, 10000, 30000, 100000])
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--vf", type=float, default=0.2)
    p.add_argument("--boundary", default="walls")
    p.add_argument("--engine", default="ed")
    p.add_argument("--set", action="append", default=[])
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")

    print(f"machine: {machine()}")
    print(f"command: bench/ed_scaling.py {' '.join(sys.argv[1:])}".rstrip())
    print(f"engine {args.engine}, volume fraction {args.vf}, {args.boundary}, fixed-speed 1, lattice start, "
          f"median of {args.seeds} seeds, run to a single cluster\n")
    print("| D | N | wall time (s) | events | collisions | wall bounces | list rebuilds | events/s | simulated time |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dim in args.dims:
        medians = []
        for n in args.sizes:
            runs = [run_once(dim, n, seed, args) for seed in range(1, args.seeds + 1)]
            runs.sort(key=lambda s: s["wall_seconds"])
            m = runs[len(runs) // 2]
            medians.append(m["wall_seconds"])
            print(f"| {dim} | {n} | {m['wall_seconds']:.3f} | {m['events']} | {m['collisions']} | "
                  f"{m['wall_bounces']} | {m['list_rebuilds']} | {m['events_per_second']:.3g} | {m['time']:.4g} |",
                  flush=True)
        if len(args.sizes) > 1:
            print(f"| {dim} | exponent | {fit_exponent(args.sizes, medians):.3f} | | | | | | |", flush=True)


if __name__ == "__main__":
    main()
