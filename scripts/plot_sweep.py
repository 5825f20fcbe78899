"""Figures of a sweep directory, like those of Degond et al. 2023 (docs/sweeps.md).

Usage: /usr/bin/python3 scripts/plot_sweep.py [--out OUT_DIR] SWEEP_DIR [SWEEP_DIR ...]
(`ballagg plot SWEEP_DIR...` runs this script, embedded in the binary.)

Reads sweep.csv, sweep_box_counting.csv and sweep_pair_distribution.csv of each sweep
directory (their points together, so that one sweep's TS runs can be compared with
another's ED runs) and writes PNG files into OUT_DIR (default: the first
SWEEP_DIR/figures). Error bars are the standard deviation of the mean over the
realizations. Exit status 2 with one line on stderr for bad input.
"""
import csv
import math
import os
import sys


def fail(message):
    print(f"ballagg plot: error: {message}", file=sys.stderr)
    sys.exit(2)


try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:
    fail(f"{e} (install Debian's python3-matplotlib and python3-numpy: scripts/setup)")

DPI = 80  # small PNGs for the repository


# A sweep's tables are a few kilobytes a point: a file near this size is no sweep table,
# and is refused before it is read (docs/hardening.md).
MAX_TABLE_BYTES = 1 << 30


def read_csv(path):
    """The rows of a sweep table as dicts; one line and exit status 2 for anything else."""
    if not os.path.exists(path):
        fail(f"{path}: missing (is this a sweep directory? run ballagg sweep first)")
    if not os.path.isfile(path):
        fail(f"{path}: not a regular file (is this a sweep directory?)")
    if os.path.getsize(path) > MAX_TABLE_BYTES:
        fail(f"{path}: larger than {MAX_TABLE_BYTES} bytes, not a sweep table")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            return list(csv.DictReader(f))
    except UnicodeDecodeError as e:
        fail(f"{path}: not UTF-8 text (byte {e.start}: {e.reason}); not a ballagg sweep table")
    except csv.Error as e:
        fail(f"{path}: not a CSV table ({e})")
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")


def number(row, key):
    v = row.get(key, "nan")
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def label_of(row):
    """The method and, for time stepping, its first step (dt_factor)."""
    dt = number(row, "dt_factor")
    return row["method"] if math.isnan(dt) else f"{row['method']} dt={dt:g}"


_colours = {}


def colour(label):
    """One colour per method label, the same in every panel and figure."""
    if label not in _colours:
        _colours[label] = plt.get_cmap("tab10")(len(_colours) % 10)
    return _colours[label]


def group(rows, key):
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def series(rows, y):
    rows = sorted(rows, key=lambda r: number(r, "n"))
    n = np.array([number(r, "n") for r in rows])
    m = np.array([number(r, y + "_mean") for r in rows])
    e = np.array([number(r, y + "_sem") for r in rows])
    ok = np.isfinite(m)
    return n[ok], m[ok], np.nan_to_num(e[ok])


def vf_key(r):
    return round(number(r, "volume_fraction"), 6)


def panels(count, width=4.0, height=3.2):
    fig, axes = plt.subplots(1, count, figsize=(width * count, height), squeeze=False)
    return fig, axes[0]


def save(fig, out, name, legend_outside=False):
    """legend_outside: one legend for the figure, right of the panels (many lines)."""
    if legend_outside:
        handles, labels = {}, []
        for ax in fig.axes:
            for h, l in zip(*ax.get_legend_handles_labels()):
                if l not in handles:
                    handles[l] = h
                    labels.append(l)
            if ax.get_legend():
                ax.get_legend().remove()
        fig.legend([handles[l] for l in labels], labels, loc="center right", fontsize=6)
        fig.tight_layout(rect=(0, 0, 0.78, 1))
    else:
        fig.tight_layout()
    path = os.path.join(out, name)
    temporary = os.path.join(out, f".{name}.tmp")  # renamed when complete: no half-written figure
    try:
        fig.savefig(temporary, dpi=DPI, format="png")
        os.replace(temporary, path)
    except OSError as e:
        fail(f"{path}: cannot write: {e.strerror}")
    plt.close(fig)
    print(f"plot: {path}")


def fig_wall_time(rows, out):
    """Figs 6-7: wall time against N, log-log, with the fitted exponent of each line."""
    by_vf = group(rows, vf_key)
    fig, axes = panels(len(by_vf))
    for ax, (vf, vrows) in zip(axes, sorted(by_vf.items())):
        for lab, lrows in sorted(group(vrows, label_of).items()):
            n, m, e = series(lrows, "wall_seconds")
            ok = m > 0
            n, m, e = n[ok], m[ok], e[ok]
            if len(n) == 0:
                continue
            text = lab
            if len(set(n)) >= 2:
                slope = np.polyfit(np.log(n), np.log(m), 1)[0]
                text += f": N^{slope:.2f}"
            ax.errorbar(n, m, yerr=e, marker="o", ms=3, capsize=2, label=text, color=colour(lab))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("N")
        ax.set_ylabel("wall time (s)")
        ax.set_title(f"Vf = {vf:g}")
        ax.legend(fontsize=7)
    save(fig, out, "wall_time.png")


def fig_against_n(rows, out, column, ylabel, name, reference=None, logy=False):
    by_vf = group(rows, vf_key)
    fig, axes = panels(len(by_vf))
    for ax, (vf, vrows) in zip(axes, sorted(by_vf.items())):
        for lab, lrows in sorted(group(vrows, label_of).items()):
            n, m, e = series(lrows, column)
            if len(n):
                ax.errorbar(n, m, yerr=e, marker="o", ms=3, capsize=2, label=lab, color=colour(lab))
        if reference is not None:
            ax.axhline(reference[0], color="grey", ls=":", lw=1, label=reference[1])
        ax.set_xscale("log")
        if logy:
            ax.set_yscale("log")
        ax.set_xlabel("N")
        ax.set_ylabel(ylabel)
        ax.set_title(f"Vf = {vf:g}")
        ax.legend(fontsize=7)
    save(fig, out, name)


def chosen_n(rows, count):
    ns = sorted({number(r, "n") for r in rows})
    if len(ns) <= count:
        return ns
    picks = [ns[round(k * (len(ns) - 1) / (count - 1))] for k in range(count)]
    return sorted(set(picks))


def fig_pair_distribution(rows, pairs, out):
    """Fig 9: P(r) against r/R, one panel per N, a line per method and volume fraction."""
    ns = chosen_n(rows, 3)
    fig, axes = panels(len(ns), width=4.8)
    styles = ["-", "--", ":", "-."]
    vfs = sorted({vf_key(r) for r in rows})
    for ax, n in zip(axes, ns):
        for r in rows:
            if number(r, "n") != n:
                continue
            curve = [p for p in pairs if p["point"] == r["point"] and p["_dir"] == r["_dir"]]
            if not curve:
                continue
            x = [number(p, "r_over_R") for p in curve]
            y = [number(p, "P_all_mean") for p in curve]
            ax.plot(x, y, ls=styles[vfs.index(vf_key(r)) % len(styles)], color=colour(label_of(r)),
                    label=f"{label_of(r)} Vf={vf_key(r):g}")
        ax.set_xlabel("r / R")
        ax.set_ylabel("P(r) (4.6)")
        ax.set_title(f"N = {n:g}")
        ax.legend(fontsize=6)
    save(fig, out, "pair_distribution.png", legend_outside=True)


def fig_box_counting(rows, boxes, out):
    """Fig 11: N(eps) against eps, log-log, over the fitted levels, at the middle Vf."""
    vfs = sorted({vf_key(r) for r in rows})
    vf = vfs[len(vfs) // 2]
    vrows = [r for r in rows if vf_key(r) == vf]
    ns = chosen_n(vrows, 4)
    fig, axes = panels(len(ns))
    for ax, n in zip(axes, ns):
        for r in vrows:
            if number(r, "n") != n:
                continue
            curve = [b for b in boxes if b["point"] == r["point"] and b["_dir"] == r["_dir"] and number(b, "fitted") == 1]
            if not curve:
                continue
            eps = [number(b, "eps") for b in curve]
            count = [number(b, "boxes_all_mean") for b in curve]
            err = [number(b, "boxes_all_sem") for b in curve]
            d = number(r, "box_counting_dimension_mean")
            ax.errorbar(eps, count, yerr=np.nan_to_num(err), marker="o", ms=3, capsize=2, color=colour(label_of(r)),
                        label=f"{label_of(r)}: D_f={d:.3f}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("eps")
        ax.set_ylabel("N(eps) (4.7)")
        ax.set_title(f"N = {n:g}, Vf = {vf:g}")
        ax.legend(fontsize=7)
    save(fig, out, "box_counting.png")


def fig_fractal_dimension(rows, out):
    """Fig 12: D_f against N (left) and the relative error of each TS method against ED."""
    fig, axes = panels(2, width=6.0)
    styles = ["-", "--", ":", "-."]
    vfs = sorted({vf_key(r) for r in rows})
    for (lab, vf), lrows in sorted(group(rows, lambda r: (label_of(r), vf_key(r))).items()):
        n, m, e = series(lrows, "box_counting_dimension")
        if len(n):
            axes[0].errorbar(n, m, yerr=e, marker="o", ms=3, capsize=2, color=colour(lab),
                             ls=styles[vfs.index(vf) % len(styles)], label=f"{lab} Vf={vf:g}")
    ed = {(number(r, "n"), vf_key(r)): number(r, "box_counting_dimension_mean")
          for r in rows if r["method"] == "ed"}
    for (lab, vf), lrows in sorted(group([r for r in rows if r["method"].startswith("ts")],
                                         lambda r: (label_of(r), vf_key(r))).items()):
        pts = sorted((number(r, "n"), number(r, "box_counting_dimension_mean")) for r in lrows)
        xs, ys = [], []
        for n, d in pts:
            ref = ed.get((n, vf))
            if ref is not None and math.isfinite(ref) and math.isfinite(d):
                xs.append(n)
                ys.append(abs(d - ref) / ref)
        if xs:
            axes[1].plot(xs, ys, marker="o", ms=3, color=colour(lab), ls=styles[vfs.index(vf) % len(styles)],
                         label=f"{lab} Vf={vf:g}")
    axes[0].set_ylabel("D_f (box counting, 4.7)")
    axes[1].set_ylabel("|D_f,TS - D_f,ED| / D_f,ED")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_xlabel("N")
        ax.legend(fontsize=6)
    save(fig, out, "fractal_dimension.png", legend_outside=True)


def read_tagged(sweep, name):
    rows = read_csv(os.path.join(sweep, name))
    for r in rows:
        r["_dir"] = sweep
    return rows


def main(argv):
    args = argv[1:]
    out = None
    if len(args) >= 2 and args[0] == "--out":
        out, args = args[1], args[2:]
    if not args:
        fail("usage: plot_sweep.py [--out OUT_DIR] SWEEP_DIR [SWEEP_DIR ...]")
    rows, boxes, pairs = [], [], []
    for sweep in args:
        if not os.path.isdir(sweep):
            fail(f"{sweep}: not a directory")
        table = read_tagged(sweep, "sweep.csv")
        if any("runs" not in r or "method" not in r for r in table):
            fail(f"{os.path.join(sweep, 'sweep.csv')}: no runs or method column (not a ballagg sweep table)")
        rows += [r for r in table if number(r, "runs") > 0]
        boxes += read_tagged(sweep, "sweep_box_counting.csv")
        pairs += read_tagged(sweep, "sweep_pair_distribution.csv")
    if not rows:
        fail(f"{', '.join(args)}: no finished run to plot (sweep.csv)")
    out = out or os.path.join(args[0], "figures")
    if os.path.exists(out) and not os.path.isdir(out):
        fail(f"--out {out}: exists and is not a directory")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        fail(f"--out {out}: cannot create the directory: {e.strerror}")
    if not os.access(out, os.W_OK):
        fail(f"--out {out}: cannot write in the directory")
    fig_wall_time(rows, out)
    fig_against_n(rows, out, "contacts", "N_c (4.5), pairs i != j", "contacts.png")
    fig_against_n(rows, out, "contacts_with_self", "N_c (4.5) with i = j", "contacts_with_self.png", (0.5, "paper: ~0.5"))
    fig_pair_distribution(rows, pairs, out)
    fig_box_counting(rows, boxes, out)
    fig_fractal_dimension(rows, out)
    fig_against_n(rows, out, "largest_aspect_ratio", "aspect ratio A_r (4.3)", "aspect_ratio.png")
    dims = int(number(rows[0], "dimension"))
    fig_against_n(rows, out, "largest_orientation_x_abs", "|D_x| of the orientation (4.4)", "orientation.png",
                  (2 / math.pi, "isotropic: 2/pi") if dims == 2 else (0.5, "isotropic: 1/2"))


if __name__ == "__main__":
    main(sys.argv)
