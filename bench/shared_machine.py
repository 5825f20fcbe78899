#!/usr/bin/python3
"""A time-stepping run on a machine another process keeps busy.

Times the same run (2D, N = 10^4, Vf 0.3, ts.dt_factor 0.005: 0.2-0.3 s on one core) on
the machine as it is ("alone") and beside busy processes (`python3 -c 'while True: pass'`,
one by default, unpinned unless --pin), each way with
  default  - no OMP_* variable: the team is ballagg's own choice (docs/time_stepping.md#threads)
  1 thread - OMP_NUM_THREADS=1
  fixed    - OMP_NUM_THREADS=<allowed cores>: a team of every core, whatever the load
The modes are run in rounds (every mode once a round, --repeats rounds) and the medians
reported. Prints the machine, the commit, the load average before and after, a Markdown
table, and whether the targets hold:
  beside the busy process(es), default <= 1.5 x 1 thread;
  alone, default within TOLERANCE of fixed (the two-thread speed is kept).
--python times the same run through the Python module (sim.run(), timed inside the
interpreter) instead of the command line (the whole process, as a user waits for it);
--chunk TIME makes it a loop of short calls, sim.run(time=t) for t = TIME, 2 TIME, ... (0.5:
about 300 calls of 1 ms at N = 10^4).
--binary times another build (e.g. an older commit) the same way. --late SECONDS starts
the busy process(es) that long after each run instead of before it: the team is then
chosen from its threads' waits, not from the glance at the start (use a run of a few
seconds, --n 100000).

The machine should otherwise be idle: check `uptime` first. Only the standard library is used.

Usage: bench/shared_machine.py [--repeats 7] [--competitors 1] [--pin] [--python [--chunk TIME]]
                               [--binary build/bin/ballagg] [--n 10000] [--late SECONDS]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")
PYTHON_DIR = os.path.join(ROOT, "build", "python")
TARGET_SHARED = 1.5  # default / one thread beside the busy process(es)
TOLERANCE_ALONE = 1.15  # default / fixed team with no busy process (its runs vary by ~10 %)
OMP_VARIABLES = ("OMP_NUM_THREADS", "OMP_DYNAMIC", "OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "OMP_THREAD_LIMIT")

PYTHON_RUN = """
import sys, time, ballagg
config = ballagg.Config({"engine": {"kind": "ts"}, "ts": {"dt_factor": 0.005},
                         "system": {"n": int(sys.argv[1]), "volume_fraction": 0.3}})
sim = ballagg.Simulation(config)
chunk = float(sys.argv[2])
start = time.perf_counter()
if chunk > 0:
    t = 0.0
    while sim.n_clusters > 1:
        t += chunk
        sim.run(time=t)
else:
    sim.run()
print(time.perf_counter() - start)
"""


def machine():
    model, cpus = "?", "?"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "Model name":
                model = value.strip()
            if key.strip() == "CPU(s)":
                cpus = value.strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return f"{model}, {cpus} CPUs ({len(os.sched_getaffinity(0))} allowed)"


def commit():
    def git(*args):
        return subprocess.run(["git", "-C", ROOT, *args], capture_output=True, text=True).stdout.strip()
    dirty = " (with uncommitted changes)" if git("status", "--porcelain", "--untracked-files=no") else ""
    return (git("rev-parse", "--short", "HEAD") or "?") + dirty


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:4])


def environment(threads):
    env = {k: v for k, v in os.environ.items() if k not in OMP_VARIABLES}
    if threads is not None:
        env["OMP_NUM_THREADS"] = str(threads)
    if os.path.isdir(PYTHON_DIR):
        env["PYTHONPATH"] = PYTHON_DIR + os.pathsep + env.get("PYTHONPATH", "")
    return env


def time_run(args, threads, scratch, late_competitors=0):
    """Seconds of one run with OMP_NUM_THREADS=threads (None: no OMP_* variable), with
    late_competitors busy processes started args.late seconds after it."""
    env = environment(threads)
    if args.python:
        cmd = [sys.executable, "-c", PYTHON_RUN, str(args.n), str(args.chunk)]
    else:
        out_dir = os.path.join(scratch, "run")
        shutil.rmtree(out_dir, ignore_errors=True)
        cmd = [args.binary, "run", "-q", "--set", "engine.kind=ts", "--set", f"system.n={args.n}",
               "--set", "system.volume_fraction=0.3", "--set", "ts.dt_factor=0.005", "--out", out_dir]
    start = time.perf_counter()
    run = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True)
    procs = []
    if late_competitors:
        try:
            run.wait(timeout=args.late)
        except subprocess.TimeoutExpired:
            procs = start_competitors(late_competitors, args.pin, settle=0.0)
    out = run.communicate()[0]
    seconds = time.perf_counter() - start
    stop(procs)
    if run.returncode != 0:
        raise SystemExit(f"run failed ({run.returncode}): {' '.join(cmd)}")
    return float(out.split()[-1]) if args.python else seconds


def start_competitors(count, pin, settle=0.5):
    procs = []
    for k in range(count):
        cpu = sorted(os.sched_getaffinity(0))[k % len(os.sched_getaffinity(0))]
        preexec = (lambda c=cpu: os.sched_setaffinity(0, {c})) if pin else None
        procs.append(subprocess.Popen([sys.executable, "-c", "while True: pass"], preexec_fn=preexec))
    time.sleep(settle)  # running, and seen by the scheduler as busy
    return procs


def stop(procs):
    for p in procs:
        p.kill()
    for p in procs:
        p.wait()


def conditions(args):
    late = "" if args.late is None else f" after {args.late:g} s"
    return ("alone", f"+{args.competitors} busy{late}")


def measure(args, scratch):
    cores = len(os.sched_getaffinity(0))
    modes = {"default": None, "1 thread": 1, f"fixed {cores}": cores}
    conds = conditions(args)
    times = {(cond, mode): [] for cond in conds for mode in modes}
    for round_ in range(args.repeats):
        for cond in conds:
            busy = cond != conds[0]
            procs = start_competitors(args.competitors, args.pin) if busy and args.late is None else []
            late = args.competitors if busy and args.late is not None else 0
            try:
                for mode, threads in modes.items():
                    times[(cond, mode)].append(time_run(args, threads, scratch, late))
            finally:
                stop(procs)
        print(f"round {round_ + 1}/{args.repeats} done, load {load()}", file=sys.stderr, flush=True)
    return modes, {key: statistics.median(v) for key, v in times.items()}, times


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeats", type=int, default=7)
    p.add_argument("--competitors", type=int, default=1, help="busy processes beside the run")
    p.add_argument("--pin", action="store_true", help="pin each busy process to one CPU")
    p.add_argument("--python", action="store_true", help="run through the Python module")
    p.add_argument("--chunk", type=float, default=0.0, metavar="TIME",
                   help="with --python: sim.run(time=t) in steps of TIME (simulated) until one cluster")
    p.add_argument("--binary", default=BINARY)
    p.add_argument("--n", type=int, default=10000)
    p.add_argument("--late", type=float, default=None, metavar="SECONDS",
                   help="start the busy process(es) this long after each run")
    args = p.parse_args()

    print(f"machine: {machine()}")
    print(f"commit: {commit()}" + ("" if args.binary == BINARY else f", binary {args.binary}"))
    calls = f"sim.run(time=t), t in steps of {args.chunk:g}" if args.chunk > 0 else "sim.run()"
    via = f"the Python module ({calls})" if args.python else "the command line (whole process)"
    competitor = f"{args.competitors} x `python3 -c 'while True: pass'`" + (" pinned" if args.pin else "")
    print(f"run: ts, 2D, N = {args.n}, Vf 0.3, dt_factor 0.005, through {via}; "
          f"busy: {competitor}; median of {args.repeats}")
    print(f"load average before: {load()}")
    with tempfile.TemporaryDirectory() as scratch:
        modes, median, every = measure(args, scratch)
    print(f"load average after: {load()}\n")
    names = list(modes)
    conds = conditions(args)
    print("| beside the run | " + " | ".join(f"{m} (s)" for m in names) + " | default / 1 thread | default / fixed |")
    print("|---|" + "---|" * (len(names) + 2))
    for cond in conds:
        row = [median[(cond, m)] for m in names]
        print(f"| {cond} | " + " | ".join(f"{t:.3f}" for t in row)
              + f" | {row[0] / row[1]:.2f} | {row[0] / row[2]:.2f} |")
    print()
    width = max(len(f"{c} {m}") for c, m in every)
    for (cond, mode), values in every.items():
        print(f"  {f'{cond} {mode}':{width}}: " + " ".join(f"{t:.3f}" for t in values))
    shared = median[(conds[1], names[0])] / median[(conds[1], names[1])]
    alone = median[(conds[0], names[0])] / median[(conds[0], names[2])]
    print(f"\n{conds[1]}: default = {shared:.2f} x one thread "
          f"(target <= {TARGET_SHARED}): {'holds' if shared <= TARGET_SHARED else 'MISSED'}")
    print(f"alone: default = {alone:.2f} x the fixed team of {len(os.sched_getaffinity(0))} "
          f"(<= {TOLERANCE_ALONE}): {'holds' if alone <= TOLERANCE_ALONE else 'MISSED'}")


if __name__ == "__main__":
    main()
