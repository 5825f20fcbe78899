#!/usr/bin/python3
"""The supplementary videos of Degond, Dimarco, Ferreira & Hecht (2023), Appendix C.

One video per case the paper lists: VideoN_ts (the time-stepping method) for N = 100, 400,
900, 2500, 10^4, 4 x 10^4, 9 x 10^4, 2.5 x 10^5 and 10^6, and VideoN_ed (event-driven) for
N = 100, 400, 900 and 2500; every one in 2D from the lattice start with speed 1 in random
directions (4.2), volume fraction 0.2, TS at the smallest step of Table 1
(examples/degond2023/appendix_c_ts.toml and appendix_c_ed.toml), run to one cluster.

Each case is run twice with build/bin/ballagg: once without a trajectory, for the time T
at which one cluster is reached, then with output.snapshot_every = T / --frames (the
trajectory does not change the run), and rendered by `ballagg render --video`. The
videos go to OUT/NAME.mp4 and the runs to OUT/NAME/ (trajectory.h5md removed after the
video is made, unless --keep-trajectories: it takes 20 bytes a disc a frame).

Usage: scripts/appendix_c_videos.py [--out out/appendix_c] [--cases Video100_ts ...]
           [--max-n N] [--frames 150] [--fps 15] [--width 1000] [--binary build/bin/ballagg]
           [--keep-trajectories] [--list]

The whole list takes hours and, at N = 10^6, gigabytes of disk while a case runs;
`--max-n 2500` makes the eight videos of N <= 2500 in a few minutes.
Only the Python standard library is used (and ffmpeg, through ballagg render).
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "examples", "degond2023")
CONFIGS = {"ts": os.path.join(EXAMPLES, "appendix_c_ts.toml"), "ed": os.path.join(EXAMPLES, "appendix_c_ed.toml")}

# Relative widening of the frame interval (see make_video).
FRAME_SLACK = 1e-9

# The paper's list, in its order: (video name, number of spheres, method).
CASES = [(f"Video{n}_{method}", n, method)
         for n, methods in [(100, "ts ed"), (400, "ts ed"), (900, "ts ed"), (2500, "ts ed"), (10000, "ts"),
                            (40000, "ts"), (90000, "ts"), (250000, "ts"), (1000000, "ts")]
         for method in methods.split()]


def selected_cases(names, max_n):
    """The cases named (all when none is), those with N above max_n left out."""
    known = {name: (name, n, method) for name, n, method in CASES}
    unknown = [name for name in names or [] if name not in known]
    if unknown:
        sys.exit(f"appendix_c_videos.py: unknown case {unknown[0]} (cases: {', '.join(known)})")
    chosen = [known[name] for name in names] if names else CASES
    return [case for case in chosen if max_n is None or case[1] <= max_n]


def run(binary, method, n, out, extra):
    """ballagg run of the case's configuration at N spheres into out; its summary.json."""
    cmd = [binary, "run", CONFIGS[method], "-q", "--out", out, "--set", f"system.n={n}",
           "--set", "output.xyz=false"]
    for setting in extra:
        cmd += ["--set", setting]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def make_video(args, name, n, method):
    """Runs the case for its end time, again with frames, and renders OUT/NAME.mp4."""
    probe = os.path.join(args.out, name + ".probe")
    end = run(args.binary, method, n, probe, [])
    for file in os.listdir(probe):
        os.remove(os.path.join(probe, file))
    os.rmdir(probe)
    if end.get("n_clusters") != 1:
        sys.exit(f"appendix_c_videos.py: {name} stopped with {end.get('n_clusters')} clusters "
                 f"({end.get('stop_reason')}), not one")
    # A hair more than T / frames, so that the last regular frame falls before T and the
    # run's end gives the final one: frames + 1 in all, whatever the rounding of T / frames.
    every = end["time"] / args.frames * (1.0 + FRAME_SLACK)
    directory = os.path.join(args.out, name)
    run(args.binary, method, n, directory, [f"output.snapshot_every={every!r}"])
    video = os.path.join(args.out, name + ".mp4")
    subprocess.run([args.binary, "render", directory, "--video", video, "--width", str(args.width),
                    "--fps", str(args.fps), "-q"], check=True, stdout=subprocess.DEVNULL)
    if not args.keep_trajectories:
        os.remove(os.path.join(directory, "trajectory.h5md"))
    return end["time"], every, video


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join("out", "appendix_c"))
    p.add_argument("--cases", nargs="+", metavar="NAME", help="the videos to make (default: every one)")
    p.add_argument("--max-n", type=int, metavar="N", help="leave out the cases of more than N spheres")
    p.add_argument("--frames", type=int, default=150, help="frames from t = 0 to one cluster (one more at the end)")
    p.add_argument("--fps", type=float, default=15)
    p.add_argument("--width", type=int, default=1000)
    p.add_argument("--binary", default=os.path.join(ROOT, "build", "bin", "ballagg"))
    p.add_argument("--keep-trajectories", action="store_true")
    p.add_argument("--list", action="store_true", help="print the cases and stop")
    args = p.parse_args()
    cases = selected_cases(args.cases, args.max_n)
    if args.list:
        for name, n, method in cases:
            print(f"{name}: N = {n}, {method}, {os.path.relpath(CONFIGS[method], ROOT)}")
        return 0
    if args.frames < 1:
        sys.exit("appendix_c_videos.py: --frames must be at least 1")
    if not os.path.exists(args.binary):
        sys.exit(f"appendix_c_videos.py: {args.binary} not found: run `make build` first")
    os.makedirs(args.out, exist_ok=True)
    for name, n, method in cases:
        for stale in (os.path.join(args.out, name), os.path.join(args.out, name + ".probe")):
            if os.path.exists(stale):
                sys.exit(f"appendix_c_videos.py: {stale} exists: remove it or choose another --out")
    for name, n, method in cases:
        end, every, video = make_video(args, name, n, method)
        print(f"{video}: N = {n}, {method}, one cluster at t = {end:.6g}, a frame every {every:.4g}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
