#!/usr/bin/python3
"""Cost per event of sphere coalescence (collision.coagulation = "sphere", Richardson's test
models i-ii) beside fractal rigid clusters on the same gas.

Cases (periodic, random start, Gaussian velocities, zero total momentum, to 100 clusters):

  * 3D, N = 2 x 10^4, Vf 0.005: coalescing spheres of constant density (model ii's rule),
    fractal rigid clusters (rigid-body engine), and the same with `ed`;
  * 2D, N = 5000, Vf 0.02: coalescing spheres and fractal rigid clusters.

Runs build/bin/ballagg --repeat times per case (one thread) and prints a Markdown table with
the fastest engine time, events, microseconds per event, list rebuilds and pair predictions
per merge. The runs are deterministic: every repetition handles the same events; the
machine may be shared, so take the minimum.

Usage: bench/coalescence_speed.py [--repeat 3] [--cases 3d-spheres 3d-fractal ...]
Only the Python standard library is used.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ed_scaling import BINARY, machine  # noqa: E402

GAS = ["system.boundary=periodic", "initial.positions=random", "initial.velocities=gaussian",
       "initial.zero_momentum=true", "stop.clusters=100", "output.xyz=false"]
GAS_3D = GAS + ["system.dimension=3", "system.n=20000", "system.volume_fraction=0.005"]
GAS_2D = GAS + ["system.dimension=2", "system.n=5000", "system.volume_fraction=0.02"]
SPHERES = ["engine.kind=rigid-body", "collision.coagulation=sphere", "collision.merged_radius=constant-density"]
FRACTAL = ["engine.kind=rigid-body"]

CASES = {
    "3d-spheres": ("3D, 2 x 10^4, coalescing spheres (rigid-body)", GAS_3D + SPHERES),
    "3d-fractal": ("3D, 2 x 10^4, fractal rigid clusters (rigid-body)", GAS_3D + FRACTAL),
    "3d-ed": ("3D, 2 x 10^4, fractal rigid clusters (ed)", GAS_3D + ["engine.kind=ed"]),
    "2d-spheres": ("2D, 5000, coalescing spheres (rigid-body)", GAS_2D + SPHERES),
    "2d-fractal": ("2D, 5000, fractal rigid clusters (rigid-body)", GAS_2D + FRACTAL),
}


def run_once(sets):
    with tempfile.TemporaryDirectory() as out:
        cmd = [BINARY, "run", "-q", "--out", out]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env={**os.environ, "OMP_NUM_THREADS": "1"})
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    print(f"machine: {machine()}, load average {os.getloadavg()[0]:.1f} at the start")
    print(f"command: bench/coalescence_speed.py {' '.join(sys.argv[1:])}".rstrip())
    print()
    print("| case | engine time (s), min of runs | events | µs per event | list rebuilds | merges | "
          "pair predictions per merge |")
    print("|---|---|---|---|---|---|---|")
    for case in args.cases:
        label, sets = CASES[case]
        runs = [run_once(sets) for _ in range(args.repeat)]
        best = min(runs, key=lambda s: s["wall_seconds"])
        merges = max(best["merges"], 1)
        print(f"| {label} | {best['wall_seconds']:.2f} ({len(runs)}) | {best['events']} | "
              f"{1e6 * best['wall_seconds'] / best['events']:.2f} | {best['list_rebuilds']} | {best['merges']} | "
              f"{best['pair_predictions'] / merges:.1f} |", flush=True)


if __name__ == "__main__":
    main()
