#!/usr/bin/python3
"""ballagg's `ed` engine beside Smallenburg's EDMD on EDMD's own benchmark, one core each.

The benchmark: a 3D elastic hard-sphere gas (sigma = 1, m = 1, kT = 1), N of about 32 000
in a periodic cube, at packing fractions 0.45 and 0.25. EDMD is F. Smallenburg's
event-driven code ("Efficient event-driven simulations of hard spheres", Eur. Phys. J. E
45, 22 (2022)), its variant `Single/mdSingle.c` (one event per particle, neighbour lists),
MIT licence. Its code is not part of ballagg and is not shipped with it; get it with

    git clone https://github.com/FSmallenburg/EDMD

and give the checkout (or its Single/mdSingle.c) as --edmd PATH. The script copies
mdSingle.c, mdSingle.h and mt19937ar.c to a temporary directory, sets the globals the code
reads its parameters from (N, packfrac, maxtime; initialconfig = 1 for its FCC start,
usethermostat = 0, makesnapshots = 0, writeinterval so that a report falls on maxtime),
stopping with an error if a definition is not found, builds it with
`gcc -O3 -march=native ... -lm` (--edmd-cflags; EDMD's own Makefile uses -Ofast
-funroll-loops -march=native) and runs it there.

ballagg runs `ed` with OMP_NUM_THREADS=1: N = 32 768 on its simple cubic lattice (the
random start jams near a volume fraction of 0.38 in 3D and cannot reach 0.45), radius 0.5,
periodic, Gaussian velocities with <|v|^2> = 3 (kT = 1), zero momentum, bounces with
restitution 1, no trajectory.

Equal footing:
  * Collisions per second, not events: EDMD counts collisions only (its neighbour-list
    updates are events too, uncounted), ballagg's `events` also count neighbour-list
    rebuilds. ballagg's figure is `collisions` of summary.json (all
    bounces here; `events` is printed beside it).
  * Time: ballagg's is `wall_seconds` of summary.json, the engine's time without set-up
    and output. EDMD prints no timing; its time is the process's wall time
    (time.perf_counter) less that of the same build run to maxtime = 0 (set-up, the
    first report and the final snapshot), the minimum of those set-up runs.
  * Collision count: EDMD's last report line ("Simtime: T, Collisions: C, ...", one every
    writeinterval) at T = maxtime; the one event EDMD handles past maxtime is not in it.
  * Start: both start from a lattice at the packing fraction asked (EDMD FCC, N = 4 k^3;
    ballagg simple cubic) with Gaussian velocities and zero total momentum. EDMD has no
    equilibration phase of its own, so by default both timings include the lattice's
    melting (EDMD's FCC at 0.45 melts in about 2 time units: fewer collisions than the
    fluid at first; ballagg's simple cubic lattice, more). --equilibrate TIME runs both
    that long first, untimed, and times runs from there: EDMD from its end snapshot
    (snapshot_end.sph, read as its start file; it draws new velocities at kT = 1), ballagg
    on from the finished run (initial.file). EDMD scales its velocities to kT = 1 exactly;
    ballagg's kinetic energy is drawn (about 3N/2). The table's "per sphere" column
    (2 C / (N t)) is set beside the equilibrium fluid's rate from Enskog's theory with the
    Carnahan-Starling contact value, and EDMD's rate in each report interval is printed,
    to show how far a run is from equilibrium.
  * EDMD's source sets usethermostat = 1 (its README calls the thermostat off by
    default, and the paper's runs are microcanonical): it is set to 0 here, so that both
    run an NVE gas; --edmd-thermostat keeps it on.
  * Compilers: EDMD gets -march=native here; ballagg's build has none (its results are
    the same on any x86-64 machine), so it gives EDMD the vector instructions of the CPU.
  * Both runs are deterministic (seed 1), so repeats redo the same work.

Cases: packing fraction 0.45 to t = 5 (both), 0.25 to t = 20 (EDMD) and t = 10 (ballagg)
by default; other packing fractions need --edmd-times and --ballagg-times. Each repeat runs
EDMD's set-up run, EDMD and ballagg in turn; the table gives the minimum and the median of
the wall times and the rates from them, and ballagg / EDMD of the collision rates.

Usage: bench/edmd_compare.py --edmd PATH [--ballagg build/bin/ballagg] [--repeats 3]
           [--packing-fractions 0.45 0.25] [--edmd-times 5 20] [--ballagg-times 5 10]
           [--edmd-n 32000] [--ballagg-n 32768] [--edmd-cflags "-O3 -march=native"]
           [--edmd-thermostat] [--equilibrate TIME] [--keep DIR]
Run one at a time on an otherwise quiet machine. Only the Python standard library is used.
"""
import argparse
import json
import math
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_BALLAGG = os.path.join(ROOT, "build", "bin", "ballagg")

# (EDMD's simulated time, ballagg's) for the default packing fractions: about 2 x 10^6
# collisions for EDMD at either density.
DEFAULT_TIMES = {0.45: (5.0, 5.0), 0.25: (20.0, 10.0)}

EDMD_FILES = ("mdSingle.c", "mdSingle.h", "mt19937ar.c")
EDMD_REPORT = re.compile(r"^Simtime:\s*([-+0-9.eE]+),\s*Collisions:\s*(\d+),", re.MULTILINE)
# Relative slack between EDMD's last report time and maxtime (its report times are sums
# of writeinterval, exact to a few ulp).
REPORT_TIME_TOLERANCE = 1e-9
EDMD_FILENAME_LENGTH = 100  # char inputfilename[100] in mdSingle.c
EDMD_END_SNAPSHOT = "snapshot_end.sph"  # the state EDMD writes at maxtime
SPEED_RMS_KT1 = math.sqrt(3.0)  # <|v|^2> = 3 kT / m in 3D


def fail(message):
    print(f"edmd_compare: error: {message}", file=sys.stderr)
    sys.exit(2)


def edmd_source_dir(path):
    """The folder holding mdSingle.c and the files it includes, from a checkout, its
    Single/ folder or the path of mdSingle.c itself."""
    if os.path.isfile(path):
        folder = os.path.dirname(os.path.abspath(path))
    elif os.path.isfile(os.path.join(path, "Single", "mdSingle.c")):
        folder = os.path.join(path, "Single")
    else:
        folder = path
    missing = [f for f in EDMD_FILES if not os.path.isfile(os.path.join(folder, f))]
    if missing:
        fail(f"--edmd {path}: {', '.join(missing)} not found in {folder} (give a checkout of "
             "https://github.com/FSmallenburg/EDMD, its Single/ folder or Single/mdSingle.c)")
    return folder


def set_global(source, declaration, value):
    """Replace the initial value of the global `declaration` (e.g. 'double maxtime')."""
    words = r"\s+".join(re.escape(w) for w in declaration.split())
    pattern = re.compile(r"^(\s*" + words + r"\s*=\s*)[^;]+;", re.MULTILINE)
    if len(pattern.findall(source)) != 1:
        fail(f"mdSingle.c: expected one definition '{declaration} = ...;' at the start of a line, "
             f"found {len(pattern.findall(source))}; this EDMD version is laid out differently, "
             "adapt set_global's calls in bench/edmd_compare.py")
    return pattern.sub(lambda m: f"{m.group(1)}{value};", source)


def edmd_settings(n, packing_fraction, maxtime, thermostat, start_file=None):
    """The globals of mdSingle.c to set, in the order they are set: its FCC start, or the
    snapshot start_file (an .sph file) when given."""
    reports = max(1, round(maxtime))
    write_interval = maxtime / reports if maxtime > 0 else 1.0
    settings = [
        ("double maxtime", repr(float(maxtime))),
        ("int makesnapshots", "0"),
        ("double writeinterval", repr(write_interval)),
        ("int initialconfig", "1" if start_file is None else "0"),
        ("double packfrac", repr(float(packing_fraction))),
        ("int N", str(n)),
        ("const int usethermostat", "1" if thermostat else "0"),
    ]
    if start_file is not None:
        if len(start_file) >= EDMD_FILENAME_LENGTH or '"' in start_file or "\\" in start_file:
            fail(f"{start_file}: EDMD reads its start from a path of fewer than {EDMD_FILENAME_LENGTH} "
                 "characters without quotes or backslashes (use a shorter TMPDIR or --keep DIR)")
        settings.append(("char inputfilename[100]", f'"{start_file}"'))
    return settings


def check_edmd_source(source_dir, args):
    """Stop before any run if mdSingle.c lacks a definition the script sets."""
    with open(os.path.join(source_dir, "mdSingle.c")) as f:
        source = f.read()
    for declaration, value in edmd_settings(args.edmd_n, 0.25, 1.0, False, "start.sph"):
        source = set_global(source, declaration, value)


def build_edmd(source_dir, build_dir, settings, cflags):
    """Copy EDMD's files into build_dir, set its globals, compile; the binary's path."""
    os.makedirs(build_dir)
    for name in EDMD_FILES:
        shutil.copy(os.path.join(source_dir, name), build_dir)
    main_file = os.path.join(build_dir, "mdSingle.c")
    with open(main_file) as f:
        source = f.read()
    for declaration, value in settings:
        source = set_global(source, declaration, value)
    with open(main_file, "w") as f:
        f.write(source)
    binary = os.path.join(build_dir, "md")
    cmd = ["gcc", *shlex.split(cflags), "mdSingle.c", "-o", binary, "-lm"]
    done = subprocess.run(cmd, cwd=build_dir, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"building EDMD failed ({' '.join(cmd)}):\n{done.stderr}")
    return binary


def run_edmd(binary, run_dir):
    """(process wall seconds, reports [(time, collisions)]) of one EDMD run in run_dir."""
    os.makedirs(run_dir)
    start = time.perf_counter()
    done = subprocess.run([binary], cwd=run_dir, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        fail(f"EDMD exited with {done.returncode}:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    reports = [(float(t), int(c)) for t, c in EDMD_REPORT.findall(done.stdout)]
    if not reports:
        fail(f"no 'Simtime: ..., Collisions: ...' line in EDMD's output:\n{done.stdout[-2000:]}")
    return wall, reports


def edmd_result(wall, setup_wall, reports, maxtime, n):
    """One EDMD run's figures: its last report must fall on maxtime."""
    end_time, collisions = reports[-1]
    if abs(end_time - maxtime) > REPORT_TIME_TOLERANCE * max(1.0, maxtime):
        fail(f"EDMD's last report is at t = {end_time}, not at maxtime = {maxtime}")
    interval_rates = [2.0 * (c1 - c0) / (n * (t1 - t0)) for (t0, c0), (t1, c1) in zip(reports, reports[1:])]
    return {"wall": wall - setup_wall, "time": end_time, "collisions": collisions,
            "events": None, "interval_rates": interval_rates}


def run_ballagg(binary, n, packing_fraction, stop_time, out_dir, start_dir=None):
    """One ballagg `ed` run's figures from its summary.json: from its lattice, or on from
    the finished run in start_dir (stop_time then counts from that run's end)."""
    sets = {
        "system.dimension": 3, "system.n": n, "system.volume_fraction": packing_fraction,
        "system.radius": 0.5, "system.boundary": "periodic", "initial.positions": "lattice",
        "initial.velocities": "gaussian", "initial.speed": f"{SPEED_RMS_KT1:.9f}",
        "initial.zero_momentum": "true", "collision.outcome": "bounce",
        "collision.restitution": 1, "stop.time": stop_time, "output.xyz": "false",
        "engine.kind": "ed",
    }
    start_time = 0.0
    if start_dir is not None:
        with open(os.path.join(start_dir, "summary.json")) as f:
            start_time = json.load(f)["time"]
        sets.update({"initial.positions": "file", "initial.file": start_dir, "stop.time": start_time + stop_time})
    cmd = [binary, "run", "-q", "--out", out_dir]
    for key, value in sets.items():
        cmd += ["--set", f"{key}={value}"]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"ballagg exited with {done.returncode}: {done.stderr.strip()}")
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    return {"wall": summary["wall_seconds"], "time": summary["time"] - start_time,
            "collisions": summary["collisions"], "events": summary["events"], "interval_rates": []}


def equilibrate(args, source_dir, case_dir, pf, duration):
    """Run both programs from their lattices for `duration`: (EDMD's end snapshot,
    ballagg's run folder), the starts of the timed runs."""
    settings = edmd_settings(args.edmd_n, pf, duration, args.edmd_thermostat)
    binary = build_edmd(source_dir, os.path.join(case_dir, "build-equilibrate"), settings, args.edmd_cflags)
    run_dir = os.path.join(case_dir, "equilibrate-edmd")
    run_edmd(binary, run_dir)
    ballagg_dir = os.path.join(case_dir, "equilibrate-ballagg")
    run_ballagg(args.ballagg, args.ballagg_n, pf, duration, ballagg_dir)
    return os.path.join(run_dir, EDMD_END_SNAPSHOT), ballagg_dir


def enskog_rate(packing_fraction):
    """Collisions per sphere per unit time of the equilibrium fluid (sigma = m = kT = 1):
    Enskog's 4 rho g(sigma) sqrt(pi) with the Carnahan-Starling contact value."""
    phi = packing_fraction
    z = (1 + phi + phi ** 2 - phi ** 3) / (1 - phi) ** 3
    contact = (z - 1) / (4 * phi)
    density = 6 * phi / math.pi
    return 4 * density * contact * math.sqrt(math.pi)


def machine():
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    allowed = len(os.sched_getaffinity(0))
    return f"{model}, {os.cpu_count()} cores ({allowed} allowed)"


def load_average():
    return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())


def case_times(args):
    """[(packing fraction, EDMD time, ballagg time)] from the options."""
    fractions = args.packing_fractions
    for name in ("edmd_times", "ballagg_times"):
        given = getattr(args, name)
        if given is not None and len(given) != len(fractions):
            fail(f"--{name.replace('_', '-')} needs one time per packing fraction ({len(fractions)})")
    cases = []
    for i, pf in enumerate(fractions):
        if not 0 < pf < 0.74:
            fail(f"--packing-fractions {pf}: a hard-sphere packing fraction lies in (0, 0.74)")
        default = DEFAULT_TIMES.get(pf)
        times = [getattr(args, name)[i] if getattr(args, name) is not None else
                 (default[j] if default else None) for j, name in enumerate(("edmd_times", "ballagg_times"))]
        if None in times:
            fail(f"packing fraction {pf} has no default times: give --edmd-times and --ballagg-times")
        if min(times) <= 0:
            fail(f"packing fraction {pf}: the simulated times must be > 0")
        cases.append((pf, *times))
    return cases


def summarise(runs):
    walls = [r["wall"] for r in runs]
    first = runs[0]
    for r in runs[1:]:
        if r["collisions"] != first["collisions"]:
            fail(f"repeats of one run differ in collisions: {first['collisions']} and {r['collisions']}")
    return {"min": min(walls), "median": statistics.median(walls), **first}


def rate(collisions, wall):
    return collisions / wall if wall > 0 else float("inf")


def print_case(pf, n_edmd, n_ballagg, edmd, ballagg):
    """The case's two Markdown rows."""
    ratios = (rate(ballagg["collisions"], ballagg["min"]) / rate(edmd["collisions"], edmd["min"]),
              rate(ballagg["collisions"], ballagg["median"]) / rate(edmd["collisions"], edmd["median"]))
    for name, n, r in (("EDMD", n_edmd, edmd), ("ballagg ed", n_ballagg, ballagg)):
        per_sphere = 2.0 * r["collisions"] / (n * r["time"])
        ratio = f"{ratios[0]:.2f} ({ratios[1]:.2f})" if name != "EDMD" else ""
        print(f"| {pf} | {name} | {n} | {r['time']:g} | {r['collisions']} | {per_sphere:.2f} "
              f"| {r['min']:.3f} ({r['median']:.3f}) | {rate(r['collisions'], r['min']):.3g} "
              f"({rate(r['collisions'], r['median']):.3g}) | {ratio} |", flush=True)


def run_case(args, source_dir, work, pf, edmd_time, ballagg_time):
    """Build EDMD for the case, run both programs --repeats times alternated; the summaries."""
    case_dir = os.path.join(work, f"pf{pf}")
    os.makedirs(case_dir)
    edmd_start, ballagg_start = None, None
    if args.equilibrate > 0:
        edmd_start, ballagg_start = equilibrate(args, source_dir, case_dir, pf, args.equilibrate)
    settings = [edmd_settings(args.edmd_n, pf, t, args.edmd_thermostat, edmd_start) for t in (edmd_time, 0.0)]
    binary, setup_binary = (build_edmd(source_dir, os.path.join(case_dir, name), s, args.edmd_cflags)
                            for name, s in zip(("build", "build-setup"), settings))
    setup_walls, edmd_raw, ballagg_runs = [], [], []
    for k in range(args.repeats):
        setup_walls.append(run_edmd(setup_binary, os.path.join(case_dir, f"setup-{k}"))[0])
        edmd_raw.append(run_edmd(binary, os.path.join(case_dir, f"edmd-{k}")))
        out_dir = os.path.join(case_dir, f"ballagg-{k}")
        ballagg_runs.append(run_ballagg(args.ballagg, args.ballagg_n, pf, ballagg_time, out_dir, ballagg_start))
        shutil.rmtree(out_dir)
    setup = min(setup_walls)
    edmd_runs = [edmd_result(wall, setup, reports, edmd_time, args.edmd_n) for wall, reports in edmd_raw]
    return summarise(edmd_runs), summarise(ballagg_runs), setup


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--edmd", required=True, help="an EDMD checkout, its Single/ folder or Single/mdSingle.c")
    ap.add_argument("--ballagg", default=DEFAULT_BALLAGG, help="the ballagg binary (default: build/bin/ballagg)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--packing-fractions", type=float, nargs="+", default=[0.45, 0.25])
    ap.add_argument("--edmd-times", type=float, nargs="+")
    ap.add_argument("--ballagg-times", type=float, nargs="+")
    ap.add_argument("--edmd-n", type=int, default=32000, help="4 k^3 for EDMD's FCC start (default 32000)")
    ap.add_argument("--ballagg-n", type=int, default=32768)
    ap.add_argument("--edmd-cflags", default="-O3 -march=native")
    ap.add_argument("--edmd-thermostat", action="store_true", help="keep EDMD's thermostat on")
    ap.add_argument("--equilibrate", type=float, default=0.0,
                    help="run both from their lattices this long first, untimed, and time the runs from there")
    ap.add_argument("--keep", help="build and run EDMD in this new folder and keep it (default: a temporary one)")
    args = ap.parse_args()
    if args.repeats < 1:
        fail("--repeats must be at least 1")
    if not 0 <= args.equilibrate < math.inf:
        fail("--equilibrate must be a finite time >= 0")
    k = round((args.edmd_n / 4) ** (1 / 3))
    if 4 * k ** 3 != args.edmd_n:
        fail(f"--edmd-n {args.edmd_n}: EDMD's FCC start needs N = 4 k^3 (e.g. {4 * k ** 3})")
    if not os.access(args.ballagg, os.X_OK):
        fail(f"--ballagg {args.ballagg}: not an executable file (build it with make build)")
    return args


def main():
    args = parse_args()
    source_dir = edmd_source_dir(args.edmd)
    check_edmd_source(source_dir, args)
    cases = case_times(args)
    print(f"machine: {machine()}; load average {load_average()} at the start")
    print(f"EDMD: {source_dir}, gcc {args.edmd_cflags}, thermostat {'on' if args.edmd_thermostat else 'off'}; "
          f"ballagg: {args.ballagg}; {args.repeats} repeat(s), alternated\n")
    print("| packing fraction | program | N | simulated time | collisions | per sphere per unit time "
          "| wall s, min (median) | collisions/s, min (median) | ballagg / EDMD |")
    print("|---|---|---|---|---|---|---|---|---|")
    notes = []
    work = os.path.abspath(args.keep) if args.keep else tempfile.mkdtemp(prefix="edmd_compare-")
    if args.keep:
        os.makedirs(work)
    try:
        for pf, edmd_time, ballagg_time in cases:
            edmd, ballagg, setup = run_case(args, source_dir, work, pf, edmd_time, ballagg_time)
            print_case(pf, args.edmd_n, args.ballagg_n, edmd, ballagg)
            intervals = ", ".join(f"{r:.1f}" for r in edmd["interval_rates"])
            notes.append(f"* {pf}: equilibrium fluid {enskog_rate(pf):.2f} collisions per sphere per unit "
                         f"time (Enskog, Carnahan-Starling); EDMD by report interval: {intervals}; "
                         f"EDMD set-up run {setup:.3f} s (subtracted); ballagg events {ballagg['events']}")
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    print("\nRates: collisions over the minimum (median) wall time; ratio of the collision rates.")
    print("\n".join(notes))
    print(f"load average {load_average()} at the end")


if __name__ == "__main__":
    main()
