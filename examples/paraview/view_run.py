"""Opens a ballagg run directory in ParaView: final.csv and, if present, trajectory.h5md.

    pvpython examples/paraview/view_run.py RUN_DIR [--frame K] [--screenshot F.png] [--width W]
    xvfb-run -a pvpython examples/paraview/view_run.py RUN_DIR --screenshot F.png   # no display

In the ParaView GUI: set the environment variable BALLAGG_RUN to the run directory before
starting paraview (or edit RUN_DIR below), then View > Python Shell > Run Script and pick
this file; or start it as `BALLAGG_RUN=RUN_DIR paraview --script=examples/paraview/view_run.py`
(close the welcome dialog of a first start beforehand: while it is open the script stops
when it sets the time).

What it builds (the pipeline browser shows each step):

* `final.csv`: CSV Reader -> Table To Points (x, y, z; "2D Points" for a 2D run).
* `trajectory.h5md`, when the run wrote one: a Programmable Source that reads the file
  with h5py through ballagg_h5md.py (beside this script), one ParaView time step per frame
  at the frame's simulated time, points with the arrays radius, mass, cluster, velocity,
  image (periodic boxes) and id. The animation toolbar steps through the frames.
* The box (summary.json's box_length) as an outline, and the time as text.

The trajectory, or final.csv when there is none, is shown as Point Gaussian spheres of
the spheres' radius, coloured by cluster. ParaView's own plugin mechanism for Python
readers is not used: in Debian 12's ParaView 5.11 it fails to import under Python 3.11
(paraview/detail/pythonalgorithm.py imports inspect.getargspec).
"""
import csv
import inspect
import json
import math
import os
import sys

from paraview.simple import (AnnotateTime, Box, ColorBy, CSVReader, GetActiveViewOrCreate,
                             GetAnimationScene, GetColorTransferFunction, GetScalarBar,
                             ProgrammableSource, Render, SaveScreenshot, SetActiveSource, Show,
                             TableToPoints, Text)

RUN_DIR = None  # or set it here, for Run Script in the GUI without BALLAGG_RUN


def _here():
    """This script's directory, where ballagg_h5md.py is. `__file__` is set by pvpython and
    by the GUI's Run Script; `paraview --script=FILE` sets none, so its command line is read
    (Linux's /proc/self/cmdline); BALLAGG_PARAVIEW_DIR overrides both."""
    if os.environ.get("BALLAGG_PARAVIEW_DIR"):
        return os.path.abspath(os.environ["BALLAGG_PARAVIEW_DIR"])
    name = globals().get("__file__") or inspect.currentframe().f_code.co_filename
    if name and os.path.isfile(name):
        return os.path.dirname(os.path.abspath(name))
    try:
        with open("/proc/self/cmdline", "rb") as f:
            args = [a.decode() for a in f.read().split(b"\0")]
        for i, a in enumerate(args):
            if a.startswith("--script="):
                return os.path.dirname(os.path.abspath(a[len("--script="):]))
            if a == "--script" and i + 1 < len(args):
                return os.path.dirname(os.path.abspath(args[i + 1]))
    except OSError:
        pass
    sys.exit("view_run.py: cannot tell where ballagg_h5md.py is: set BALLAGG_PARAVIEW_DIR "
             "to the directory of view_run.py")


def _arguments():
    """(run_dir, frame, screenshot, width) from the command line, BALLAGG_RUN or RUN_DIR."""
    args = sys.argv[1:] if sys.argv and os.path.basename(sys.argv[0]) == "view_run.py" else []
    run_dir, frame, screenshot, width = None, None, None, 1000
    i = 0
    while i < len(args):
        a = args[i]
        if a in ("--frame", "--screenshot", "--width") and i + 1 < len(args):
            value = args[i + 1]
            if a == "--frame":
                frame = int(value)
            elif a == "--screenshot":
                screenshot = value
            else:
                width = int(value)
            i += 2
        elif a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        elif run_dir is None and not a.startswith("--"):
            run_dir = a
            i += 1
        else:
            sys.exit(f"view_run.py: unexpected argument {a!r} (see --help)")
    run_dir = run_dir or os.environ.get("BALLAGG_RUN") or RUN_DIR
    if not run_dir:
        sys.exit("view_run.py: give the run directory (argument, BALLAGG_RUN or RUN_DIR)")
    return run_dir, frame, screenshot, width


def _show_spheres(source, view):
    """Point Gaussian spheres of the array radius (world units), coloured by cluster."""
    display = Show(source, view)
    display.SetRepresentationType("Point Gaussian")
    display.ShaderPreset = "Sphere"
    display.ScaleByArray = 1
    display.UseScaleFunction = 0  # the radius array is the radius itself
    display.SetScaleArray = ["POINTS", "radius"]
    display.GaussianRadius = 1.0
    ColorBy(display, ("POINTS", "cluster"))
    lut = GetColorTransferFunction("cluster")
    lut.ApplyPreset("Turbo", True)
    lut.AutomaticRescaleRangeMode = "Clamp and update every timestep"  # each frame's ids
    display.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = bar.RangeLabelFormat = "%.0f"  # ids are integers
    return display


# What both scripts of the Programmable Source start with: the reader module and the frame times.
_PREAMBLE = """
import sys
if {here!r} not in sys.path:
    sys.path.insert(0, {here!r})
import ballagg_h5md
times = ballagg_h5md.read_times({path!r})
executive = self.GetExecutive()
info = executive.GetOutputInformation(0)
"""

_INFORMATION_SCRIPT = _PREAMBLE + """info.Remove(executive.TIME_STEPS())
info.Remove(executive.TIME_RANGE())
for t in times:
    info.Append(executive.TIME_STEPS(), float(t))
info.Append(executive.TIME_RANGE(), float(times[0]))
info.Append(executive.TIME_RANGE(), float(times[-1]))
"""

_DATA_SCRIPT = _PREAMBLE + """t = info.Get(executive.UPDATE_TIME_STEP()) if info.Has(executive.UPDATE_TIME_STEP()) else times[-1]
frame = ballagg_h5md.read_frame({path!r}, ballagg_h5md.frame_index(times, t))
output = self.GetOutput()
ballagg_h5md.fill_polydata(output, frame)
output.GetInformation().Set(output.DATA_TIME_STEP(), frame["time"])
"""


def trajectory_source(path, here=None):
    """A Programmable Source reading trajectory.h5md, one time step per frame."""
    here = here or _here()
    source = ProgrammableSource(registrationName="trajectory.h5md")
    source.OutputDataSetType = "vtkPolyData"
    source.ScriptRequestInformation = _INFORMATION_SCRIPT.format(here=here, path=path)
    source.Script = _DATA_SCRIPT.format(here=here, path=path)
    return source


def open_run(run_dir, frame=None, screenshot=None, width=1000):
    """Builds the pipeline for run_dir in the active session and shows trajectory frame
    `frame` (default the last; negative counts from the end), or final.csv when the run
    has no trajectory.h5md; saves a width x width screenshot if asked. Returns the view and
    the sources: {"view", "final_csv", "points", "trajectory" (None without one),
    "display", "dimension"}."""
    run_dir = os.path.abspath(run_dir)
    if not os.path.isfile(os.path.join(run_dir, "final.csv")):
        raise ValueError(f"{run_dir}: no final.csv (not a finished ballagg run?)")
    with open(os.path.join(run_dir, "final.csv")) as f:
        header = next(csv.reader(f))
    dimension = 3 if "z" in header else 2
    summary_path = os.path.join(run_dir, "summary.json")
    box_length, final_time = None, float("nan")
    if os.path.isfile(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
        box_length, final_time = summary["box_length"], summary["time"]

    trajectory = os.path.join(run_dir, "trajectory.h5md")
    has_trajectory = os.path.isfile(trajectory)
    if frame is not None:  # checked before anything is built
        if not has_trajectory:
            raise ValueError("--frame needs trajectory.h5md (run with output.snapshot_every > 0)")
        if _here() not in sys.path:
            sys.path.insert(0, _here())
        import ballagg_h5md
        frames = len(ballagg_h5md.read_times(trajectory))
        if not -frames <= frame < frames:
            raise ValueError(f"frame {frame} out of range: the trajectory has {frames} frames")

    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0

    csv_reader = CSVReader(registrationName="final.csv", FileName=[os.path.join(run_dir, "final.csv")])
    points = TableToPoints(registrationName="final.csv points", Input=csv_reader)
    points.XColumn, points.YColumn = "x", "y"
    if dimension == 3:
        points.ZColumn = "z"
    else:
        points.ZColumn = "x"  # ignored: 2D points get z = 0
        points.a2DPoints = 1
    shown = points

    source = None
    if has_trajectory:
        shown = source = trajectory_source(trajectory)
        display = _show_spheres(shown, view)
        shown.UpdatePipelineInformation()
        times = shown.TimestepValues
        times = list(times) if hasattr(times, "__len__") else [times]
        scene = GetAnimationScene()
        scene.PlayMode = "Snap To TimeSteps"  # the animation steps through the frames
        scene.AnimationTime = times[frame if frame is not None else -1]
    else:
        display = _show_spheres(points, view)

    if box_length is not None:
        box = Box(registrationName="box", XLength=box_length, YLength=box_length,
                  ZLength=box_length if dimension == 3 else 0.0,
                  Center=[box_length / 2, box_length / 2, box_length / 2 if dimension == 3 else 0.0])
        box_display = Show(box, view)
        box_display.SetRepresentationType("Outline")
        box_display.AmbientColor = box_display.DiffuseColor = [0.3, 0.3, 0.3]
    if shown is points:  # final.csv alone: its time is summary.json's
        annotation = Text(registrationName="time", Text=f"t = {final_time:.6g} (final.csv)")
    else:
        annotation = AnnotateTime(registrationName="time", Format="t = {time:.6g}")
    Show(annotation, view).WindowLocation = "Upper Left Corner"
    SetActiveSource(shown)

    view.ResetCamera()
    if dimension == 2:
        view.InteractionMode = "2D"
    else:
        focal = [box_length / 2] * 3 if box_length else list(view.CameraFocalPoint)
        distance = 3.0 * (box_length or 1.0)
        direction = [1.0, -1.6, 1.0]  # as ballagg render's default --view; z is up
        norm = math.hypot(*direction)
        view.CameraFocalPoint = focal
        view.CameraPosition = [focal[i] + distance * direction[i] / norm for i in range(3)]
        view.CameraViewUp = [0.0, 0.0, 1.0]
        view.ResetCamera()
    Render(view)
    if source is not None:
        source.UpdatePipeline(GetAnimationScene().AnimationTime)  # the shown frame
    display.RescaleTransferFunctionToDataRange(False, True)  # to the shown frame's ids
    Render(view)
    if screenshot:
        SaveScreenshot(screenshot, view, ImageResolution=[width, width])
        print(f"view_run.py: wrote {screenshot}")
    return {"view": view, "final_csv": csv_reader, "points": points, "trajectory": source,
            "display": display, "dimension": dimension}


def main():
    run_dir, frame, screenshot, width = _arguments()
    try:
        open_run(run_dir, frame, screenshot, width)
    except ValueError as e:
        sys.exit(f"view_run.py: {e}")


# Run as a script (pvpython, pvbatch, the GUI's Run Script), not when imported as a module.
if __name__ != "view_run":
    main()
