#!/usr/bin/python3
"""Reads trajectory.h5md back with h5py (Debian's python3-h5py), as a user would.

Runs ballagg (the binary given as the first argument) in a temporary directory, a 2D
periodic and a 3D walled run with snapshots, and checks that the file has the H5MD 1.1
layout, frames at t = 0, k * snapshot_every and the end, and that its last frame holds
exactly the positions, velocities and cluster ids of final.csv. Exit status 0 when every
check passes; prints one line per run.
"""
import csv
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np


def check(binary, workdir, name, dimension, boundary, every, n):
    out = os.path.join(workdir, name)
    subprocess.run([binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}",
                    "--set", f"system.n={n}", "--set", f"system.boundary={boundary}",
                    "--set", "initial.positions=random", "--set", f"output.snapshot_every={every}"],
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
        assert np.array_equal(position[-1], final_x), "last frame positions differ from final.csv"
        assert np.array_equal(f["particles/all/velocity/value"][-1], final_v)
        assert np.array_equal(f["particles/all/cluster/value"][-1], final_cluster)
        assert np.array_equal(f["particles/all/radius"][:], final_radius)
        edges = f["particles/all/box/edges"][:]
        assert edges.shape == (dimension,)
        if boundary == "periodic":
            # Unwrapped positions keep each cluster in one piece: no two spheres of one
            # cluster that touch are a box length apart.
            x = position[-1] + f["particles/all/image/value"][-1] * edges
            folded_d = position[-1][:, None, :] - position[-1][None, :, :]
            folded_d -= edges * np.round(folded_d / edges)
            touching = (np.linalg.norm(folded_d, axis=2) < 2 * final_radius.max() * (1 + 1e-9))
            touching &= final_cluster[:, None] == final_cluster[None, :]
            unwrapped_d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
            assert np.all(unwrapped_d[touching] < 2 * final_radius.max() * (1 + 1e-9))
        clusters = f["observables/clusters/value"][:]
        assert clusters.shape == (frames,) and clusters[0] == n and clusters[-1] == final_cluster.max() + 1
        config = f["parameters/config.toml"][()].decode()
        with open(os.path.join(out, "config.toml")) as g:
            assert config == g.read(), "parameters/config.toml differs from config.toml"
    print(f"{name}: {frames} frames of {n} spheres read back with h5py; the last equals final.csv")


def main():
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ballagg-h5py-") as workdir:
        check(binary, workdir, "2d-periodic", 2, "periodic", 2.0, 300)
        check(binary, workdir, "3d-walls", 3, "walls", 1.5, 200)


if __name__ == "__main__":
    main()
