#!/usr/bin/python3
"""The output corpus: small runs of every engine and cluster model whose files must not change.

Each case runs `ballagg` (a run, a resumed run, `analyze`, `verify`) and hashes the files it
writes. `--record` writes the hashes to the manifest; without it the hashes are compared with
the manifest and every difference is listed. What a restructuring of the code must leave alone
is exactly this: the bytes users get.

Left out of the hashes: what depends on the wall clock (`wall_seconds`, `events_per_second` of
summary.json) and on the machine (`version` is kept: it changes only with a release).

Usage: output_corpus.py BALLAGG_BINARY [--record] [--manifest FILE] [--only REGEX] [--keep DIR]
"""
import argparse
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_MANIFEST = os.path.join(HERE, "output_corpus.txt")

# Every case: a name and the `ballagg run` arguments. Small enough to run in a second or two
# each in Release and a few seconds under the sanitizers.
RUNS = {
    "ed-2d-walls": ["--set", "system.n=400"],
    "ed-3d-periodic": ["--set", "system.dimension=3", "--set", "system.n=300", "--set", "system.boundary=periodic",
                       "--set", "initial.positions=random", "--set", "initial.velocities=gaussian",
                       "--set", "initial.zero_momentum=true"],
    "ed-2d-bounce": ["--set", "system.n=300", "--set", "collision.outcome=bounce", "--set", "collision.restitution=0.9",
                     "--set", "stop.time=20", "--set", "output.timeseries_interval=1"],
    "ed-naive-2d-periodic": ["--set", "engine.kind=ed-naive", "--set", "system.n=120",
                             "--set", "system.boundary=periodic"],
    "ed-naive-3d-walls": ["--set", "engine.kind=ed-naive", "--set", "system.dimension=3", "--set", "system.n=80"],
    "ts-rigid-2d": ["--set", "engine.kind=ts", "--set", "system.n=400", "--set", "system.volume_fraction=0.3",
                    "--set", "ts.dt_factor=0.01"],
    "ts-almost-rigid-2d": ["--set", "engine.kind=ts", "--set", "ts.model=almost-rigid", "--set", "system.n=200",
                           "--set", "ts.dt_factor=0.01"],
    "ts-non-rigid-2d": ["--set", "engine.kind=ts", "--set", "ts.model=non-rigid", "--set", "system.n=200",
                        "--set", "ts.dt_factor=0.01"],
    "ts-rigid-3d-periodic": ["--set", "engine.kind=ts", "--set", "system.dimension=3", "--set", "system.n=300",
                             "--set", "system.boundary=periodic", "--set", "initial.positions=random",
                             "--set", "ts.dt_factor=0.02"],
    "rigid-body-3d-bridges": ["--set", "engine.kind=rigid-body", "--set", "system.dimension=3",
                              "--set", "system.n=300", "--set", "system.box_length=10", "--set", "system.radius=0.1",
                              "--set", "system.boundary=periodic", "--set", "initial.positions=random",
                              "--set", "initial.velocities=gaussian", "--set", "initial.speed=10",
                              "--set", "initial.zero_momentum=true", "--set", "collision.outcome=energy-threshold",
                              "--set", "collision.restitution_law=bridges", "--set", "collision.velocity_unit=0.01",
                              "--set", "stop.time=5", "--set", "output.timeseries_interval=0.5"],
    "rigid-body-2d-spheres": ["--set", "engine.kind=rigid-body", "--set", "system.n=300",
                              "--set", "system.volume_fraction=0.05", "--set", "collision.coagulation=sphere",
                              "--set", "initial.velocities=gaussian", "--set", "stop.clusters=30"],
    "snapshots-xyz-h5md": ["--set", "system.n=200", "--set", "system.boundary=periodic",
                           "--set", "collision.outcome=bounce", "--set", "stop.time=10",
                           "--set", "output.snapshot_every=2", "--set", "output.snapshot_formats=[\"xyz\",\"h5md\"]"],
    "ed-2d-gas-long": ["--set", "system.n=1000", "--set", "collision.outcome=bounce", "--set", "stop.time=60",
                       "--set", "output.snapshot_every=5", "--set", "output.snapshot_formats=[\"xyz\"]",
                       "--set", "output.timeseries_interval=1"],
}

# Runs interrupted by SIGINT after a checkpoint and resumed: their files must be those of the
# uninterrupted run (the checkpoint contract), so their hashes are checked against that case.
RESUMED = {"ed-2d-gas-long-resumed": "ed-2d-gas-long"}

# Runs whose final state `analyze` and `verify` read.
ANALYZED = ["ed-2d-walls", "ed-3d-periodic", "rigid-body-2d-spheres"]

WALL_CLOCK_KEYS = ("wall_seconds", "events_per_second")


def digest(path, scratch):
    """The file's hash, with the scratch directory's path (which analysis.json and verify
    name) replaced by a fixed word."""
    with open(path, "rb") as f:
        data = f.read().replace(scratch.encode(), b"SCRATCH")
    if os.path.basename(path) == "summary.json":
        summary = json.loads(data)
        for key in WALL_CLOCK_KEYS:
            summary.pop(key, None)
        data = json.dumps(summary, sort_keys=True).encode()
    return hashlib.sha256(data).hexdigest()[:16]


def text_digest(text, scratch):
    return hashlib.sha256(text.replace(scratch, "SCRATCH").encode()).hexdigest()[:16]


def hash_dir(d, scratch):
    return {name: digest(os.path.join(d, name), scratch) for name in sorted(os.listdir(d))
            if os.path.isfile(os.path.join(d, name)) and not name.startswith(".")}


def run(binary, args, **kw):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    return subprocess.run([binary] + args, env=env, capture_output=True, text=True, **kw)


def resumed_run(binary, args, out):
    """Starts the run, interrupts it once a checkpoint could be written, and resumes it."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    p = subprocess.Popen([binary, "run", "-q", "--out", out, "--set", "output.checkpoint_every=0.01"] + args,
                         env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    checkpoint = os.path.join(out, "checkpoint.bin")
    deadline = time.monotonic() + 30
    while not os.path.exists(checkpoint) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    p.send_signal(signal.SIGINT)
    p.wait()
    if p.returncode == 0:
        return "finished before the signal"
    r = run(binary, ["run", "-q", "--resume", out])
    return None if r.returncode == 0 else f"resume failed: {r.stderr.strip()}"


def collect(binary, only, scratch):
    hashes, problems = {}, []

    def keep(case, d):
        for name, h in hash_dir(d, scratch).items():
            hashes[f"{case}/{name}"] = h

    for case, args in RUNS.items():
        if only and not re.search(only, case):
            continue
        out = os.path.join(scratch, case)
        r = run(binary, ["run", "-q", "--out", out] + args)
        if r.returncode != 0:
            problems.append(f"{case}: exit {r.returncode}: {r.stderr.strip()}")
            continue
        keep(case, out)
        if case in ANALYZED:
            a = run(binary, ["analyze", out, "--out", os.path.join(scratch, case + "-analysis")])
            if a.returncode != 0:
                problems.append(f"{case}: analyze exit {a.returncode}: {a.stderr.strip()}")
            else:
                keep(case + "-analysis", os.path.join(scratch, case + "-analysis"))
            v = run(binary, ["verify", out])
            hashes[f"{case}/verify.stdout"] = text_digest(v.stdout, scratch)
            hashes[f"{case}/verify.status"] = str(v.returncode)
    for case, base in RESUMED.items():
        if only and not re.search(only, case):
            continue
        out = os.path.join(scratch, case)
        problem = resumed_run(binary, RUNS[base], out)
        if problem:
            problems.append(f"{case}: {problem}")
            continue
        for name, h in hash_dir(out, scratch).items():
            hashes[f"{base}/{name}@resumed"] = h
    return hashes, problems


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binary")
    p.add_argument("--record", action="store_true", help="write the manifest instead of checking it")
    p.add_argument("--manifest", default=DEFAULT_MANIFEST)
    p.add_argument("--only", help="a regex on case names")
    p.add_argument("--keep", help="run in this directory and keep it")
    a = p.parse_args()
    scratch = a.keep or tempfile.mkdtemp(prefix="ballagg-corpus-")
    os.makedirs(scratch, exist_ok=True)
    try:
        hashes, problems = collect(a.binary, a.only, scratch)
    finally:
        if not a.keep:
            shutil.rmtree(scratch, ignore_errors=True)
    for line in problems:
        print(line, file=sys.stderr)
    if a.record:
        with open(a.manifest, "w") as f:
            f.write("# file hash: written by output_corpus.py --record; the bytes users get\n")
            for k in sorted(hashes):
                f.write(f"{k} {hashes[k]}\n")
        print(f"recorded {len(hashes)} hashes in {a.manifest}")
        return 1 if problems else 0
    expected = {}
    with open(a.manifest) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                k, h = line.split()
                expected[k] = h
    # A resumed run's files are the uninterrupted run's (the checkpoint contract).
    for k in list(hashes):
        if k.endswith("@resumed"):
            expected.setdefault(k, expected.get(k[: -len("@resumed")], "missing"))
    differ = [k for k in sorted(hashes) if expected.get(k) != hashes[k]]
    absent = [k for k in sorted(expected) if k not in hashes and not k.endswith("@resumed")
              and (not a.only or re.search(a.only, k.split("/")[0]))]
    for k in differ:
        print(f"changed: {k}: {expected.get(k, 'not in the manifest')} -> {hashes[k]}")
    for k in absent:
        print(f"missing: {k}")
    ok = not (differ or absent or problems)
    print(f"{len(hashes)} files, {len(differ)} changed, {len(absent)} missing" + ("" if ok else ": FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
