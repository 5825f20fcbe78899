#!/usr/bin/python3
"""Speed of the rigid-body engine on its speed targets:

  * Richardson's model (v) (examples/richardson1995/model-v.toml: 9000 spheres, to
    T = 40.8): target under 10 s;
  * the same gas (density, radius, velocities, outcome rules) with 10^5 spheres in a
    periodic cube, until 99% of the mass is aggregated: target under 10 minutes.

Runs build/bin/ballagg --repeat times per case and prints a Markdown table with the
fastest and the median run (wall time of the whole process and of the engine alone),
events, collisions and events per second. The machine may be shared: take the minimum.

Usage: bench/rigid_body_speed.py [--repeat 3] [--cases model-v 1e5] [--seed 1]
Only the Python standard library is used.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ed_scaling import BINARY, ROOT, machine  # noqa: E402

MODEL_V = os.path.join(ROOT, "examples", "richardson1995", "model-v.toml")

# Model (v) has 9000 spheres in a cube of side 10; 10^5 at the same density need a side
# of 10 (10^5 / 9000)^(1/3).
CASES = {
    "model-v": ("model (v), 9000 spheres, T = 40.8", []),
    "1e5": ("model (v) gas, 10^5 spheres, until 99% of the mass is aggregated",
            ["system.n=100000", f"system.box_length={10 * (1e5 / 9000) ** (1 / 3):.9f}",
             "stop.time=inf", "stop.aggregated_fraction=0.99"]),
}


def slope(fit):
    return f"{fit['slope']:.3f} ± {fit['slope_error']:.3f}" if fit else "-"


def mean(m):
    """A weighted mean of analysis.json: mean ± spread (clusters)."""
    return f"{m['mean']:.2f} ± {m['spread']:.2f} ({m['clusters']})" if m["clusters"] else "-"


def run_once(case, seed):
    sets = CASES[case][1]
    with tempfile.TemporaryDirectory() as out:
        cmd = [BINARY, "run", MODEL_V, "-q", "--out", out, "--seed", str(seed), "--set", "output.xyz=false"]
        for s in sets:
            cmd += ["--set", s]
        start = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        wall = time.perf_counter() - start
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        with open(os.path.join(out, "analysis.json")) as f:
            summary["analysis"] = json.load(f)
    summary["process_seconds"] = wall
    return summary


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--cases", nargs="+", default=list(CASES))
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    print(f"machine: {machine()}, load average {os.getloadavg()[0]:.1f} at the start")
    print(f"command: bench/rigid_body_speed.py {' '.join(sys.argv[1:])}".rstrip())
    print()
    print("| case | runs | process wall (s): min / median | engine (s): min | events | collisions | "
          "events/s | simulated time | stop |")
    print("|---|---|---|---|---|---|---|---|---|")
    ends = []
    for case in args.cases:
        runs = [run_once(case, args.seed) for _ in range(args.repeat)]
        best = min(runs, key=lambda s: s["process_seconds"])
        process = [s["process_seconds"] for s in runs]
        print(f"| {CASES[case][0]} | {len(runs)} | {min(process):.2f} / {statistics.median(process):.2f} | "
              f"{min(s['wall_seconds'] for s in runs):.2f} | {best['events']} | {best['collisions']} | "
              f"{best['events_per_second']:.3g} | {best['time']:.4g} | {best['stop_reason']} |", flush=True)
        ends.append((case, best["analysis"]))
    # The end statistics of the runs (the same in every repetition: the run is deterministic).
    print()
    print("| case | bodies | aggregated mass | heaviest body | R_max exponent | gamma | 3 / (1 - gamma) | "
          "mean f_D, every centre (aggregates) | mean f_D, 4R..R_g (aggregates) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for case, a in ends:
        p = a["population"]
        print(f"| {CASES[case][0]} | {a['n_clusters']} | {100 * a['aggregated_mass_fraction']:.2f}% | "
              f"{100 * a['heaviest_mass_fraction']:.1f}% | {slope(p['r_max_vs_size'])} | {slope(p['density_vs_size'])} | "
              f"{p['dimension_from_density']:.2f} | {mean(p['mean_richardson_dimension'])} | "
              f"{mean(p['mean_mass_radius_dimension'])} |")


if __name__ == "__main__":
    main()
