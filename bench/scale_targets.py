#!/usr/bin/python3
"""The large-system targets of the engines, each measured and set beside its goal.

Every case is one `ballagg run` (then `ballagg verify`, and for the largest `ed` runs
`ballagg analyze`) of the installed build, one after the other. The peak resident set of
each process is read from the kernel when it ends (wait4's ru_maxrss: the whole process,
outputs included), and "bytes per sphere" is that peak less the program's baseline (the
same binary run with 10 spheres) over N.

Cases (all `output.xyz=false`; the other defaults are the program's: lattice start,
fixed speed 1, stick, run to one cluster):
  ed-2d      ed, 2D, Vf 0.2, walls, at each --sizes, one core: engine time, events/s,
             bytes per sphere, the process's time outside the engine, and the growth
             exponent of the engine time over the sizes (goal: 5e5 events/s at 10^6,
             3e5 at 10^7, exponent <= 1.08);
  ed-3d      the same in 3D (goal as ed-2d, and a peak of at most 3 GB at 10^7);
  analyze    `ballagg analyze` of the largest ed-2d run: wall time and peak (goal: a
             small fraction of the engine time, within the run's memory);
  ed-big     ed, 2D, Vf 0.2, walls at --big-n (10^8 by default), only with --big: goal
             at most 20 GB and 1 hour, verify passing;
  ts         ts rigid, 2D, Vf 0.3, dt_factor 0.005, two threads at --ts-n, only with
             --ts: goal at most 15 minutes and 300 bytes per sphere, verify passing;
             with --ts-held-step, dt_factor 0.005 sqrt(10^6 / N) instead: the step
             keeps the physical length it has at 10^6 (not the paper's rule, which the
             goal names; the row says which);
  model-v    the rigid-body engine on Richardson's model (v)
             (examples/richardson1995/model-v.toml, T = 40.8), one core: goal 3 s of
             engine time. Its 10^5-sphere version is bench/rigid_body_speed.py.
Smallenburg's EDMD beside ed is bench/edmd_compare.py.

Before a case that would not fit, the script projects its peak from the bytes per sphere
of the largest run so far and the memory the machine has (MemAvailable) and skips it with
a line saying so.

Usage: bench/scale_targets.py [--sizes 100000 1000000 10000000] [--dims 2 3]
           [--big] [--big-n 100000000] [--ts] [--ts-n 10000000] [--ts-held-step]
           [--no-model-v]
           [--binary PATH] [--dir /tmp/ballagg-scale-targets] [--seed 1]
Run on an otherwise quiet machine. Only the Python standard library is used.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

import ed_scaling  # machine() and fit_exponent(): bench/ is the script's directory

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")
MODEL_V = os.path.join(ROOT, "examples", "richardson1995", "model-v.toml")

# The goals, as the table prints them.
EVENTS_PER_SECOND_GOAL = {10**6: 5e5, 10**7: 3e5}
GROWTH_EXPONENT_GOAL = 1.08
PEAK_3D_1E7_GOAL_BYTES = 3e9
BIG_PEAK_GOAL_BYTES = 20e9
BIG_WALL_GOAL_SECONDS = 3600.0
TS_WALL_GOAL_SECONDS = 900.0
TS_BYTES_PER_SPHERE_GOAL = 300.0
MODEL_V_GOAL_SECONDS = 3.0
# A projected peak above this share of the machine's available memory skips the case.
MEMORY_HEADROOM = 0.9


def machine():
    return f"{ed_scaling.machine()}, {total_memory_bytes() / 2**30:.1f} GiB"


def meminfo_bytes(key):
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


def total_memory_bytes():
    return meminfo_bytes("MemTotal")


class Measured:
    """One finished process: its wall time, peak resident set and exit status."""

    def __init__(self, cmd, threads):
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
        start = time.monotonic()
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        _, status, usage = os.wait4(proc.pid, 0)
        self.wall = time.monotonic() - start
        self.peak_bytes = usage.ru_maxrss * 1024
        self.returncode = os.waitstatus_to_exitcode(status)
        self.stderr = proc.stderr.read().decode(errors="replace").strip()
        proc.returncode = self.returncode
        self.cmd = cmd
        if self.returncode != 0:
            raise SystemExit(f"exit {self.returncode}: {' '.join(cmd)}\n{self.stderr}")


def run(binary, out, sets, threads=1, config=None):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [binary, "run"] + ([config] if config else []) + ["-q", "--out", out, "--set", "output.xyz=false"]
    for s in sets:
        cmd += ["--set", s]
    m = Measured(cmd, threads)
    with open(os.path.join(out, "summary.json")) as f:
        m.summary = json.load(f)
    return m


def verify(binary, out):
    r = subprocess.run([binary, "verify", out], capture_output=True, text=True)
    return "pass" if r.returncode == 0 else f"FAIL ({r.returncode})"


def verdict(value, goal, at_most=True):
    return "met" if (value <= goal if at_most else value >= goal) else "not met"


class Table:
    def __init__(self):
        print("| case | N | engine (s) | process (s) | outside engine (s) | events | events/s | peak (MB) | bytes/sphere | verify | goal | verdict |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")

    def row(self, case, n, m, baseline, verified, goal="", met=""):
        s = m.summary
        engine = s["wall_seconds"]
        per_sphere = (m.peak_bytes - baseline) / n
        print(f"| {case} | {n} | {engine:.2f} | {m.wall:.2f} | {m.wall - engine:.2f} | {s['events']} | "
              f"{s['events_per_second']:.3g} | {m.peak_bytes / 1e6:.0f} | {per_sphere:.0f} | {verified} | {goal} | {met} |",
              flush=True)
        return per_sphere


def fits(n, bytes_per_sphere, baseline, case):
    if bytes_per_sphere is None:
        return True
    projected = baseline + n * bytes_per_sphere
    available = meminfo_bytes("MemAvailable")
    if projected <= MEMORY_HEADROOM * available:
        return True
    print(f"| {case} | {n} | skipped: projected peak {projected / 1e9:.1f} GB "
          f"({bytes_per_sphere:.0f} B/sphere) above {MEMORY_HEADROOM:.0%} of the {available / 1e9:.1f} GB available | | | | | | | | | |",
          flush=True)
    return False


def ed_series(a, table, dim, baseline):
    sets = [f"system.dimension={dim}", "system.volume_fraction=0.2", "system.boundary=walls", "engine.kind=ed"]
    done, per_sphere = [], None
    for n in a.sizes:
        case = f"ed-{dim}d"
        if not fits(n, per_sphere, baseline, case):
            break
        out = os.path.join(a.dir, f"{case}-{n}")
        m = run(a.binary, out, sets + [f"system.n={n}", f"initial.seed={a.seed}"])
        goals = []
        if n in EVENTS_PER_SECOND_GOAL:
            goals.append((f">= {EVENTS_PER_SECOND_GOAL[n]:.0e} events/s",
                          verdict(m.summary["events_per_second"], EVENTS_PER_SECOND_GOAL[n], at_most=False)))
        if dim == 3 and n == 10**7:
            goals.append((f"peak <= {PEAK_3D_1E7_GOAL_BYTES / 1e9:.0f} GB", verdict(m.peak_bytes, PEAK_3D_1E7_GOAL_BYTES)))
        per_sphere = table.row(case, n, m, baseline, verify(a.binary, out),
                               "; ".join(g for g, _ in goals), "; ".join(v for _, v in goals))
        done.append((n, m.summary["wall_seconds"], out))
    if len(done) > 1:
        z = ed_scaling.fit_exponent([n for n, _, _ in done], [t for _, t, _ in done])
        print(f"| ed-{dim}d | growth exponent {done[0][0]}..{done[-1][0]} | {z:.3f} | | | | | | | | "
              f"<= {GROWTH_EXPONENT_GOAL} | {verdict(z, GROWTH_EXPONENT_GOAL)} |", flush=True)
    return done


def analyze_largest(a, done):
    n, engine_seconds, out = done[-1]
    m = Measured([a.binary, "analyze", "-q", out, "--out", out + "-analysis"], 1)
    print(f"\n`ballagg analyze` of the ed-2d run at N = {n}: {m.wall:.2f} s "
          f"({m.wall / engine_seconds:.2%} of the engine's {engine_seconds:.2f} s), peak {m.peak_bytes / 1e6:.0f} MB",
          flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", type=int, nargs="+", default=[10**5, 10**6, 10**7])
    p.add_argument("--dims", type=int, nargs="+", default=[2, 3], choices=[2, 3])
    p.add_argument("--big", action="store_true", help="run ed-big")
    p.add_argument("--big-n", type=int, default=10**8)
    p.add_argument("--ts", action="store_true", help="run the ts case")
    p.add_argument("--ts-n", type=int, default=10**7)
    p.add_argument("--ts-held-step", action="store_true",
                   help="ts with dt_factor 0.005 sqrt(10^6 / N): the step of 10^6 held")
    p.add_argument("--no-model-v", action="store_true")
    p.add_argument("--binary", default=BINARY)
    p.add_argument("--dir", default="/tmp/ballagg-scale-targets")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    if not os.path.exists(a.binary):
        sys.exit(f"{a.binary} not found: run `make build` first")
    os.makedirs(a.dir, exist_ok=True)

    print(f"machine: {machine()}")
    print(f"command: bench/scale_targets.py {' '.join(sys.argv[1:])}".rstrip())
    print(f"started {time.strftime('%Y-%m-%d %H:%M:%S')}, load average {os.getloadavg()[0]:.1f}")
    baseline = run(a.binary, os.path.join(a.dir, "baseline"), ["system.n=10"]).peak_bytes
    print(f"baseline (10 spheres): {baseline / 2**20:.1f} MiB\n")
    table = Table()
    largest_2d = []
    for dim in a.dims:
        done = ed_series(a, table, dim, baseline)
        if dim == 2:
            largest_2d = done
    if a.big:
        out = os.path.join(a.dir, "ed-big")
        m = run(a.binary, out, ["system.dimension=2", "system.volume_fraction=0.2", "system.boundary=walls",
                                "engine.kind=ed", f"system.n={a.big_n}", f"initial.seed={a.seed}"])
        met = f"{verdict(m.peak_bytes, BIG_PEAK_GOAL_BYTES)}; {verdict(m.wall, BIG_WALL_GOAL_SECONDS)}"
        table.row("ed-big", a.big_n, m, baseline, verify(a.binary, out), "<= 20 GB; <= 1 h", met)
    if a.ts:
        out = os.path.join(a.dir, "ts")
        dt_factor = 0.005 * (10**6 / a.ts_n) ** 0.5 if a.ts_held_step else 0.005
        m = run(a.binary, out, ["system.dimension=2", "system.volume_fraction=0.3", "engine.kind=ts",
                                f"ts.dt_factor={dt_factor:.10g}", f"system.n={a.ts_n}", f"initial.seed={a.seed}"],
                threads=2)
        per_sphere = (m.peak_bytes - baseline) / a.ts_n
        met = f"{verdict(m.wall, TS_WALL_GOAL_SECONDS)}; {verdict(per_sphere, TS_BYTES_PER_SPHERE_GOAL)}"
        case = f"ts (2 threads, dt_factor {dt_factor:.6g})"
        table.row(case, a.ts_n, m, baseline, verify(a.binary, out), "<= 15 min; <= 300 B/sphere", met)
    if not a.no_model_v:
        out = os.path.join(a.dir, "model-v")
        m = run(a.binary, out, [], config=MODEL_V)
        table.row("model-v", 9000, m, baseline, verify(a.binary, out), f"engine <= {MODEL_V_GOAL_SECONDS:.0f} s",
                  verdict(m.summary["wall_seconds"], MODEL_V_GOAL_SECONDS))
    if largest_2d:
        analyze_largest(a, largest_2d)
    print(f"\nfinished {time.strftime('%Y-%m-%d %H:%M:%S')}, load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
