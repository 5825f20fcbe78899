#!/usr/bin/python3
"""Long runs of issue #8: each engine at scale, to one cluster (or 99% of the mass), with
`ballagg verify` at the end and the memory sampled over the run (docs/performance.md,
"Long runs").

For each case: wall time, CPU time, peak resident set, the resident set at a quarter,
half, three quarters and the end of the run (flat memory: no growth beyond the state),
the summary's stop reason and clusters, and the verdict of `ballagg verify`.

Usage: bench/long_runs.py [--cases ed-2d-1e6 ts-2d-1e6 ed-3d-1e5 ts-3d-1e5 rigid-body-3d-1e5]
                          [--dir /tmp/ballagg-long-runs] [--threads 2]
Only the Python standard library is used (memory from /proc/PID/status).
"""
import argparse
import json
import os
import shutil
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")

# 2D: the paper's set-up (walls, Vf 0.3). 3D: a periodic box at Vf 0.2.
THREE_D = ["system.dimension=3", "system.boundary=periodic", "system.volume_fraction=0.2"]
CASES = {
    "ed-2d-1e6": ["engine.kind=ed", "system.n=1000000", "system.volume_fraction=0.3"],
    "ts-2d-1e6": ["engine.kind=ts", "system.n=1000000", "system.volume_fraction=0.3", "ts.dt_factor=0.005"],
    "ed-3d-1e5": ["engine.kind=ed", "system.n=100000"] + THREE_D,
    "ts-3d-1e5": ["engine.kind=ts", "system.n=100000", "ts.dt_factor=0.005"] + THREE_D,
    "rigid-body-3d-1e5": ["engine.kind=rigid-body", "system.n=100000", "stop.aggregated_fraction=0.99"] + THREE_D,
}


def rss_kb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except FileNotFoundError:
        return None
    return None


def run_case(name, out, threads):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [BINARY, "run", "-q", "--out", out, "--set", "output.xyz=false"]
    for s in CASES[name]:
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    start = time.monotonic()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL)
    samples = []  # (seconds, kB)
    while proc.poll() is None:
        kb = rss_kb(proc.pid)
        if kb is not None:
            samples.append((time.monotonic() - start, kb))
        time.sleep(0.5)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        raise SystemExit(f"{name}: ballagg run exited with {proc.returncode}: {' '.join(cmd)}")
    verify = subprocess.run([BINARY, "verify", out], capture_output=True, text=True)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return cmd, wall, samples, verify, summary


def at_fraction(samples, q):
    if not samples:
        return 0
    t_end = samples[-1][0]
    return min(samples, key=lambda s: abs(s[0] - q * t_end))[1]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    p.add_argument("--dir", default="/tmp/ballagg-long-runs")
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args()
    print(f"threads {a.threads}; load average at the start {os.getloadavg()[0]:.1f}")
    print("| case | wall (s) | engine (s) | stop | clusters | peak RSS (MB) | RSS at 25/50/75/100 % (MB) | verify |")
    print("|---|---|---|---|---|---|---|---|")
    for name in a.cases:
        out = os.path.join(a.dir, name)
        cmd, wall, samples, verify, s = run_case(name, out, a.threads)
        peak = max((kb for _, kb in samples), default=0) / 1024
        marks = " / ".join(f"{at_fraction(samples, q) / 1024:.0f}" for q in (0.25, 0.5, 0.75, 1.0))
        verdict = "pass" if verify.returncode == 0 else f"FAIL ({verify.returncode}): {verify.stdout.strip()} {verify.stderr.strip()}"
        print(f"| {name} | {wall:.1f} | {s['wall_seconds']:.1f} | {s['stop_reason']} | {s['n_clusters']} | {peak:.0f} | {marks} | {verdict} |",
              flush=True)
        print(f"    command: {' '.join(cmd)}", flush=True)
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
