#!/usr/bin/python3
"""bench/ts_vs_ed.py's bookkeeping, with the runs made up (no binary is run).

1. The repeats come in rounds: every size and seed once a round, the sizes above
   --repeat-max-n in the first round only, so that a drift of the machine's speed over
   the measurement spreads over every size instead of moving one size's reading; a
   regression to size-after-size order fails here.
2. The time kept for a size is the median over seeds of each seed's median run.
3. The --engines table (the paper's Figs 6-7): made-up times t = c N^p give back each
   engine's p with a standard error of 0, and p within its error of the scatter's; ts's
   ratios to the others; ed-naive left out above --naive-max-n.
4. With the ballagg binary as argument: the --engines table of real runs at tiny N
   (ed-naive, ed and ts to one cluster), one row per N and an exponent row.
Exit status 0 when all hold.
"""
import contextlib
import io
import math
import os
import sys
from types import SimpleNamespace

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
import ed_scaling  # noqa: E402
import ts_vs_ed  # noqa: E402

# Made-up cost laws of the --engines check: (prefactor, exponent) per engine.
MADE_UP_LAWS = {"ed-naive": (1e-9, 3.5), "ed": (1e-6, 1.1), "ts": (1e-5, 1.25)}


def check_timing_table():
    """Item 3: exponents and ratios of made-up runs, ed-naive cut at --naive-max-n."""
    def fake_run_once(dim, n, seed, ns):
        c, p = MADE_UP_LAWS[ns.engine]
        return {"wall_seconds": c * n ** p}

    ts_vs_ed.run_once = fake_run_once
    args = SimpleNamespace(vfs=[0.2], sizes=[100, 400, 1600, 6400], seeds=2, repeats=1, repeat_max_n=10,
                           set=[], naive_max_n=1600)
    runs = ts_vs_ed.collect_runs(args, ts_vs_ed.ENGINES, lambda n: [])
    if ("ed-naive", 0.2, 6400, 1) in runs or ("ed", 0.2, 6400, 1) not in runs:
        return "ed-naive ran above --naive-max-n, or ed did not"
    table = ts_vs_ed.timing_table(args, runs, ts_vs_ed.ENGINES)
    if "| 0.2 | exponent | 3.50 ± 0.00 | 1.10 ± 0.00 | 1.25 ± 0.00 | | |" not in table:
        return f"exponents of made-up power laws wrong:\n{table}"
    ratio = MADE_UP_LAWS["ts"][0] * 100 ** 1.25 / (MADE_UP_LAWS["ed-naive"][0] * 100 ** 3.5)
    if f"| 0.2 | 100 | " not in table or f"| {ratio:.3g} |" not in table or "| 0.2 | 6400 | - |" not in table:
        return f"rows or ratios wrong:\n{table}"
    # Scatter between seeds: the error covers the slope's deviation from the law.
    p, error = ts_vs_ed.fit_exponent_with_error([100, 100, 400, 400, 1600, 1600],
                                                [1.0, 1.2, 4.4, 3.6, 16.8, 15.0])
    if error is None or not (0.0 < error < 0.2) or abs(p - 1.0) > 3 * error:
        return f"exponent {p} ± {error} of scattered points around N^1"
    if ts_vs_ed.fit_exponent_with_error([10, 20], [1.0, 2.0])[1] is not None:
        return "an error from two points"
    return None


def check_real_runs(binary):
    """Item 4: the --engines table of real runs at tiny N."""
    ed_scaling.BINARY = binary
    ts_vs_ed.BINARY = binary
    ts_vs_ed.run_once = ed_scaling.run_once
    argv = sys.argv
    sys.argv = ["ts_vs_ed.py", "--engines", "ed-naive", "ed", "ts", "--vfs", "0.2", "--sizes", "16", "36",
                "--seeds", "1", "--dt-factor", "0.01"]
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            ts_vs_ed.main()
    finally:
        sys.argv = argv
    rows = [line for line in out.getvalue().splitlines() if line.startswith("| 0.2 |")]
    if len(rows) != 3 or not rows[2].startswith("| 0.2 | exponent |"):
        return f"table of real runs:\n{out.getvalue()}"
    for row in rows[:2]:
        cells = [c.strip() for c in row.strip("|").split("|")]
        if len(cells) != 7 or not all(math.isfinite(float(c)) and float(c) > 0 for c in cells[2:]):
            return f"row {row!r}: not five positive times and ratios"
    return None


def main():
    for message in filter(None, [check_timing_table(),
                                 check_real_runs(sys.argv[1]) if len(sys.argv) > 1 else None]):
        print(f"FAIL: {message}")
        return 1
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
