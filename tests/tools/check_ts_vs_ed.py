#!/usr/bin/python3
"""bench/ts_vs_ed.py's bookkeeping, with the runs made up (no binary is run).

1. The repeats come in rounds: every size and seed once a round, the sizes above
   --repeat-max-n in the first round only, so that a drift of the machine's speed over
   the measurement spreads over every size instead of moving one size's reading; a
   regression to size-after-size order fails here.
2. The time kept for a size is the median over seeds of each seed's median run.
Exit status 0 when both hold.
"""
import os
import sys
from types import SimpleNamespace

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
import ts_vs_ed  # noqa: E402


def main():
    calls = []

    def fake_run_once(dim, n, seed, ns):
        calls.append((ns.engine, n, seed))
        # Seed s at size n, its k-th run: a wall time whose median over runs is n + s.
        k = sum(1 for c in calls if c == (ns.engine, n, seed))
        return {"wall_seconds": n + seed + (0.5 if k == 1 else -0.25 if k == 2 else 0.0)}

    ts_vs_ed.run_once = fake_run_once
    args = SimpleNamespace(vfs=[0.3], sizes=[10, 20], seeds=3, repeats=3, repeat_max_n=10, set=[])
    runs = ts_vs_ed.collect_runs(args, ["ts"], lambda n: [])
    one_round = [("ts", 10, s) for s in (1, 2, 3)]
    expected = one_round + [("ts", 20, s) for s in (1, 2, 3)] + one_round + one_round
    if calls != expected:
        print(f"FAIL: runs made in the order {calls}, expected {expected}")
        return 1
    if [len(runs[("ts", 0.3, 10, s)]) for s in (1, 2, 3)] != [3, 3, 3] or \
            [len(runs[("ts", 0.3, 20, s)]) for s in (1, 2, 3)] != [1, 1, 1]:
        print("FAIL: wrong number of runs per seed")
        return 1
    log = []
    kept = ts_vs_ed.median_run(runs, "ts", 0.3, 10, 3, log)["wall_seconds"]
    if kept != 12.0:  # seeds' medians 11, 12, 13: their median
        print(f"FAIL: kept {kept} s for N = 10, expected 12.0")
        return 1
    if log[0] != "ts Vf 0.3 N 10 seed 1: 10.750 11.000 11.500":
        print(f"FAIL: run listing {log[0]!r}")
        return 1
    print("ts_vs_ed.py: rounds and medians as expected")
    return 0


if __name__ == "__main__":
    sys.exit(main())
