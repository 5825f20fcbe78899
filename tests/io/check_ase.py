#!/usr/bin/python3
"""Reads final.xyz and trajectory.xyz back with ASE (Debian's python3-ase), as a user would.

Runs ballagg (the binary given as the first argument) in a temporary directory, a 2D
walled and a 3D periodic run with extended-XYZ snapshots, and reads both files with
ase.io.read in the "extxyz" format (a file ASE cannot parse fails the test). Checks that

* the cell is the box (2D: a third vector one largest diameter deep), Origin is 0 and the
  pbc flags are the boundary's (2D: z is never periodic);
* the columns come through as ASE arrays with the right values: positions (2D: z = 0),
  `velo` (2D: vz = 0), `radius`, `cluster` (integers), all equal to final.csv exactly
  (both files print shortest round-trip doubles, so what is read is the same double);
* trajectory.xyz has frames at t = 0, k * snapshot_every and the end (summary.json's time),
  read from each frame's `Time`, and its last frame is final.xyz;
* when the run also writes trajectory.h5md, every frame of trajectory.xyz holds the same
  time, positions, velocities and cluster ids as that frame of trajectory.h5md (whose
  positions and velocities are, in single precision, the XYZ file's rounded to float32).

Exit status 0 when every check passes; prints one line per run.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

try:
    import ase.io
    import numpy as np
except ImportError as missing:  # an optional reader: reported by ctest as skipped (exit 77)
    print(f"check_ase: skipped: {missing} (scripts/setup installs python3-ase)")
    sys.exit(77)


def run(binary, out, dimension, boundary, every, n, formats):
    subprocess.run([binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}",
                    "--set", f"system.n={n}", "--set", f"system.boundary={boundary}",
                    "--set", "initial.positions=random", "--set", f"output.snapshot_every={every}",
                    "--set", "output.snapshot_formats=[" + ", ".join(f'"{f}"' for f in formats) + "]"],
                   check=True, stdout=subprocess.DEVNULL)


def read_final_csv(path, dimension):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    axes = "xyz"[:dimension]
    n = len(rows)
    x = np.zeros((n, 3))
    v = np.zeros((n, 3))
    x[:, :dimension] = [[float(r[a]) for a in axes] for r in rows]
    v[:, :dimension] = [[float(r["v" + a]) for a in axes] for r in rows]
    radius = np.array([float(r["radius"]) for r in rows])
    cluster = np.array([int(r["cluster"]) for r in rows])
    return x, v, radius, cluster


def check_frame(atoms, what, n, box, dimension, periodic, radius):
    """The parts of one frame that every frame shares: size, cell, pbc, columns."""
    assert len(atoms) == n, f"{what}: {len(atoms)} atoms, expected {n}"
    for array in ("velo", "radius", "cluster"):
        assert array in atoms.arrays, f"{what}: ASE did not read the column {array!r}: {list(atoms.arrays)}"
    assert atoms.arrays["velo"].shape == (n, 3), atoms.arrays["velo"].shape
    assert np.issubdtype(atoms.arrays["cluster"].dtype, np.integer), atoms.arrays["cluster"].dtype
    assert np.issubdtype(atoms.arrays["radius"].dtype, np.floating), atoms.arrays["radius"].dtype
    depth = box if dimension == 3 else 2 * radius.max()
    assert np.array_equal(atoms.cell.array, np.diag([box, box, depth])), f"{what}: cell {atoms.cell.array}"
    expected_pbc = [periodic, periodic, periodic and dimension == 3]
    assert list(atoms.pbc) == expected_pbc, f"{what}: pbc {atoms.pbc}, expected {expected_pbc}"
    assert np.array_equal(atoms.info["Origin"], [0, 0, 0]), f"{what}: Origin {atoms.info.get('Origin')}"
    assert set(atoms.get_chemical_symbols()) == {"S"}
    assert np.array_equal(atoms.arrays["radius"], radius), f"{what}: radii differ"
    x = atoms.get_positions()
    if dimension == 2:
        assert np.all(x[:, 2] == 0) and np.all(atoms.arrays["velo"][:, 2] == 0), f"{what}: 2D z != 0"
    # Positions are folded into the box (walls: the sphere inside it).
    assert np.all(x[:, :dimension] >= 0) and np.all(x[:, :dimension] < box), f"{what}: outside the box"
    # Cluster ids are 0, 1, ... in order of each cluster's first sphere.
    cluster = atoms.arrays["cluster"]
    _, first = np.unique(cluster, return_index=True)
    assert np.array_equal(cluster[np.sort(first)], np.arange(len(first))), f"{what}: cluster ids"


def check(binary, workdir, name, dimension, boundary, every, n, formats):
    out = os.path.join(workdir, name)
    run(binary, out, dimension, boundary, every, n, formats)
    periodic = boundary == "periodic"
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    box, t_end = summary["box_length"], summary["time"]
    final_x, final_v, radius, final_cluster = read_final_csv(os.path.join(out, "final.csv"), dimension)

    final = ase.io.read(os.path.join(out, "final.xyz"), format="extxyz")
    check_frame(final, "final.xyz", n, box, dimension, periodic, radius)
    assert np.array_equal(final.get_positions(), final_x), "final.xyz positions differ from final.csv"
    assert np.array_equal(final.arrays["velo"], final_v), "final.xyz velocities differ from final.csv"
    assert np.array_equal(final.arrays["cluster"], final_cluster), "final.xyz cluster ids differ from final.csv"
    assert final.info["Time"] == t_end, (final.info["Time"], t_end)

    frames = ase.io.read(os.path.join(out, "trajectory.xyz"), index=":", format="extxyz")
    assert len(frames) >= 3, f"only {len(frames)} frames"
    for k, atoms in enumerate(frames):
        check_frame(atoms, f"trajectory.xyz frame {k}", n, box, dimension, periodic, radius)
    time = np.array([atoms.info["Time"] for atoms in frames], dtype=float)
    # Frames at 0, every, 2 every, ... (no multiple before the end left out), then the end.
    assert np.array_equal(time[:-1], every * np.arange(len(frames) - 1)), time
    assert time[-1] == t_end and time[-2] <= t_end <= every * (len(frames) - 1), (time[-2:], t_end)
    assert frames[0].arrays["cluster"].max() == n - 1, "frame 0 is not every sphere on its own"
    last = frames[-1]
    assert np.array_equal(last.get_positions(), final.get_positions()), "last frame positions != final.xyz"
    assert np.array_equal(last.arrays["velo"], final.arrays["velo"]), "last frame velocities != final.xyz"
    assert np.array_equal(last.arrays["cluster"], final.arrays["cluster"]), "last frame clusters != final.xyz"
    assert last.info["Time"] == final.info["Time"] and set(last.info) == set(final.info), (last.info, final.info)
    with open(os.path.join(out, "final.xyz")) as f, open(os.path.join(out, "trajectory.xyz")) as g:
        assert g.read().endswith(f.read()), "trajectory.xyz does not end with the text of final.xyz"

    compared = ""
    if "h5md" in formats:
        import h5py
        with h5py.File(os.path.join(out, "trajectory.h5md"), "r") as f:
            assert np.array_equal(f["particles/all/position/time"][:], time), "frame times differ from H5MD"
            position = f["particles/all/position/value"][:]
            velocity = f["particles/all/velocity/value"][:]
            cluster = f["particles/all/cluster/value"][:]
        assert position.shape[0] == len(frames)
        stored = position.dtype  # float32: output.snapshot_precision = "single" (the default)
        assert stored in (np.float32, np.float64) and velocity.dtype == stored, (stored, velocity.dtype)
        for k, atoms in enumerate(frames):
            x, v = atoms.get_positions()[:, :dimension], atoms.arrays["velo"][:, :dimension]
            assert np.array_equal(x.astype(stored), position[k]), f"frame {k} positions"
            assert np.array_equal(v.astype(stored), velocity[k]), f"frame {k} velocities"
            assert np.array_equal(atoms.arrays["cluster"], cluster[k]), f"frame {k} cluster ids"
        compared = ", every frame equal to trajectory.h5md's"
    print(f"{name}: final.xyz and {len(frames)} frames of {n} spheres (t = 0 ... {t_end:.6g}) read back "
          f"with ASE {ase.__version__}; the last equals final.xyz and final.csv{compared}")


def main():
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ballagg-ase-") as workdir:
        check(binary, workdir, "2d-walls", 2, "walls", 2.0, 300, ["xyz"])
        check(binary, workdir, "3d-periodic", 3, "periodic", 0.25, 300, ["h5md", "xyz"])


if __name__ == "__main__":
    main()
