#!/usr/bin/python3
"""Cost of snapshots and pictures at N = 10^6 (docs/pictures.md, "Costs").

1. A 2D run (N = 10^6, Vf = 0.3, walls, event-driven, to one cluster) without and with
   snapshots every 1/100 of its simulated duration (H5MD only), alternating, REPEATS
   times: the minimum engine time (summary.json wall_seconds: what the run itself took,
   captures included) and the minimum whole-process time (with the wait for the writer
   thread at the end and the final files).
2. `ballagg render` of 10^6 discs to PNG: the final state (final.csv), and a trajectory
   frame with many clusters (H5MD).

Usage: bench/pictures_bench.py [--repeats 3] [--n 1000000] [--dir /tmp/ballagg-pictures-bench]
The trajectory takes ~3.5 GB on disk while it exists. Only the standard library is used.
"""
import argparse
import json
import os
import shutil
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")


def run(out, n, extra):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [BINARY, "run", "-q", "--out", out, "--set", f"system.n={n}", "--set", "system.volume_fraction=0.3",
           "--set", "output.xyz=false"] + extra
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    total = time.monotonic() - t0
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return s, total, " ".join(cmd)


def timed(cmd):
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.monotonic() - t0


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--dir", default="/tmp/ballagg-pictures-bench")
    a = p.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    base_dir, snap_dir = os.path.join(a.dir, "base"), os.path.join(a.dir, "snap")
    summary, _, _ = run(base_dir, a.n, [])
    every = summary["time"] / 100
    engine = {"without": [], "with": []}
    process = {"without": [], "with": []}
    commands = {}
    for _ in range(a.repeats):
        for kind, out, extra in (("without", base_dir, []), ("with", snap_dir, ["--set", f"output.snapshot_every={every}"])):
            s, total, cmd = run(out, a.n, extra)
            engine[kind].append(s["wall_seconds"])
            process[kind].append(total)
            commands[kind] = cmd
    size = os.path.getsize(os.path.join(snap_dir, "trajectory.h5md"))
    print(f"N = {a.n}, simulated time {summary['time']:.6g}, snapshot_every = {every:.6g}")
    for kind in ("without", "with"):
        print(f"  {kind:7s} snapshots: engine min {min(engine[kind]):.2f} s (all {', '.join(f'{x:.2f}' for x in engine[kind])}), "
              f"process min {min(process[kind]):.2f} s (all {', '.join(f'{x:.2f}' for x in process[kind])})")
        print(f"    command: {commands[kind]}")
    print(f"  engine overhead (min/min): {100 * (min(engine['with']) / min(engine['without']) - 1):+.1f} %, "
          f"process overhead: {100 * (min(process['with']) / min(process['without']) - 1):+.1f} %; "
          f"trajectory.h5md {size / 1e9:.2f} GB")

    for label, extra in (("final state (final.csv)", []), ("frame 1 (H5MD)", ["--frame", "1"])):
        png = os.path.join(a.dir, "render.png")
        cmd = [BINARY, "render", snap_dir, "--png", png] + extra
        times = [timed(cmd) for _ in range(a.repeats)]
        print(f"render {label}: min {min(times):.2f} s (all {', '.join(f'{x:.2f}' for x in times)}), "
              f"PNG {os.path.getsize(png) / 1e6:.2f} MB\n    command: {' '.join(cmd)}")
    shutil.rmtree(a.dir, ignore_errors=True)


if __name__ == "__main__":
    main()
