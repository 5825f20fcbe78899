#!/usr/bin/python3
"""scripts/appendix_c_videos.py at its smallest: the paper's list of videos, and the two
videos of N = 100 (TS and ED) made with few small frames.

Usage: check_appendix_c_videos.py BALLAGG_BINARY. Exit status 0 when
1. --list names the 13 videos of the paper's Appendix C, VideoN_ts for N = 100 ... 10^6
   and VideoN_ed for N = 100 ... 2500;
2. Video100_ts.mp4 and Video100_ed.mp4 are written, each with one frame per snapshot
   (--frames 5: t = 0, four more and the end at one cluster), and the run directories
   keep their summary.json (one cluster) but not the trajectory;
3. an unknown case is refused before anything is run.
77 (skipped) where ffprobe is not installed.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "appendix_c_videos.py")
FRAMES = 5


def fail(message):
    print(f"FAIL: {message}")
    return 1


def frame_count(video):
    out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                          "stream=nb_read_frames", "-of", "csv=p=0", video], check=True, capture_output=True, text=True)
    return int(out.stdout.strip())


def main():
    binary = sys.argv[1]
    if shutil.which("ffprobe") is None:
        print("ffprobe is not installed: skipped")
        return 77
    listing = subprocess.run([sys.executable, SCRIPT, "--list"], check=True, capture_output=True, text=True).stdout
    names = [line.split(":")[0] for line in listing.splitlines()]
    expected = [f"Video{n}_{m}" for n in (100, 400, 900, 2500) for m in ("ts", "ed")] + \
               [f"Video{n}_ts" for n in (10000, 40000, 90000, 250000, 1000000)]
    if names != expected:
        return fail(f"--list gives {names}, expected {expected}")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "videos")
        bad = subprocess.run([sys.executable, SCRIPT, "--binary", binary, "--out", out, "--cases", "Video7_ts"],
                             capture_output=True, text=True)
        if bad.returncode == 0 or "unknown case Video7_ts" not in bad.stderr or os.path.exists(out):
            return fail(f"an unknown case gave status {bad.returncode}, {bad.stderr!r}")
        subprocess.run([sys.executable, SCRIPT, "--binary", binary, "--out", out, "--cases", "Video100_ts",
                        "Video100_ed", "--frames", str(FRAMES), "--width", "128"], check=True, stdout=subprocess.DEVNULL)
        for name in ("Video100_ts", "Video100_ed"):
            frames = frame_count(os.path.join(out, name + ".mp4"))
            if frames != FRAMES + 1:
                return fail(f"{name}.mp4 has {frames} frames, expected {FRAMES + 1}")
            with open(os.path.join(out, name, "summary.json")) as f:
                summary = json.load(f)
            if summary["n_clusters"] != 1 or summary["n_particles"] != 100:
                return fail(f"{name}: {summary['n_particles']} spheres ending in {summary['n_clusters']} clusters")
            if os.path.exists(os.path.join(out, name, "trajectory.h5md")):
                return fail(f"{name}/trajectory.h5md kept without --keep-trajectories")
        if sorted(os.listdir(out)) != ["Video100_ed", "Video100_ed.mp4", "Video100_ts", "Video100_ts.mp4"]:
            return fail(f"{out} holds {sorted(os.listdir(out))}")
    print("appendix_c_videos.py: the list and the two videos of N = 100 as expected")
    return 0


if __name__ == "__main__":
    sys.exit(main())
