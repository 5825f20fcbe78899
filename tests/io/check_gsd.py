#!/usr/bin/python3
"""Reads trajectory.gsd back with the gsd package (Debian's python3-gsd), as a HOOMD user would.

Runs ballagg (the binary given as the first argument) in a temporary directory, a 2D walled
and a 3D periodic run writing trajectory.gsd and trajectory.xyz, and opens the GSD file
with gsd.hoomd.open (whose file layer, the gsd C code, checks the header, the name list
and the index). Checks per frame against trajectory.xyz (shortest round-trip doubles):

* configuration: dimensions = D, box [L, L, L (2D: 0), 0, 0, 0], step;
* particles: N, positions = the XYZ positions - L/2 (HOOMD's box is centred on the origin)
  rounded to float32, velocities rounded to float32, z = 0 in 2D, diameters = 2 radius,
  masses (final.csv), body = the cluster ids, images (periodic: unwrapped positions put
  each cluster in one piece, as trajectory.h5md's do);
* log: time (float64, the XYZ frame's Time exactly), clusters.

Also: a run interrupted by SIGINT (which writes a checkpoint) and resumed writes the same
trajectory.gsd, byte for byte, as the uninterrupted run. That part needs no gsd package
and runs first. Exit status 0 when every check passes, 77 (reported by ctest as skipped)
when the gsd package is not installed; prints one line per run.
"""
import csv
import filecmp
import os
import signal
import subprocess
import sys
import tempfile
import time

CHECKPOINT_WAIT_SECONDS = 30  # at most this long for the first checkpoint of the interrupted run


def run_args(binary, out, dimension, boundary, n, every, formats):
    return [binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}", "--set", f"system.n={n}",
            "--set", f"system.boundary={boundary}", "--set", "initial.positions=random",
            "--set", "collision.outcome=bounce", "--set", "stop.time=40",
            "--set", f"output.snapshot_every={every}",
            "--set", "output.snapshot_formats=[" + ", ".join(f'"{f}"' for f in formats) + "]"]


def check_resume(binary, workdir):
    """SIGINT after the first checkpoint, --resume: trajectory.gsd as the uninterrupted run's."""
    reference, interrupted = os.path.join(workdir, "reference"), os.path.join(workdir, "interrupted")
    args = lambda out: run_args(binary, out, 2, "periodic", 2000, 1.0, ["gsd"])  # noqa: E731
    subprocess.run(args(reference), check=True, stdout=subprocess.DEVNULL)
    p = subprocess.Popen(args(interrupted) + ["--set", "output.checkpoint_every=0.01"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    checkpoint = os.path.join(interrupted, "checkpoint.bin")
    deadline = time.monotonic() + CHECKPOINT_WAIT_SECONDS
    while not os.path.exists(checkpoint) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.002)
    p.send_signal(signal.SIGINT)
    p.wait()
    assert p.returncode != 0, "the run finished before it was interrupted: make it longer"
    assert not os.path.exists(os.path.join(interrupted, "trajectory.gsd"))
    subprocess.run([binary, "run", "-q", "--resume", interrupted], check=True, stdout=subprocess.DEVNULL)
    a, b = os.path.join(reference, "trajectory.gsd"), os.path.join(interrupted, "trajectory.gsd")
    assert filecmp.cmp(a, b, shallow=False), "the resumed run's trajectory.gsd differs from the uninterrupted run's"
    print(f"resumed run: trajectory.gsd ({os.path.getsize(a)} bytes) is the uninterrupted run's, byte for byte")


try:
    import gsd.hoomd
    import numpy as np
except ImportError as e:
    gsd = None
    missing = e.name


def read_xyz_frames(path):
    """(time, positions [N][3], velocities [N][3], cluster [N]) of every frame of trajectory.xyz."""
    frames = []
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                return frames
            n = int(line)
            comment = f.readline()
            t = float(comment.split("Time=")[1].split()[0])
            rows = [f.readline().split() for _ in range(n)]
            x = np.array([[float(v) for v in r[1:4]] for r in rows])
            v = np.array([[float(v) for v in r[4:7]] for r in rows])
            cluster = np.array([int(r[8]) for r in rows])
            frames.append((t, x, v, cluster))


def check(binary, workdir, name, dimension, boundary, n, every):
    out = os.path.join(workdir, name)
    subprocess.run(run_args(binary, out, dimension, boundary, n, every, ["gsd", "xyz"]), check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "final.csv")) as f:
        rows = list(csv.DictReader(f))
    radius = np.array([float(r["radius"]) for r in rows])
    mass = np.array([float(r["mass"]) for r in rows])
    xyz = read_xyz_frames(os.path.join(out, "trajectory.xyz"))
    with open(os.path.join(out, "summary.json")) as f:
        import json
        length = json.load(f)["box_length"]
    periodic = boundary == "periodic"
    with gsd.hoomd.open(os.path.join(out, "trajectory.gsd"), "rb") as trajectory:
        assert len(trajectory) == len(xyz), (len(trajectory), len(xyz))
        steps = []
        for k, frame in enumerate(trajectory):
            t, x, v, cluster = xyz[k]
            c = frame.configuration
            assert c.dimensions == dimension, c.dimensions
            box = [length, length, length if dimension == 3 else 0.0, 0, 0, 0]
            assert np.array_equal(c.box, np.array(box, dtype=np.float32)), c.box
            steps.append(int(c.step))
            p = frame.particles
            assert p.N == n and p.types == ["S"] and not np.any(p.typeid)
            centred = x - length / 2
            centred[:, dimension:] = 0.0
            assert p.position.dtype == np.float32 and np.array_equal(p.position, centred.astype(np.float32)), k
            assert np.array_equal(p.velocity, v.astype(np.float32)), f"frame {k}: velocities"
            assert np.array_equal(p.diameter, (2 * radius).astype(np.float32))
            assert np.array_equal(p.mass, mass.astype(np.float32))
            assert p.body.dtype == np.int32 and np.array_equal(p.body, cluster), f"frame {k}: cluster ids"
            assert frame.log["time"].dtype == np.float64 and frame.log["time"][0] == t, (k, frame.log["time"], t)
            assert frame.log["clusters"][0] == len(set(cluster))
            if periodic:
                # Unwrapped, every pair of touching spheres of one cluster is within a contact.
                unwrapped = p.position.astype(np.float64) + p.image * np.array(box[:3])
                d = np.linalg.norm(unwrapped[:, None, :] - unwrapped[None, :, :], axis=2)
                same = cluster[:, None] == cluster[None, :]
                folded = p.position[:, None, :].astype(np.float64) - p.position[None, :, :]
                folded[..., :dimension] -= length * np.round(folded[..., :dimension] / length)
                touching = same & (np.linalg.norm(folded, axis=2) < 2 * radius.max() * (1 + 1e-5))
                assert np.all(d[touching] < 2 * radius.max() * (1 + 1e-5)), f"frame {k}: a cluster is cut by a face"
            elif dimension == 2:
                assert not np.any(p.image)
        assert steps == sorted(steps)
    print(f"{name}: {len(xyz)} frames of {n} spheres read back with gsd {gsd.__version__}: trajectory.xyz's")


def main():
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ballagg-gsd-") as workdir:
        check_resume(binary, workdir)
        if gsd is None:
            print(f"skipped the gsd round trip: {missing} is not installed (apt-get install python3-gsd)")
            sys.exit(77)
        check(binary, workdir, "2d-walls", 2, "walls", 150, 5.0)
        check(binary, workdir, "3d-periodic", 3, "periodic", 150, 5.0)


if __name__ == "__main__":
    main()
