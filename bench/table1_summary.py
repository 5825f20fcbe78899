"""Tables of docs/validation.md from the Table 1 sweeps (bench/reproduce_table1.sh).

Usage: /usr/bin/python3 bench/table1_summary.py out/paper_table1 [out/paper_table1_per_sphere ...]
Prints, per TS variant: the relative error of the box-counting D_f against ED at each
(N, Vf) (the paper's Fig. 12: e = |D_f,TS - D_f,ED| / D_f,ED, of the means over the
realizations), its mean and worst over the grid, and the same for N_c and the other
indicators; then the ED and TS values side by side.
"""
import csv
import math
import sys


def rows_of(dirs):
    rows = []
    for d in dirs:
        with open(f"{d}/sweep.csv", newline="") as f:
            rows += [r for r in csv.DictReader(f)]
    return rows


def num(r, k):
    try:
        return float(r[k])
    except (KeyError, ValueError):
        return math.nan


def points_of(d):
    """point id -> its row of DIR/sweep.csv."""
    with open(f"{d}/sweep.csv", newline="") as f:
        return {r["point"]: r for r in csv.DictReader(f)}


def runs_of(dirs):
    """(variant, N, Vf, realization) -> row of runs.csv, with the point's variant."""
    out = {}
    for d in dirs:
        points = points_of(d)
        with open(f"{d}/runs.csv", newline="") as f:
            for r in csv.DictReader(f):
                if r["stop_reason"] == "wall_seconds":
                    continue
                p = points[r["point"]]
                out[(p["variant"], int(num(p, "n")), round(num(p, "volume_fraction"), 6), int(r["realization"]))] = r
    return out


def paired(runs, variant, n, vf, column):
    """Mean and standard error of the per-realization differences TS - ED (same seeds)."""
    diffs = []
    for (v, rn, rvf, k), r in runs.items():
        if v == variant and rn == n and rvf == vf:
            e = runs.get(("ed", n, vf, k))
            if e is not None and math.isfinite(num(r, column)) and math.isfinite(num(e, column)):
                diffs.append(num(r, column) - num(e, column))
    if len(diffs) < 2:
        return None
    m = sum(diffs) / len(diffs)
    se = math.sqrt(sum((d - m) ** 2 for d in diffs) / (len(diffs) * (len(diffs) - 1)))
    return m, se, len(diffs)


def pair_distribution_at(dirs, r_over_R):
    """(variant, N, Vf) -> (mean, sem) of P(r) at r = r_over_R R (sweep_pair_distribution.csv)."""
    out = {}
    for d in dirs:
        points = points_of(d)
        with open(f"{d}/sweep_pair_distribution.csv", newline="") as f:
            for r in csv.DictReader(f):
                if abs(num(r, "r_over_R") - r_over_R) < 1e-9:
                    p = points[r["point"]]
                    variant = "ed" if p["method"] == "ed" else p["variant"]
                    out[(variant,) + key(p)] = (num(r, "P_all_mean"), num(r, "P_all_sem"))
    return out


def key(r):
    return (int(num(r, "n")), round(num(r, "volume_fraction"), 6))


def main(dirs):
    rows = rows_of(dirs)
    ed = {key(r): r for r in rows if r["method"] == "ed" and int(r["runs"]) > 0}
    variants = []
    for r in rows:
        if r["method"] != "ed" and r["variant"] not in variants:
            variants.append(r["variant"])

    print("### Relative error of D_f (box counting) against ED, e = |D_TS - D_ED| / D_ED (%)\n")
    ns = sorted({key(r)[0] for r in rows})
    vfs = sorted({key(r)[1] for r in rows})
    header = "| variant | Vf | " + " | ".join(f"N = {n}" for n in ns) + " | mean | worst |"
    print(header)
    print("|" + "---|" * (len(ns) + 4))
    summary = []
    for v in variants:
        errors = []
        for vf in vfs:
            cells = []
            for n in ns:
                t = next((r for r in rows if r["variant"] == v and key(r) == (n, vf) and int(r["runs"]) > 0), None)
                e = ed.get((n, vf))
                if t is None or e is None:
                    cells.append("—")
                    continue
                err = abs(num(t, "box_counting_dimension_mean") - num(e, "box_counting_dimension_mean")) / num(
                    e, "box_counting_dimension_mean")
                errors.append(err)
                cut = int(t["runs_cut"])
                cells.append(f"{100 * err:.2f}" + (f" ({t['runs']}/{int(t['runs']) + cut})" if cut else ""))
            print(f"| {v} | {vf:g} | " + " | ".join(cells) + " | | |")
        if errors:
            summary.append((v, 100 * sum(errors) / len(errors), 100 * max(errors), len(errors)))
            print(f"| {v} | all | " + " | ".join("" for _ in ns) +
                  f" | **{summary[-1][1]:.2f}** | **{summary[-1][2]:.2f}** |")
    print()
    print("| variant | points | mean e (%) | worst e (%) |")
    print("|---|---|---|---|")
    for v, mean, worst, count in summary:
        print(f"| {v} | {count} | {mean:.2f} | {worst:.2f} |")

    def side_by_side(column, title, digits=3):
        print(f"\n### {title}: mean ± standard deviation of the mean over the realizations\n")
        print("| N | Vf | ed | " + " | ".join(variants) + " |")
        print("|" + "---|" * (len(variants) + 3))
        for n in ns:
            for vf in vfs:
                cells = []
                for m in ["ed"] + variants:
                    r = ed.get((n, vf)) if m == "ed" else next(
                        (r for r in rows if r["variant"] == m and key(r) == (n, vf) and int(r["runs"]) > 0), None)
                    if r is None:
                        cells.append("—")
                    else:
                        cells.append(f"{num(r, column + '_mean'):.{digits}f} ± {num(r, column + '_sem'):.{digits}f}")
                if any(c != "—" for c in cells):  # a point no sweep ran is left out
                    print(f"| {n} | {vf:g} | " + " | ".join(cells) + " |")

    runs = runs_of(dirs)
    print("\n### Paired differences D_f,TS - D_f,ED (same seeds), mean ± standard error, in units of 10^-3\n")
    print("| variant | Vf | " + " | ".join(f"N = {n}" for n in ns) + " |")
    print("|" + "---|" * (len(ns) + 2))
    for v in variants:
        for vf in vfs:
            cells = []
            for n in ns:
                d = paired(runs, v, n, vf, "box_counting_dimension")
                cells.append("—" if d is None else f"{1000 * d[0]:+.0f} ± {1000 * d[1]:.0f}")
            print(f"| {v} | {vf:g} | " + " | ".join(cells) + " |")

    side_by_side("box_counting_dimension", "D_f (box counting, 4.7)")
    side_by_side("contacts_with_self", "N_c (4.5) as printed (with i = j)")
    side_by_side("contacts", "N_c (4.5), pairs i != j")
    side_by_side("correlation_dimension", "Correlation dimension (slope of P(r), 4R ... 20R)")
    p20 = pair_distribution_at(dirs, 20.0)
    print("\n### P(r) (4.6) at r = 20R: mean ± standard deviation of the mean over the realizations\n")
    print("| N | Vf | ed | " + " | ".join(variants) + " |")
    print("|" + "---|" * (len(variants) + 3))
    for n in ns:
        for vf in vfs:
            cells = [("—" if (m, n, vf) not in p20 else f"{p20[(m, n, vf)][0]:.1f} ± {p20[(m, n, vf)][1]:.1f}")
                     for m in ["ed"] + variants]
            if any(c != "—" for c in cells):
                print(f"| {n} | {vf:g} | " + " | ".join(cells) + " |")
    side_by_side("largest_aspect_ratio", "Aspect ratio A_r (4.3)", 2)
    side_by_side("largest_orientation_x_abs", "|D_x| of the orientation (4.4)", 2)
    side_by_side("max_overlap", "Largest relative overlap 1 - d / (R_i + R_j) of the run (summary.json max_overlap)", 3)
    side_by_side("wall_seconds", "Wall time (s) of the engine", 3)


if __name__ == "__main__":
    main(sys.argv[1:])
