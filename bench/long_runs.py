#!/usr/bin/python3
"""Long runs: each engine at scale, to one cluster (or 99% of the mass), with
`ballagg verify` at the end and the memory sampled over the run (docs/profiles.md,
"Long runs").

For each case: wall time, CPU time, peak resident set, the resident set at a quarter,
half, three quarters and the end of the run (flat memory: no growth beyond the state),
the summary's stop reason and clusters, the verdict of `ballagg verify`, and the machine's
load average (1 min) over the run. Every sample (seconds, resident set, load average) is
kept in DIR/CASE.samples.csv.

Usage: bench/long_runs.py [--cases ed-2d-1e6 ts-2d-1e6 ed-3d-1e5 ts-3d-1e5 rigid-body-3d-1e5
                                   rigid-body-3d-1e5-model-v]
                          [--dir /tmp/ballagg-long-runs] [--threads 2] [--binary PATH]
--binary runs a copy of the program (a rebuild during a run of hours then changes nothing).
Only the Python standard library is used (memory from /proc/PID/status).
"""
import argparse
import json
import os
import resource
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
    # Stops when a body spans half the box (stop_reason body_spans_box: a rigid body cannot
    # touch its own periodic image), at Vf 0.2 before 99% of the mass is aggregated.
    "rigid-body-3d-1e5": ["engine.kind=rigid-body", "system.n=100000", "stop.aggregated_fraction=0.99"] + THREE_D,
    # Richardson's model (v) gas (examples/richardson1995/model-v.toml: 9000 spheres in a
    # cube of side 10) with 10^5 spheres at the same density, as in bench/rigid_body_speed.py.
    "rigid-body-3d-1e5-model-v": ["system.n=100000", f"system.box_length={10 * (1e5 / 9000) ** (1 / 3):.9f}",
                                  "stop.time=inf", "stop.aggregated_fraction=0.99"],
}
CONFIG_FILES = {"rigid-body-3d-1e5-model-v": os.path.join(ROOT, "examples", "richardson1995", "model-v.toml")}


def rss_kb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except FileNotFoundError:
        return None
    return None


def run_case(name, out, threads, binary):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [binary, "run"] + ([CONFIG_FILES[name]] if name in CONFIG_FILES else []) + ["-q", "--out", out, "--set", "output.xyz=false"]
    for s in CASES[name]:
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL)
    samples = []  # (seconds, kB, load average over the last minute)
    while proc.poll() is None:
        kb = rss_kb(proc.pid)
        if kb is not None:
            samples.append((time.monotonic() - start, kb, os.getloadavg()[0]))
        time.sleep(0.5)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode != 0:
        raise SystemExit(f"{name}: ballagg run exited with {proc.returncode}: {' '.join(cmd)}")
    verify = subprocess.run([binary, "verify", out], capture_output=True, text=True)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return cmd, wall, cpu, samples, verify, summary


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
    p.add_argument("--binary", default=BINARY)
    a = p.parse_args()
    print(f"threads {a.threads}; load average at the start {os.getloadavg()[0]:.1f}")
    print("| case | wall (s) | CPU (s) | engine (s) | stop | clusters | peak RSS (MB) | RSS at 25/50/75/100 % (MB) | load average min-max | verify |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in a.cases:
        out = os.path.join(a.dir, name)
        started = time.strftime("%Y-%m-%d %H:%M:%S")
        cmd, wall, cpu, samples, verify, s = run_case(name, out, a.threads, a.binary)
        with open(os.path.join(a.dir, name + ".samples.csv"), "w") as f:
            f.write("seconds,rss_kb,load_average\n")
            f.writelines(f"{t:.1f},{kb},{load:.2f}\n" for t, kb, load in samples)
        peak = max((kb for _, kb, _ in samples), default=0) / 1024
        marks = " / ".join(f"{at_fraction(samples, q) / 1024:.0f}" for q in (0.25, 0.5, 0.75, 1.0))
        loads = [load for _, _, load in samples] or [0.0]
        verdict = "pass" if verify.returncode == 0 else f"FAIL ({verify.returncode}): {verify.stdout.strip()} {verify.stderr.strip()}"
        print(f"| {name} | {wall:.1f} | {cpu:.1f} | {s['wall_seconds']:.1f} | {s['stop_reason']} | {s['n_clusters']} | {peak:.0f} | {marks} "
              f"| {min(loads):.1f}-{max(loads):.1f} | {verdict} |", flush=True)
        print(f"    started {started}, command: OMP_NUM_THREADS={a.threads} {' '.join(cmd)}", flush=True)
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
