#!/usr/bin/python3
"""Two builds of ballagg side by side: the engine's wall time of the same runs, alternated.

On a shared machine the wall time of one run drifts with the load by more than the
difference between two builds; alternating A, B, A, B, ... exposes both builds to the same
drift, and the minimum over the repeats is the figure least touched by it. Each run also
checks that both builds give the same events (the count in summary.json), so that a
difference in time is not a difference in work.

Cases (docs/performance.md, "How fast"):
  ed-2d-1e6   ed, 2D, N = 10^6, Vf 0.3, walls, to one cluster, one thread
  ts-2d-1e6   ts (rigid), 2D, N = 10^6, Vf 0.3, walls, dt_factor 0.005, to one cluster, two threads
  model-v     rigid-body, Richardson's model (v) (examples/richardson1995/model-v.toml), one thread

Usage: bench/compare_binaries.py OLD NEW [--cases ed-2d-1e6 ts-2d-1e6 model-v] [--repeats 3]
OLD and NEW are paths to ballagg binaries. Prints one Markdown row per case: the minimum
and median engine wall time of each build and NEW / OLD of the minima.
Only the Python standard library is used.
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL_V = os.path.join(ROOT, "examples", "richardson1995", "model-v.toml")

CASES = {
    "ed-2d-1e6": ([], ["engine.kind=ed", "system.n=1000000", "system.volume_fraction=0.3"], 1),
    "ts-2d-1e6": ([], ["engine.kind=ts", "system.n=1000000", "system.volume_fraction=0.3", "ts.dt_factor=0.005"], 2),
    "model-v": ([MODEL_V], [], 1),
}


def run_once(binary, case, seed):
    """(engine wall seconds, the run's count of events or steps) of one run."""
    config, sets, threads = CASES[case]
    with tempfile.TemporaryDirectory() as out:
        cmd = [binary, "run", *config, "-q", "--out", out, "--seed", str(seed), "--set", "output.xyz=false"]
        for s in sets:
            cmd += ["--set", s]
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
    work = summary.get("events", summary.get("steps"))
    return summary["wall_seconds"], work


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    print("| case | old: min (median) s | new: min (median) s | new / old | events or steps |")
    print("|---|---|---|---|---|")
    for case in args.cases:
        times = {"old": [], "new": []}
        work = set()
        for _ in range(args.repeats):
            for name in ("old", "new"):
                wall, done = run_once(getattr(args, name), case, args.seed)
                times[name].append(wall)
                work.add(done)
        if len(work) != 1:
            raise SystemExit(f"{case}: the two builds did different work: {sorted(work)}")
        old, new = times["old"], times["new"]
        print(f"| {case} | {min(old):.2f} ({statistics.median(old):.2f}) | {min(new):.2f} ({statistics.median(new):.2f}) "
              f"| {min(new) / min(old):.3f} | {work.pop()} |", flush=True)


if __name__ == "__main__":
    main()
