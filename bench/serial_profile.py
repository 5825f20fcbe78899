#!/usr/bin/python3
"""Where a run leaves the second core idle: the main thread's samples taken while OpenMP's
worker threads had nothing to do, by function.

Record a run with perf, then feed this script perf's text output:

    OMP_NUM_THREADS=2 perf record -F 499 -g -o /tmp/perf.data \\
        build/bin/ballagg run -q --out /tmp/prof --seed 2 --set system.n=1000000 \\
        --set system.volume_fraction=0.3 --set engine.kind=ts --set output.xyz=false \\
        --set ts.dt_factor=0.005
    perf script -i /tmp/perf.data > /tmp/perf.txt
    /usr/bin/python3 bench/serial_profile.py /tmp/perf.txt --frequency 499

The run is cut into bins (--bin seconds). A bin in which no worker thread has a sample
outside libgomp (which spins while it waits) is one in which the main thread worked alone;
its main-thread samples are the serial part, listed by the function they were taken in (the
leaf of the call chain). With call chains that unwind through inlined functions (`perf
record --call-graph dwarf` on a build with -g), --stages also lists them by the innermost
stage of the time-stepping engine (detect_overlaps, commit, end_round, ...). Each sample
counts 1 / frequency seconds. docs/performance.md, "The serial part of a step", shows
what it found.
"""
import argparse
import collections
import re

STAGES = ["detect_overlaps", "commit", "advect", "end_round", "apply", "repair_waves", "take_changed_groups",
          "new_overlaps", "round_signature", "settle", "residual_overlap", "materialise_positions", "binned_cells",
          "rebin", "keep_flight", "retreat_group", "solve_group", "resolve", "step", "run_in_dimension"]


def read_samples(path):
    """(thread id, time, [frames from the leaf out], shared object of the leaf) per sample."""
    samples, current = [], None
    header = re.compile(r"\S+\s+(\d+)\s+([\d.]+):")
    frame = re.compile(r"\s+\S+\s+(.*?)\s+\((.*)\)$")
    with open(path, errors="replace") as f:
        for line in f:
            if line.strip() and not line.startswith("\t"):
                m = header.match(line)
                current = [int(m.group(1)), float(m.group(2)), [], None] if m else None
                if current:
                    samples.append(current)
            elif line.startswith("\t") and current is not None:
                m = frame.match(line.rstrip())
                if m:
                    current[2].append(re.sub(r"\+0x[0-9a-f]+$", "", m.group(1)))
                    if current[3] is None:
                        current[3] = m.group(2).rsplit("/", 1)[-1]
    return samples


def short(symbol):
    s = symbol.replace("(anonymous namespace)::", "").replace("ballagg::", "")
    s = re.sub(r"\(.*", "", s)
    while True:  # drop template arguments, innermost first
        t = re.sub(r"<[^<>]*>", "", s)
        if t == s:
            return s[:100]
        s = t


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("perf_script", help="the output of `perf script`")
    p.add_argument("--frequency", type=float, default=499.0, help="perf record's -F (samples per second)")
    p.add_argument("--bin", type=float, default=0.02, help="seconds per bin (a few sampling periods)")
    p.add_argument("--top", type=int, default=25, help="functions listed")
    p.add_argument("--stages", action="store_true", help="also list by stage of the time-stepping engine")
    args = p.parse_args()

    samples = read_samples(args.perf_script)
    main_thread = min(s[0] for s in samples)
    busy = collections.Counter()
    for tid, time, _, dso in samples:
        if tid != main_thread and dso and "gomp" not in dso:
            busy[int(time / args.bin)] += 1
    alone = [s for s in samples if s[0] == main_thread and not busy[int(s[1] / args.bin)]]
    n_main = sum(1 for s in samples if s[0] == main_thread)
    seconds = 1.0 / args.frequency
    print(f"main thread: {n_main * seconds:.1f} s, alone: {len(alone) * seconds:.1f} s ({len(alone) / n_main:.0%})")
    by_function = collections.Counter(short(s[2][0]) if s[2] else "?" for s in alone)
    for name, count in by_function.most_common(args.top):
        print(f"{count * seconds:7.2f} s  {name}")
    if args.stages:
        by_stage = collections.Counter()
        for _, _, frames, _ in alone:
            names = [short(f) for f in frames]
            by_stage[next((st for f in names for st in STAGES if re.search(rf"\b{st}\b", f)), "?")] += 1
        print("\nby stage of the engine (innermost):")
        for name, count in by_stage.most_common():
            print(f"{count * seconds:7.2f} s  {name}")


if __name__ == "__main__":
    main()
