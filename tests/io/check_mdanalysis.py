#!/usr/bin/python3
"""Reads trajectory.h5md with MDAnalysis (Debian's python3-mdanalysis) and h5py, as a user would.

Runs ballagg (the binary given as the first argument) in a temporary directory: a 3D
periodic run, a 2D walled run with output.h5md_pad_3d = true, and a 2D periodic run
without it. Checks that

* MDAnalysis opens the 3D and the padded 2D file with its defaults (convert_units=True;
  the atoms from final.xyz: Universe("final.xyz", "trajectory.h5md"), and without a
  topology, into Universe.empty(N, trajectory=True) with load_new):
  per frame, its positions, box and time are ballagg's (the file read with h5py; the last
  frame's positions those of final.csv rounded to float32, as stored), unconverted: the
  unit attributes name MDAnalysis's own base units (Angstrom, ps);
* with h5py: the 3D layout's box is per frame (box/edges with step, time and value
  [F][3][3], hard links to position's step and time), its unit attributes are variable-length
  strings, and a padded 2D file has z = 0 everywhere, a box one largest diameter deep in z
  that is not periodic, and parameters' attribute dimension = 2;
* the 2D file without padding keeps the 2D layout (MDAnalysis refuses it: 2D boxes).

Exit status 0 when every check passes, 77 (reported by ctest as skipped) when MDAnalysis
or h5py is not installed; prints one line per run.
"""
import csv
import os
import subprocess
import sys
import tempfile
import warnings

try:
    import h5py
    import numpy as np
    # MDAnalysis 2.4 uses modules Python 3.11 deprecates (xdrlib): not ours to report.
    warnings.filterwarnings("ignore", category=DeprecationWarning)
    import MDAnalysis
    import MDAnalysis.coordinates.H5MD
except ImportError as e:
    print(f"skipped: {e.name} is not installed (apt-get install python3-mdanalysis python3-h5py)")
    sys.exit(77)


def run(binary, out, dimension, boundary, n, every, sets=()):
    args = [binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}", "--set", f"system.n={n}",
            "--set", f"system.boundary={boundary}", "--set", "initial.positions=random",
            "--set", f"output.snapshot_every={every}"]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def final_csv(out, dimension):
    with open(os.path.join(out, "final.csv")) as f:
        rows = list(csv.DictReader(f))
    x = np.zeros((len(rows), 3))
    x[:, :dimension] = [[float(r[a]) for a in "xyz"[:dimension]] for r in rows]
    radius = np.array([float(r["radius"]) for r in rows])
    return x, radius


def position_frames(f):
    return f["particles/all/position/value"].shape[0]


def check_layout_3d(f, dimension, periodic, length, largest_radius):
    """h5py: the 3D layout of a 3D run or of a padded 2D one."""
    box = f["particles/all/box"]
    assert box.attrs["dimension"] == 3, box.attrs["dimension"]
    boundary = [b.decode() for b in box.attrs["boundary"]]
    expected = ["periodic" if periodic else "none"] * dimension + ["none"] * (3 - dimension)
    assert boundary == expected, boundary
    edges = box["edges/value"]
    frames = f["particles/all/position/value"].shape[0]
    assert edges.shape == (frames, 3, 3), edges.shape
    depth = length if dimension == 3 else 2 * largest_radius
    assert np.array_equal(edges[0], np.diag([length, length, depth])), edges[0]
    assert np.array_equal(edges[:], np.broadcast_to(edges[0], edges.shape))
    # step and time: the same datasets as position's (hard links).
    for name in ("step", "time"):
        assert box["edges/" + name].id == f["particles/all/position/" + name].id, name
    units = {"particles/all/position/value": "Angstrom", "particles/all/position/time": "ps",
             "particles/all/velocity/value": "Angstrom ps-1", "particles/all/box/edges/value": "Angstrom"}
    for path, unit in units.items():
        assert f[path].attrs["unit"] == unit, (path, f[path].attrs["unit"])  # a str: variable-length
    if dimension == 2:
        assert f["parameters"].attrs["dimension"] == 2
        for path in ("position", "velocity") + (("image",) if periodic else ()):
            assert not np.any(f[f"particles/all/{path}/value"][:, :, 2]), path


def check_mdanalysis(topology, path, f):
    """MDAnalysis reads every frame as the file holds it (h5py), units unconverted. The
    topology (the atoms) comes from final.xyz: MDAnalysis 2.4 guesses one from an H5MD file
    only if its particle group is named "trajectory" (its own writer's name), whereas its
    trajectory reader takes the first group, ballagg's "all"."""
    u = MDAnalysis.Universe(topology, path)  # default convert_units=True: the units must be readable
    reader = MDAnalysis.coordinates.H5MD.H5MDReader(path)
    assert reader.n_frames == position_frames(f) and reader.units == {
        "time": "ps", "length": "Angstrom", "velocity": "Angstrom/ps", "force": None}, reader.units
    position = f["particles/all/position/value"]
    time = f["particles/all/position/time"][:]
    edges = f["particles/all/box/edges/value"]
    assert len(u.trajectory) == position.shape[0] and u.atoms.n_atoms == position.shape[1]
    for k, ts in enumerate(u.trajectory):
        assert ts.time == time[k], (k, ts.time, time[k])
        assert np.array_equal(ts.positions, position[k]), f"frame {k}: positions"
        expected_box = np.concatenate([np.diag(edges[k]), [90.0, 90.0, 90.0]]).astype(np.float32)
        assert np.array_equal(ts.dimensions, expected_box), (k, ts.dimensions)
        assert np.array_equal(ts.velocities, f["particles/all/velocity/value"][k]), f"frame {k}: velocities"
    return len(u.trajectory)


def check_without_topology(path, f):
    """Without final.xyz: an empty Universe of the file's N atoms, the trajectory loaded
    into it, gives the same frames."""
    position = f["particles/all/position/value"]
    u = MDAnalysis.Universe.empty(position.shape[1], trajectory=True)
    u.load_new(path, format="H5MD")
    assert len(u.trajectory) == position.shape[0]
    for k, ts in enumerate(u.trajectory):
        assert np.array_equal(ts.positions, position[k]), f"frame {k}: positions (no topology)"
        assert ts.time == f["particles/all/position/time"][k]


def check(binary, workdir, name, dimension, boundary, n, every, pad):
    out = os.path.join(workdir, name)
    run(binary, out, dimension, boundary, n, every, ["output.h5md_pad_3d=true"] if pad else [])
    final_x, radius = final_csv(out, dimension)
    path = os.path.join(out, "trajectory.h5md")
    with h5py.File(path, "r") as f:
        length = float(f["particles/all/box/edges/value"][0, 0, 0])
        check_layout_3d(f, dimension, boundary == "periodic", length, radius.max())
        last = f["particles/all/position/value"][-1]
        assert np.array_equal(last, final_x.astype(np.float32)), "last frame: not final.csv rounded to float32"
        frames = check_mdanalysis(os.path.join(out, "final.xyz"), path, f)
        check_without_topology(path, f)
    print(f"{name}: {frames} frames of {n} spheres read by MDAnalysis {MDAnalysis.__version__} as ballagg wrote them")


def check_plain_2d(binary, workdir):
    out = os.path.join(workdir, "2d-plain")
    run(binary, out, 2, "periodic", 100, 5.0)
    path = os.path.join(out, "trajectory.h5md")
    with h5py.File(path, "r") as f:
        assert f["particles/all/box"].attrs["dimension"] == 2
        assert f["particles/all/box/edges"].shape == (2,)
        assert f["particles/all/position/value"].shape[2] == 2
        assert "unit" not in f["particles/all/position/value"].attrs
    try:
        MDAnalysis.coordinates.H5MD.H5MDReader(path)
    except ValueError as e:
        assert "3-dimensional" in str(e), e
    else:
        raise AssertionError("MDAnalysis read a 2D box")
    print("2d-plain: the 2D layout (output.h5md_pad_3d = false), which MDAnalysis refuses")


def main():
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ballagg-mda-") as workdir:
        check(binary, workdir, "3d-periodic", 3, "periodic", 200, 0.2, pad=False)
        check(binary, workdir, "2d-walls-padded", 2, "walls", 200, 2.0, pad=True)
        check(binary, workdir, "2d-periodic-padded", 2, "periodic", 200, 2.0, pad=True)
        check_plain_2d(binary, workdir)


if __name__ == "__main__":
    main()
