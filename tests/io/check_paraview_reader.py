#!/usr/bin/python3
"""Tests the h5py part of the ParaView trajectory reader (examples/paraview/ballagg_h5md.py)
without ParaView, with Debian's /usr/bin/python3, python3-h5py and python3-numpy.

Runs ballagg (the binary given as the first argument) in a temporary directory, a 2D
periodic run with H5MD snapshots in single and in double precision and a 3D walled one in
single precision, imports ballagg_h5md with ParaView and
VTK made unimportable (the module must not need them), and checks that

* read_times gives the frames' times: 0, k * snapshot_every, and the end (summary.json);
* read_box gives the dimension, the edges (the box length) and the boundary;
* read_frame(-1) holds exactly final.csv's positions, velocities, radii, masses and cluster
  ids (2D padded with z = 0; positions and velocities rounded to float32 when the file
  stores single precision, output.snapshot_precision), as float64 arrays, the periodic
  images (None with walls), and with unwrap=True position + image * edges; read_frame(0)
  has every sphere in a cluster of its own; every frame equals trajectory.h5md read with
  h5py directly; a frame out of range is an IndexError;
* frame_index picks the last frame at or before a time (ParaView's time steps are the
  frames' times exactly; between two, the earlier frame; outside, the first or last).

fill_polydata (the VTK part) is tested by tests/io/check_paraview.py, under pvpython.
Exit status 0 when every check passes; prints one line per run.
"""
import csv
import importlib.abc
import json
import os
import subprocess
import sys
import tempfile

try:
    import h5py
    import numpy as np
except ImportError as missing:  # an optional reader: reported by ctest as skipped (exit 77)
    print(f"check_paraview_reader: skipped: {missing} (scripts/setup installs python3-h5py)")
    sys.exit(77)

READER_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "paraview")


class _NoParaView(importlib.abc.MetaPathFinder):
    """Makes paraview and VTK unimportable, as on a machine without ParaView."""

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("paraview", "vtkmodules", "vtk"):
            raise ImportError(f"{name} blocked: ballagg_h5md must read without ParaView")
        return None


def import_reader():
    sys.meta_path.insert(0, _NoParaView())
    sys.path.insert(0, os.path.abspath(READER_DIR))
    import ballagg_h5md
    assert not any(m.split(".")[0] in ("paraview", "vtkmodules", "vtk") for m in sys.modules)
    return ballagg_h5md


def pad3(a):
    out = np.zeros((a.shape[0], 3), dtype=a.dtype)
    out[:, : a.shape[1]] = a
    return out


def check(reader, binary, workdir, name, dimension, boundary, every, n, precision):
    out = os.path.join(workdir, f"{name}-{precision}")
    subprocess.run([binary, "run", "-q", "--out", out, "--set", f"system.dimension={dimension}",
                    "--set", f"system.n={n}", "--set", f"system.boundary={boundary}",
                    "--set", "initial.positions=random", "--set", f"output.snapshot_every={every}",
                    "--set", f"output.snapshot_precision={precision}"],
                   check=True, stdout=subprocess.DEVNULL)
    # What the file stores of final.csv's doubles: themselves, or their float32 rounding.
    stored = (lambda x: x) if precision == "double" else (lambda x: x.astype(np.float32).astype(np.float64))
    periodic = boundary == "periodic"
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "final.csv")) as f:
        rows = list(csv.DictReader(f))
    axes = "xyz"[:dimension]
    final_x = stored(pad3(np.array([[float(r[a]) for a in axes] for r in rows])))
    final_v = stored(pad3(np.array([[float(r["v" + a]) for a in axes] for r in rows])))
    final_radius = np.array([float(r["radius"]) for r in rows])
    final_mass = np.array([float(r["mass"]) for r in rows])
    final_cluster = np.array([int(r["cluster"]) for r in rows])
    path = os.path.join(out, "trajectory.h5md")

    times = reader.read_times(path)
    frames = len(times)
    assert times.dtype == np.float64 and frames >= 3, (times.dtype, frames)
    assert np.array_equal(times[:-1], every * np.arange(frames - 1)), times
    assert times[-1] == summary["time"], (times[-1], summary["time"])

    d, edges, is_periodic = reader.read_box(path)
    assert d == dimension and is_periodic == periodic, (d, is_periodic)
    assert np.array_equal(edges, [summary["box_length"]] * dimension), edges

    last = reader.read_frame(path, -1)
    assert last["time"] == times[-1] and last["dimension"] == dimension and last["periodic"] == periodic
    assert last["points"].shape == (n, 3) and last["points"].dtype == np.float64
    assert np.array_equal(last["points"], final_x), "last frame positions differ from final.csv"
    assert np.array_equal(last["velocity"], final_v), "last frame velocities differ from final.csv"
    assert np.array_equal(last["radius"], final_radius) and np.array_equal(last["mass"], final_mass)
    assert last["cluster"].dtype == np.int32 and np.array_equal(last["cluster"], final_cluster)
    assert np.array_equal(reader.read_frame(path, frames - 1)["points"], last["points"])
    if periodic:
        assert last["image"].shape == (n, 3) and last["image"].dtype == np.int32
        assert dimension == 3 or np.all(last["image"][:, 2] == 0)
        unwrapped = reader.read_frame(path, -1, unwrap=True)["points"]
        assert np.array_equal(unwrapped, final_x + last["image"] * pad3(edges[None, :])[0])
        assert np.any(last["image"] != 0), "no sphere crossed a face: the unwrap check is empty"
    else:
        assert last["image"] is None
        assert np.array_equal(reader.read_frame(path, -1, unwrap=True)["points"], final_x)

    first = reader.read_frame(path, 0)
    assert first["time"] == 0 and np.array_equal(first["cluster"], np.arange(n)), "frame 0"
    with h5py.File(path, "r") as f:
        g = f["particles/all"]
        for k in range(frames):
            frame = reader.read_frame(f, k)  # an open file works too
            assert frame["time"] == g["position/time"][k] and frame["step"] == g["position/step"][k]
            assert np.array_equal(frame["points"], pad3(g["position/value"][k])), f"frame {k}"
            assert np.array_equal(frame["velocity"], pad3(g["velocity/value"][k])), f"frame {k}"
            assert np.array_equal(frame["cluster"], g["cluster/value"][k]), f"frame {k}"
        assert f.id.valid, "read_frame closed a file it was given"
    for k in (frames, -frames - 1):
        try:
            reader.read_frame(path, k)
        except IndexError:
            pass
        else:
            raise AssertionError(f"read_frame({k}) of {frames} frames did not raise IndexError")

    for k in range(frames):
        assert reader.frame_index(times, times[k]) == k, k
        if k + 1 < frames:
            assert reader.frame_index(times, (times[k] + times[k + 1]) / 2) == k, k
    assert reader.frame_index(times, -1.0) == 0
    assert reader.frame_index(times, times[-1] + 1.0) == frames - 1
    try:
        reader.frame_index([], 0.0)
    except ValueError:
        pass
    else:
        raise AssertionError("frame_index of no frame did not raise ValueError")
    print(f"{name}, {precision} precision: {frames} frames of {n} spheres read by ballagg_h5md without ParaView; "
          f"the last equals final.csv" + ("" if precision == "double" else " rounded to float32"))


def main():
    binary = sys.argv[1]
    reader = import_reader()
    with tempfile.TemporaryDirectory(prefix="ballagg-pvreader-") as workdir:
        check(reader, binary, workdir, "2d-periodic", 2, "periodic", 2.0, 300, "single")
        check(reader, binary, workdir, "2d-periodic", 2, "periodic", 2.0, 300, "double")
        check(reader, binary, workdir, "3d-walls", 3, "walls", 1.5, 200, "single")


if __name__ == "__main__":
    main()
