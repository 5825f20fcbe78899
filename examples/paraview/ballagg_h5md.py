"""Reads ballagg's trajectory.h5md (H5MD 1.1) frame by frame, for ParaView and for Python.

The reading is plain h5py and numpy (Debian: python3-h5py, python3-numpy) and needs no
ParaView: `read_times`, `frame_index` and `read_frame` turn a file into numpy arrays, and
tests/io/check_paraview_reader.py tests them with /usr/bin/python3. Only `fill_polydata`
needs VTK (it imports vtkmodules when called): it is what the programmable source of
view_run.py calls, inside ParaView, to turn a frame into points.

    import ballagg_h5md                                   # this directory on sys.path
    times = ballagg_h5md.read_times("out/run/trajectory.h5md")
    frame = ballagg_h5md.read_frame("out/run/trajectory.h5md", len(times) - 1)
    frame["points"]      # (N, 3) float64, folded into the box; 2D runs get z = 0
    frame["cluster"]     # (N,) int32, ids 0, 1, ... within this frame

Positions are those of the file, folded into a periodic box; `read_frame(..., unwrap=True)`
adds image * edges, which puts every cluster in one piece across the faces. The file
stores positions and velocities as float32 (output.snapshot_precision = "single", the
default) or float64; read_frame gives float64 either way.
"""
import h5py
import numpy as np

PARTICLES = "particles/all"


def _open(source):
    """An open h5py.File for a path (the caller closes it), or the given file itself."""
    return (h5py.File(source, "r"), True) if not isinstance(source, h5py.File) else (source, False)


def read_times(source):
    """The time of every frame, a float64 array in increasing order."""
    f, close = _open(source)
    try:
        return f[PARTICLES + "/position/time"][:].astype(np.float64)
    finally:
        if close:
            f.close()


def frame_index(times, t):
    """The frame to show at time t: the last frame at or before t (the first before it)."""
    times = np.asarray(times)
    if len(times) == 0:
        raise ValueError("the trajectory has no frame")
    return int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 1))


def read_box(source):
    """(dimension, edges [D], periodic) of the trajectory's box (D: the run's dimension, also
    for a 2D run stored in 3D)."""
    f, close = _open(source)
    try:
        box = f[PARTICLES + "/box"]
        dimension = int(f["parameters"].attrs.get("dimension", box.attrs["dimension"]))
        boundary = [b.decode() if isinstance(b, bytes) else str(b) for b in box.attrs["boundary"]][:dimension]
        # edges: a vector, or (3D layout) a time-dependent group of edge matrices.
        edges = box["edges"][:] if isinstance(box["edges"], h5py.Dataset) else box["edges/value"][0].diagonal()
        return dimension, edges[:dimension].astype(np.float64), all(b == "periodic" for b in boundary)
    finally:
        if close:
            f.close()


def _pad3(a, dtype):
    """(N, D) -> (N, 3), z = 0 for D = 2: ParaView's points are 3D."""
    out = np.zeros((a.shape[0], 3), dtype=dtype)
    out[:, : a.shape[1]] = a
    return out


def read_frame(source, k, unwrap=False):
    """Frame k (negative counts from the end) as a dict of numpy arrays.

    time, step                 the frame's simulated time and step (events or time steps)
    points [N][3]              positions (z = 0 in 2D); with unwrap, position + image * edges
    velocity [N][3]            velocities (vz = 0 in 2D)
    radius, mass [N]           per sphere (float64)
    cluster [N]                int32 cluster ids of this frame
    image [N][3]               int32 periodic images, None with walls
    dimension, edges, periodic the box (edges [D])
    """
    f, close = _open(source)
    try:
        g = f[PARTICLES]
        frames = g["position/value"].shape[0]
        if not -frames <= k < frames:
            raise IndexError(f"frame {k} out of range: the trajectory has {frames} frames")
        k %= frames
        dimension, edges, periodic = read_box(f)
        position = g["position/value"][k, :, :dimension].astype(np.float64)
        image = g["image/value"][k, :, :dimension].astype(np.int32) if "image" in g else None
        if unwrap and image is not None:
            position = position + image * edges
        return {
            "time": float(g["position/time"][k]),
            "step": int(g["position/step"][k]),
            "points": _pad3(position, np.float64),
            "velocity": _pad3(g["velocity/value"][k, :, :dimension], np.float64),
            "radius": g["radius"][:].astype(np.float64),
            "mass": g["mass"][:].astype(np.float64),
            "cluster": g["cluster/value"][k].astype(np.int32),
            "image": None if image is None else _pad3(image, np.int32),
            "dimension": dimension,
            "edges": edges,
            "periodic": periodic,
        }
    finally:
        if close:
            f.close()


def fill_polydata(output, frame):
    """Puts a frame into a vtkPolyData: one vertex per sphere, with the point arrays
    radius, mass, cluster, velocity, image (periodic boxes) and id (the sphere's index),
    and the field arrays time and step. Needs VTK (ParaView's pvpython, or python3-vtk9)."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray

    n = len(frame["radius"])
    points = vtkPoints()
    points.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(frame["points"]), deep=True))
    output.SetPoints(points)
    verts = vtkCellArray()
    verts.SetData(numpy_support.numpy_to_vtkIdTypeArray(np.arange(n + 1, dtype=np.int64), deep=True),
                  numpy_support.numpy_to_vtkIdTypeArray(np.arange(n, dtype=np.int64), deep=True))
    output.SetVerts(verts)

    def add(data, name, values):
        array = numpy_support.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        data.AddArray(array)

    for name in ("radius", "mass", "cluster", "velocity", "image"):
        if frame[name] is not None:
            add(output.GetPointData(), name, frame[name])
    add(output.GetPointData(), "id", np.arange(n, dtype=np.int32))
    add(output.GetFieldData(), "time", np.array([frame["time"]]))
    add(output.GetFieldData(), "step", np.array([frame["step"]], dtype=np.int64))
    return output
