#!/usr/bin/python3
"""Reads trajectory.h5md back with h5py (Debian's python3-h5py), as a user would.

Runs ballagg (the binary given as the first argument) in a temporary directory, a 2D
periodic and a 3D walled run with snapshots, each in both output.snapshot_precision, and
checks that the file has the H5MD 1.1 layout, frames at t = 0, k * snapshot_every and the
end, and that its last frame holds the positions, velocities and cluster ids of final.csv:
exactly in double precision; in single precision (float32, the default) within
FLOAT32_RELATIVE_ERROR of them, and equal to them rounded to float32. Exit status 0 when
every check passes; prints one line per run.
"""
import csv
import os
import subprocess
import sys
import tempfile

try:
    import h5py
    import numpy as np
except ImportError as missing:  # an optional reader: reported by ctest as skipped (exit 77)
    print(f"check_h5md: skipped: {missing} (scripts/setup installs python3-h5py)")
    sys.exit(77)

# Single precision: each stored position and velocity is final.csv's double rounded to the
# nearest float32, so it differs from it by at most half a unit in the last place of a
# float32, 2^-24 of its magnitude (24-bit significand; no value here is subnormal).
FLOAT32_RELATIVE_ERROR = 2.0 ** -24


def expect_stored(stored, exact, precision, what):
    """The stored values of a frame against final.csv's doubles `exact`."""
    if precision == "double":
        assert stored.dtype == np.float64, (what, stored.dtype)
        assert np.array_equal(stored, exact), f"last frame {what} differ from final.csv"
        return
    assert stored.dtype == np.float32, (what, stored.dtype)
    error = np.abs(stored.astype(np.float64) - exact)
    assert np.all(error <= FLOAT32_RELATIVE_ERROR * np.abs(exact)), \
        f"last frame {what}: relative error {np.max(error / np.maximum(np.abs(exact), 1e-300)):.3g} beyond float32's"
    assert np.array_equal(stored, exact.astype(np.float32)), f"last frame {what}: not final.csv rounded to float32"


def check(binary, workdir, name, dimension, boundary, every, n, precision):
    out = os.path.join(workdir, f"{name}-{precision}")
    subprocess.run([binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}",
                    "--set", f"system.n={n}", "--set", f"system.boundary={boundary}",
                    "--set", "initial.positions=random", "--set", f"output.snapshot_every={every}",
                    "--set", f"output.snapshot_precision={precision}"],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "final.csv")) as f:
        rows = list(csv.DictReader(f))
    axes = "xyz"[:dimension]
    final_x = np.array([[float(r[a]) for a in axes] for r in rows])
    final_v = np.array([[float(r["v" + a]) for a in axes] for r in rows])
    final_cluster = np.array([int(r["cluster"]) for r in rows])
    final_radius = np.array([float(r["radius"]) for r in rows])

    with h5py.File(os.path.join(out, "trajectory.h5md"), "r") as f:
        assert list(f["h5md"].attrs["version"]) == [1, 1]
        assert f["h5md/creator"].attrs["name"] == b"ballagg"
        assert "name" in f["h5md/author"].attrs
        box = f["particles/all/box"]
        assert box.attrs["dimension"] == dimension
        expected_boundary = b"periodic" if boundary == "periodic" else b"none"
        assert list(box.attrs["boundary"]) == [expected_boundary] * dimension
        position = f["particles/all/position/value"]
        frames = position.shape[0]
        assert position.shape == (frames, n, dimension), position.shape
        time = f["particles/all/position/time"][:]
        step = f["particles/all/position/step"][:]
        assert time.shape == (frames,) and step.shape == (frames,)
        assert np.array_equal(time[:-1], every * np.arange(frames - 1)), time
        assert np.all(np.diff(step) >= 0)
        for element in ("velocity", "cluster") + (("image",) if boundary == "periodic" else ()):
            group = f["particles/all/" + element]
            assert np.array_equal(group["time"][:], time), element  # shared with position
            assert group["value"].shape[0] == frames, element
        expect_stored(position[-1], final_x, precision, "positions")
        expect_stored(f["particles/all/velocity/value"][-1], final_v, precision, "velocities")
        assert np.array_equal(f["particles/all/cluster/value"][-1], final_cluster)
        assert np.array_equal(f["particles/all/radius"][:], final_radius)
        if dimension == 2:
            edges = f["particles/all/box/edges"][:]
        else:  # the 3D layout: the box per frame, a matrix of edge vectors
            edges = f["particles/all/box/edges/value"][-1].diagonal()
        assert edges.shape == (dimension,)
        if boundary == "periodic":
            # Unwrapped positions keep each cluster in one piece: no two spheres of one
            # cluster that touch are a box length apart. In single precision a distance
            # is off by up to 2 sqrt(D) times a position's rounding error.
            folded = position[-1].astype(np.float64)
            slack = 1e-9 * 2 * final_radius.max()
            if precision == "single":
                slack += 2 * np.sqrt(dimension) * FLOAT32_RELATIVE_ERROR * edges.max()
            x = folded + f["particles/all/image/value"][-1] * edges
            folded_d = folded[:, None, :] - folded[None, :, :]
            folded_d -= edges * np.round(folded_d / edges)
            touching = (np.linalg.norm(folded_d, axis=2) < 2 * final_radius.max() + slack)
            touching &= final_cluster[:, None] == final_cluster[None, :]
            unwrapped_d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
            assert np.all(unwrapped_d[touching] < 2 * final_radius.max() + slack)
        clusters = f["observables/clusters/value"][:]
        assert clusters.shape == (frames,) and clusters[0] == n and clusters[-1] == final_cluster.max() + 1
        config = f["parameters/config.toml"][()].decode()
        with open(os.path.join(out, "config.toml")) as g:
            assert config == g.read(), "parameters/config.toml differs from config.toml"
    same = "equals final.csv" if precision == "double" else "is final.csv rounded to float32"
    print(f"{name}, {precision} precision: {frames} frames of {n} spheres read back with h5py; the last {same}")


def main():
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ballagg-h5py-") as workdir:
        for precision in ("single", "double"):
            check(binary, workdir, "2d-periodic", 2, "periodic", 2.0, 300, precision)
            check(binary, workdir, "3d-walls", 3, "walls", 1.5, 200, precision)


if __name__ == "__main__":
    main()
