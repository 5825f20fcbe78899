#!/usr/bin/python3
"""The CPU time of a time-stepping run by stage, at two sizes side by side: which stages
grow faster than the number of spheres (what lifts the growth exponent of the run time).

Record each size with frame-pointer call chains, on a build made with
-DCMAKE_CXX_FLAGS="-fno-omit-frame-pointer -g" (the release flags otherwise):

    perf record -F 499 --call-graph fp -o /tmp/small.data bash -c 'for i in $(seq 40); do
        OMP_NUM_THREADS=2 BUILD/bin/ballagg run -q --out /tmp/s$i --seed 2 \\
        --set system.n=10000 --set system.volume_fraction=0.3 --set engine.kind=ts \\
        --set output.xyz=false --set ts.dt_factor=0.005; done'
    OMP_NUM_THREADS=2 perf record -F 499 --call-graph fp -o /tmp/large.data BUILD/bin/ballagg \\
        run -q --out /tmp/l --seed 2 --set system.n=1000000 ... (the same settings)
    perf script -i /tmp/small.data -F comm,tid,time,ip,sym,dso > /tmp/small.txt
    perf script -i /tmp/large.data -F comm,tid,time,ip,sym,dso > /tmp/large.txt
    /usr/bin/python3 bench/stage_profile.py /tmp/small.txt 40 /tmp/large.txt 1

Each sample of the `ballagg` process goes to the innermost stage found on its call chain
(STAGES below, first match from the leaf up) and counts 1 / frequency seconds of CPU time;
a recording's total is divided by the number of runs it holds. docs/performance.md,
"Where a run of 10^6 waits", shows what it found.
"""
import argparse
import collections
import re

# (stage, substrings of the symbols that belong to it), matched from the leaf of a call
# chain up; the first frame that matches decides.
STAGES = [
    ("solve (problem building, guards, DAHA)", ["solve_rigid", "solve_per_sphere", "minimise<", "update_multipliers",
                                                 "add_guards"]),
    ("retreats", ["retreat_group", "retreat_starts"]),
    ("flight sweeps", ["FlightSweep", "keep_flight"]),
    ("contact checks", ["new_overlaps", "contact_pass", "for_each_contact", "largest_overlap"]),
    ("apply", ["::apply"]),
    ("near pairs", ["NearPairs"]),
    ("cell lists (build, re-binning, materialising positions)", ["CellList", "rebin", "materialise"]),
    ("commit", ["commit"]),
    ("adhesive set, end_round, bodies, waves", ["AdhesiveSet", "end_round", "StepBodies", "PairIndex",
                                                "take_changed", "repair_waves", "clusters_of_group"]),
    ("State::merge", ["::merge", "absorb"]),
    ("set-up and output (not in wall_seconds)", ["make_initial_state", "assemble_state", "csv", "write_file",
                                                 "summary", "fmt::", "max_relative_overlap", "run_simulation"]),
    ("OpenMP waiting", ["libgomp"]),
]
HEADER = re.compile(r"^\s*(\S+)\s+(\d+)\s+(\d+\.\d+):")


def samples(path):
    """Yields (command, call chain from the leaf up) for each sample of a perf script text."""
    comm, chain = None, []
    with open(path) as f:
        for line in f:
            m = HEADER.match(line)
            if m:
                if comm is not None:
                    yield comm, chain
                comm, chain = m.group(1), []
            elif line.strip() and comm is not None:
                chain.append(line.strip())
    if comm is not None:
        yield comm, chain


def stage_of(chain):
    for frame in chain:
        for name, keys in STAGES:
            if any(k in frame for k in keys):
                return name
    return "other"


def seconds_by_stage(path, runs, frequency):
    counts = collections.Counter(stage_of(chain) for comm, chain in samples(path) if comm == "ballagg")
    return {stage: n / frequency / runs for stage, n in counts.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("small", help="perf script text of the smaller size")
    p.add_argument("small_runs", type=int, help="runs in that recording")
    p.add_argument("large", help="perf script text of the larger size")
    p.add_argument("large_runs", type=int, help="runs in that recording")
    p.add_argument("--frequency", type=float, default=499.0, help="perf record -F")
    args = p.parse_args()
    small = seconds_by_stage(args.small, args.small_runs, args.frequency)
    large = seconds_by_stage(args.large, args.large_runs, args.frequency)
    print("| stage | small (CPU s per run) | large (CPU s per run) | large / small |")
    print("|---|---|---|---|")
    for name in [s for s, _ in STAGES] + ["other"]:
        a, b = small.get(name, 0.0), large.get(name, 0.0)
        ratio = f"{b / a:.0f}" if a > 0 else "-"
        print(f"| {name} | {a:.4f} | {b:.3f} | {ratio} |")
    print(f"| all | {sum(small.values()):.4f} | {sum(large.values()):.3f} | |")


if __name__ == "__main__":
    main()
