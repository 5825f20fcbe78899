#!/usr/bin/python3
"""Searches DAHA parameters of the time-stepping engine on recorded minimisation problems.

Record problems from runs first (bench/daha_tune.cpp):
  build/bin/ballagg_daha_tune record problems.txt --set engine.kind=ts --set system.n=900 ...
then search:
  bench/daha_tune.py problems-*.txt [--trials 300] [--seed 1] [--start "alpha=0.03 ..."]

The cost of a parameter set is the work of replaying every problem (iterations times
problem size, summed) plus `--failure-weight` times the work of the problems left
unconverged and `--failure-cost` per such problem (each of those ends in a retreat, the
fall-back, instead of a minimisation, and may add rounds); with `--max-failed`, sets that
leave more problems unconverged are rejected outright.
The search perturbs every parameter of the best set so far with log-normal steps, wide at
first and narrower later (a random then local search), and prints each improvement and,
at the end, the best set as [ts] keys. Only the standard library is used.
"""
import argparse
import math
import os
import random
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.environ.get("BALLAGG_DAHA_TUNE", os.path.join(HERE, "..", "build", "bin", "ballagg_daha_tune"))
KEYS = ["alpha", "gamma", "delta", "c_bar", "c_min", "c_max", "beta_bar", "beta_max", "lambda0", "stall_iterations"]
INTEGER_KEYS = {"stall_iterations"}


def cost(params, files, failure_weight, failure_cost, max_failed=None):
    sets = [a for k, v in params.items()
            for a in ("--set", f"ts.{k}={round(v)}" if k in INTEGER_KEYS else f"ts.{k}={v:.6g}")]
    out = subprocess.run([TOOL, "replay", *files, *sets], capture_output=True, text=True)
    if out.returncode != 0:
        return math.inf, out.stderr.strip()
    f = dict(zip(out.stdout.split()[0::2], out.stdout.split()[1::2]))
    if max_failed is not None and int(f["failed"]) > max_failed:
        return math.inf, out.stdout.strip()
    return (float(f["work"]) + failure_weight * float(f["failed_work"]) + failure_cost * float(f["failed"]),
            out.stdout.strip())


def defaults():
    out = subprocess.run([os.path.join(HERE, "..", "build", "bin", "ballagg"), "config", "--set", "engine.kind=ts"],
                         capture_output=True, text=True)
    values = {}
    section = None
    for line in out.stdout.splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
        elif section == "ts" and "=" in line:
            k, v = (x.strip() for x in line.split("=", 1))
            if k in KEYS:
                values[k] = float(v)
    return values


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("files", nargs="+")
    p.add_argument("--trials", type=int, default=300)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--failure-weight", type=float, default=1.0)
    p.add_argument("--failure-cost", type=float, default=20000.0,
                   help="work charged per unconverged problem on top (its retreat, the rounds it may add)")
    p.add_argument("--start", default="", help="KEY=VALUE ... to start from instead of the defaults")
    p.add_argument("--max-failed", type=int, default=None,
                   help="reject parameter sets that leave more problems unconverged than this")
    p.add_argument("--constant-damping", action="store_true",
                   help="search with c_min = c_max: a damping the same for every variable, which keeps the "
                        "minimisation from moving a group's centre of mass (the dynamical c_i of (3.29) do not)")
    args = p.parse_args()
    if not os.path.exists(TOOL):
        sys.exit(f"{TOOL} not found: run `make build` first")
    best = defaults()
    for kv in args.start.split():
        k, v = kv.split("=")
        best[k] = float(v)
    if args.constant_damping:
        best["c_min"] = best["c_max"]
    if best.get("stall_iterations", 0) == 0:
        best["stall_iterations"] = 1000.0  # the search starts with stall detection on
    best_cost, line = cost(best, args.files, args.failure_weight, args.failure_cost)
    print(f"start: {line}", flush=True)
    rng = random.Random(args.seed)
    for trial in range(args.trials):
        width = 0.6 if trial < args.trials // 3 else 0.25
        trial_params = {k: v * math.exp(rng.gauss(0.0, width)) if rng.random() < 0.5 else v for k, v in best.items()}
        trial_params["c_max"] = min(trial_params["c_max"], 0.95)
        trial_params["c_min"] = trial_params["c_max"] if args.constant_damping else min(trial_params["c_min"],
                                                                                         trial_params["c_max"])
        trial_params["stall_iterations"] = max(20.0, trial_params["stall_iterations"])
        c, line = cost(trial_params, args.files, args.failure_weight, args.failure_cost, args.max_failed)
        if c < best_cost:
            best, best_cost = trial_params, c
            print(f"trial {trial}: {line}", flush=True)
    print("best: " + " ".join(f"{k}={round(best[k])}" if k in INTEGER_KEYS else f"{k}={best[k]:.4g}" for k in KEYS))


if __name__ == "__main__":
    main()
