#!/usr/bin/python3
"""Figures of ballagg sweeps and runs, sized for a paper (docs/sweeps.md#figures-ballagg-plot).

Usage: /usr/bin/python3 ballagg_plot.py [OPTIONS] DIR [DIR ...]

  DIR            sweep directories (with sweep.csv: the figures of Degond et al. 2023, the
                 points of several sweeps together) or run directories (with
                 timeseries.csv: the time series; after `ballagg analyze`, the end state;
                 after `ballagg analyze --frames`, the indicators against time; after
                 `ballagg analyze --kinetics`, n(t) and E(t) with the fitted laws)
  --out DIR      where to write the figures (default: the first DIR/figures)
  --format F     png (default), pdf or svg
  --dpi N        dots per inch of a PNG (default 300)
  --size WxH     size of one panel in inches (default 3.4x2.6: one journal column)
  --style FILE   a matplotlib style file, applied on top of the defaults below

`ballagg plot` runs this script, embedded in the binary; `ballagg plot --print-script`
writes it out, to edit and run with `ballagg plot --script FILE` or `python3 FILE`.
Error bars and bands are one standard deviation of the mean over the realizations.
Exit status 2 with one line on stderr for bad input.
"""
import csv
import json
import logging
import math
import os
import sys
import warnings


def fail(message):
    print(f"ballagg plot: error: {message}", file=sys.stderr)
    sys.exit(2)


# matplotlib and numpy, imported once the options and directories are known to be good
# (the import takes about a second: a mistyped option is reported at once).
plt = ticker = np = None


def import_libraries():
    global plt, ticker, np
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker as ticker
        import numpy as np
    except ImportError as e:
        fail(f"{e} (install Debian's python3-matplotlib and python3-numpy: scripts/setup)")


FORMATS = ("png", "pdf", "svg")
MIN_DPI, MAX_DPI = 10, 2400  # a PNG from a thumbnail to a print proof
MIN_INCHES, MAX_INCHES = 0.5, 50.0  # one panel's width or height
# One panel fits a journal column (3.3 to 3.5 in); a figure is its panels side by side.
# Fonts of 7 to 8 pt stay legible at that width; vector text stays editable (TrueType
# in PDF, text elements in SVG); no dates in the files, so the same tables give the same bytes.
DEFAULT_STYLE = {
    "figure.figsize": (3.4, 2.6),
    "savefig.dpi": 300,
    "figure.constrained_layout.use": True,
    "font.size": 8,
    "axes.titlesize": 8,
    "axes.labelsize": 8,
    "legend.fontsize": 7,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "lines.linewidth": 1.0,
    "lines.markersize": 3,
    "errorbar.capsize": 2,
    "legend.frameon": False,
    "legend.handlelength": 1.8,
    "pdf.fonttype": 42,
    "ps.fonttype": 42,
    "svg.fonttype": "none",
    "svg.hashsalt": "ballagg",
}
NO_DATES = {"png": None, "pdf": {"CreationDate": None, "ModDate": None}, "svg": {"Date": None}}
# A legend of more lines than this goes beside the panels, in a slot this many panel
# widths wide; a shorter one goes inside a panel.
LEGEND_INSIDE_MAX = 4
LEGEND_SLOT_WIDTH = 0.7
# A sweep's tables are a few kilobytes a point: a file near this size is no ballagg
# table, and is refused before it is read (docs/hardening.md).
MAX_TABLE_BYTES = 1 << 30
BAND_ALPHA = 0.25  # the error band of a curve, under its line
# Grid keys that are the axes and panels of the sweep figures, not lines of their own.
POSITION_KEYS = ("system.n", "system.volume_fraction", "system.box_length")


# ---------------------------------------------------------------- options

class Options:
    def __init__(self):
        self.out = None
        self.format = "png"
        self.dpi = None
        self.size = None
        self.style = None
        self.dirs = []


def parse_size(text):
    parts = text.lower().split("x")
    try:
        w, h = (float(p) for p in parts)
    except ValueError:
        w = h = math.nan
    if len(parts) != 2 or not (MIN_INCHES <= w <= MAX_INCHES and MIN_INCHES <= h <= MAX_INCHES):
        fail(f"--size {text}: not WIDTHxHEIGHT in inches, each from {MIN_INCHES:g} to {MAX_INCHES:g} (e.g. 3.4x2.6)")
    return w, h


def parse_dpi(text):
    try:
        dpi = int(text)
    except ValueError:
        dpi = 0
    if not MIN_DPI <= dpi <= MAX_DPI:
        fail(f"--dpi {text}: not an integer from {MIN_DPI} to {MAX_DPI}")
    return dpi


def parse_options(args):
    o = Options()
    names = ("--out", "--format", "--dpi", "--size", "--style")
    k = 0
    while k < len(args):
        a = args[k]
        if a == "--":  # the rest are directories, whatever their names
            o.dirs += args[k + 1:]
            break
        if a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        if not a.startswith("--"):
            o.dirs.append(a)
            k += 1
            continue
        name, eq, value = a.partition("=")
        if name not in names:
            fail(f"{a}: unknown option (options: {', '.join(names)})")
        if not eq:
            if k + 1 >= len(args):
                fail(f"{name}: needs a value")
            value, k = args[k + 1], k + 1
        k += 1
        if value == "":
            fail(f"{name}: an empty value is not allowed")
        if name == "--out":
            o.out = value
        elif name == "--format":
            if value not in FORMATS:
                fail(f"--format {value}: not a format ({', '.join(FORMATS)})")
            o.format = value
        elif name == "--dpi":
            o.dpi = parse_dpi(value)
        elif name == "--size":
            o.size = parse_size(value)
        else:
            o.style = value
    if not o.dirs:
        fail("no directory given (usage: ballagg plot [OPTIONS] SWEEP_DIR... or RUN_DIR...)")
    return o


def apply_style(o):
    """Our defaults, then the user's style file, then --size and --dpi."""
    plt.rcParams.update(DEFAULT_STYLE)
    if o.style is not None:
        if not os.path.isfile(o.style):
            what = "not a regular file" if os.path.exists(o.style) else "no such file"
            fail(f"--style {o.style}: {what} (a matplotlib style file: KEY: VALUE lines)")
        # matplotlib logs a bad key or value of a style file and goes on: here it is an error.
        complaints = []
        handler = logging.Handler(logging.WARNING)
        handler.emit = lambda record: complaints.append(record.getMessage())
        log = logging.getLogger("matplotlib")
        log.addHandler(handler)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                plt.style.use(o.style)
        except (OSError, UnicodeDecodeError, ValueError, UserWarning) as e:
            complaints.append(str(e))
        finally:
            log.removeHandler(handler)
        if complaints:
            fail(f"--style {o.style}: {complaints[0].strip().splitlines()[0]}")
    if o.size is None:
        o.size = tuple(plt.rcParams["figure.figsize"])
    if o.dpi is None:
        dpi = plt.rcParams["savefig.dpi"]
        o.dpi = plt.rcParams["figure.dpi"] if dpi == "figure" else dpi


# ---------------------------------------------------------------- files and figures

def read_csv(path, what="sweep"):
    """The rows of a table as dicts; one line and exit status 2 for anything else."""
    if not os.path.exists(path):
        fail(f"{path}: missing (is this a {what} directory?)")
    if not os.path.isfile(path):
        fail(f"{path}: not a regular file (is this a {what} directory?)")
    if os.path.getsize(path) > MAX_TABLE_BYTES:
        fail(f"{path}: larger than {MAX_TABLE_BYTES} bytes, not a ballagg table")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            return rows, list(reader.fieldnames or [])
    except UnicodeDecodeError as e:
        fail(f"{path}: not UTF-8 text (byte {e.start}: {e.reason}); not a ballagg {what} table")
    except csv.Error as e:
        fail(f"{path}: not a CSV table ({e})")
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")


def read_json(path):
    """A JSON file as a dict, or None when it is missing or unreadable."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        return data if isinstance(data, dict) else None
    except (OSError, ValueError):
        return None


def number(row, key):
    v = row.get(key, "nan") if row else "nan"
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


class Figures:
    """Figure layout and saving with the chosen format, size and resolution."""

    def __init__(self, o, out):
        self.o, self.out, self.colours = o, out, {}

    def colour(self, label):
        """One colour per line label, the same in every panel and figure."""
        if label not in self.colours:
            cycle = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["k"])
            self.colours[label] = cycle[len(self.colours) % len(cycle)]
        return self.colours[label]

    def panels(self, count, columns=None, legend_slot=False):
        """`count` panels of --size each, in rows of `columns`, and a legend slot to the right."""
        columns = columns or count
        rows = -(-count // columns)
        w, h = self.o.size
        slot = LEGEND_SLOT_WIDTH if legend_slot else 0.0
        fig = plt.figure(figsize=(w * (columns + slot), h * rows))
        grid = fig.add_gridspec(rows, columns + (1 if legend_slot else 0),
                                width_ratios=[1.0] * columns + ([slot] if legend_slot else []))
        axes = [fig.add_subplot(grid[k // columns, k % columns]) for k in range(count)]
        if legend_slot:
            fig.legend_axes = fig.add_subplot(grid[:, columns])
            fig.legend_axes.axis("off")
        return fig, axes

    def save(self, fig, name):
        path = os.path.join(self.out, f"{name}.{self.o.format}")
        legend_axes = getattr(fig, "legend_axes", None)
        if legend_axes is not None:
            handles, labels = {}, []
            for ax in fig.axes:
                for h, l in zip(*ax.get_legend_handles_labels()):
                    if l not in handles:
                        handles[l] = h
                        labels.append(l)
            legend_axes.legend([handles[l] for l in labels], labels, loc="center left", borderaxespad=0)
        for ax in fig.axes:
            tidy_log_axes(ax)
        temporary = os.path.join(self.out, f".{name}.{self.o.format}.tmp")  # renamed when complete
        try:
            fig.savefig(temporary, dpi=self.o.dpi, format=self.o.format, metadata=NO_DATES[self.o.format])
            os.replace(temporary, path)
        except OSError as e:
            fail(f"{path}: cannot write: {e.strerror}")
        except ValueError as e:  # an image too large for the renderer
            fail(f"{path}: cannot draw: {e} (choose a smaller --size or --dpi)")
        finally:
            if os.path.exists(temporary):
                os.remove(temporary)
        plt.close(fig)
        print(f"plot: {path}")


def tidy_log_axes(ax):
    """Log axes labelled at decades only (no crowded minor labels), or at 1-2-5 within one."""
    for axis, scale in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
        if scale != "log":
            continue
        lo, hi = sorted(axis.get_view_interval())
        if lo <= 0 or not math.isfinite(lo) or not math.isfinite(hi):
            continue
        axis.set_minor_formatter(ticker.NullFormatter())
        if math.floor(math.log10(hi)) - math.ceil(math.log10(lo)) >= 1:
            axis.set_major_locator(ticker.LogLocator(base=10, numticks=6))
            axis.set_major_formatter(ticker.LogFormatterSciNotation())
        else:  # less than a decade: plain numbers at round steps
            axis.set_major_locator(ticker.MaxNLocator(nbins=4))
            axis.set_major_formatter(ticker.FormatStrFormatter("%g"))


def legend_inside(ax):
    handles, labels = ax.get_legend_handles_labels()
    if labels:
        ax.legend()


def plus_minus(value, error):
    if not math.isfinite(value):
        return "n/a"
    return f"{value:.3f} ± {error:.3f}" if math.isfinite(error) and error > 0 else f"{value:.3f}"


# ---------------------------------------------------------------- sweeps

def vf_key(r):
    return round(number(r, "volume_fraction"), 6)


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


def short_key(key):
    return "dt" if key == "ts.dt_factor" else key.rsplit(".", 1)[-1]


def assign_lines(rows, axes_of):
    """Sets r["_line"], the legend label of the line a point belongs to.

    A line is one variant of one sweep at fixed values of the grid keys other than N and
    the volume fraction, so that two variants differing in any key are two lines. Its label
    is the variant's label (the method without [[variants]]), with the other grid keys'
    values; labels that would still coincide are told apart by dt, then by the sweep.
    """
    def identity(r):
        extra = tuple((k, r.get(k, "")) for k in axes_of[r["_dir"]] if k not in POSITION_KEYS)
        return (r["_dir"], r.get("variant", ""), extra)

    labels = {}
    for r in rows:
        ident = identity(r)
        if ident in labels:
            continue
        _, variant, extra = ident
        label = variant or r.get("method", "?")
        for k, v in extra:
            if k == "ts.dt_factor" and "dt" in label:
                continue
            label += f" {short_key(k)}={v}"
        labels[ident] = label
    by_label = {}
    for ident, label in labels.items():
        by_label.setdefault(label, []).append(ident)
    dts = {}
    for r in rows:
        dts.setdefault(identity(r), set()).add(r.get("dt_factor", "nan"))
    for label, idents in by_label.items():
        if len(idents) < 2:
            continue
        for ident in idents:
            dt = sorted(dts[ident])
            if "dt" not in label and len(dt) == 1 and dt[0] != "nan" and len({tuple(sorted(dts[i])) for i in idents}) == len(idents):
                labels[ident] = f"{label} dt={float(dt[0]):g}"
            elif len({i[0] for i in idents}) == len(idents):
                labels[ident] = f"{label} ({os.path.basename(os.path.normpath(ident[0]))})"
            else:
                labels[ident] = f"{label} #{idents.index(ident) + 1}"
    for r in rows:
        r["_line"] = labels[identity(r)]


def vf_panels(rows):
    return sorted(group(rows, vf_key).items())


def fig_against_n(figs, rows, column, ylabel, name, reference=None, logy=False, fitted_exponent=False):
    """A quantity against N with its error bars, one panel per volume fraction with data."""
    panels = []
    for vf, vrows in vf_panels(rows):
        lines = []
        for lab, lrows in sorted(group(vrows, lambda r: r["_line"]).items()):
            n, m, e = series(lrows, column)
            if logy:
                ok = m > 0
                n, m, e = n[ok], m[ok], e[ok]
            if len(n):
                lines.append((lab, n, m, e))
        if lines:
            panels.append((vf, lines))
    if not panels:
        print(f"plot: {name}: no data ({column}_mean is empty)")
        return
    labels = {lab for _, lines in panels for lab, *_ in lines}
    fig, axes = figs.panels(len(panels), legend_slot=len(labels) > LEGEND_INSIDE_MAX)
    for ax, (vf, lines) in zip(axes, panels):
        for lab, n, m, e in lines:
            text = lab
            if fitted_exponent and len(set(n)) >= 2:
                text += f": $N^{{{np.polyfit(np.log(n), np.log(m), 1)[0]:.2f}}}$"
            ax.errorbar(n, m, yerr=e, marker="o", label=text, color=figs.colour(lab))
        if reference is not None:
            ax.axhline(reference[0], color="grey", ls=":", lw=0.8, label=reference[1])
        ax.set_xscale("log")
        if logy:
            ax.set_yscale("log")
        ax.set_xlabel("number of spheres $N$")
        ax.set_ylabel(ylabel)
        ax.set_title(f"$V_f$ = {vf:g}")
        if not getattr(fig, "legend_axes", None):
            legend_inside(ax)
    figs.save(fig, name)


def chosen_n(rows, count):
    ns = sorted({number(r, "n") for r in rows})
    if len(ns) <= count:
        return ns
    picks = [ns[round(k * (len(ns) - 1) / (count - 1))] for k in range(count)]
    return sorted(set(picks))


def curves_of(table):
    """Rows of a per-point table (sweep_box_counting.csv, ...) by (sweep, point)."""
    return group(table, lambda p: (p["_dir"], p["point"]))


def fig_pair_distribution(figs, rows, pairs):
    """Fig 9: P(r) against r/R with its error band, one panel per N, a line per variant and Vf."""
    curves = curves_of(pairs)
    rows = [r for r in rows if (r["_dir"], r["point"]) in curves]
    ns = chosen_n(rows, 3)
    if not ns:
        print("plot: pair_distribution: no data (sweep_pair_distribution.csv is empty)")
        return
    vfs = sorted({vf_key(r) for r in rows})
    styles = ["-", "--", ":", "-."]
    labels = {r["_line"] for r in rows}
    fig, axes = figs.panels(len(ns), legend_slot=len(labels) * len(vfs) > LEGEND_INSIDE_MAX)
    for ax, n in zip(axes, ns):
        for r in sorted((r for r in rows if number(r, "n") == n), key=lambda r: (r["_line"], vf_key(r))):
            curve = curves[(r["_dir"], r["point"])]
            x = np.array([number(p, "r_over_R") for p in curve])
            y = np.array([number(p, "P_all_mean") for p in curve])
            e = np.array([number(p, "P_all_sem") for p in curve])
            label = r["_line"] + (f", $V_f$ = {vf_key(r):g}" if len(vfs) > 1 else "")
            c = figs.colour(r["_line"])
            ax.plot(x, y, ls=styles[vfs.index(vf_key(r)) % len(styles)], color=c, label=label)
            band = np.isfinite(e)
            if band.any():
                ax.fill_between(x[band], (y - e)[band], (y + e)[band], color=c, alpha=BAND_ALPHA, lw=0)
        ax.set_xlabel("pair distance $r/R$")
        ax.set_ylabel("pair distribution $P(r)$")
        ax.set_title(f"$N$ = {n:g}")
        if not getattr(fig, "legend_axes", None):
            legend_inside(ax)
    figs.save(fig, "pair_distribution")


def length_unit(row, runs_by_point):
    """R of a sweep point: the length_unit of one of its runs' analysis.json, else from N,
    V_f and L (equal radii)."""
    for run in runs_by_point.get((row["_dir"], row["point"]), []):
        a = read_json(os.path.join(row["_dir"], "runs", run, "analysis.json"))
        if a and isinstance(a.get("length_unit"), (int, float)) and a["length_unit"] > 0:
            return float(a["length_unit"])
    d, n, vf, box = number(row, "dimension"), number(row, "n"), number(row, "volume_fraction"), number(row, "box_length")
    unit_ball = math.pi if d == 2 else 4.0 * math.pi / 3.0
    return (vf * box ** d / (n * unit_ball)) ** (1.0 / d)


def fig_box_counting(figs, rows, boxes, runs_by_point):
    """Fig 11: N(eps) over the fitted levels, log-log, at the middle Vf, up to four N."""
    curves = curves_of(boxes)
    rows = [r for r in rows if (r["_dir"], r["point"]) in curves]
    if not rows:
        print("plot: box_counting: no data (sweep_box_counting.csv is empty)")
        return
    vfs = sorted({vf_key(r) for r in rows})
    vf = vfs[len(vfs) // 2]
    vrows = [r for r in rows if vf_key(r) == vf]
    ns = chosen_n(vrows, 4)
    labels = {r["_line"] for r in vrows}
    fig, axes = figs.panels(len(ns), legend_slot=len(labels) > LEGEND_INSIDE_MAX)
    for ax, n in zip(axes, ns):
        for r in sorted((r for r in vrows if number(r, "n") == n), key=lambda r: r["_line"]):
            curve = [b for b in curves[(r["_dir"], r["point"])] if number(b, "fitted") == 1]
            if not curve:
                continue
            unit = length_unit(r, runs_by_point)
            eps = [number(b, "eps") / unit for b in curve]
            count = [number(b, "boxes_all_mean") for b in curve]
            err = [number(b, "boxes_all_sem") for b in curve]
            d, d_err = number(r, "box_counting_dimension_mean"), number(r, "box_counting_dimension_sem")
            if not math.isfinite(d_err):
                d_err = number(r, "box_counting_dimension_error_mean")
            ax.errorbar(eps, count, yerr=np.nan_to_num(err), marker="o", color=figs.colour(r["_line"]),
                        label=f"{r['_line']}: $D_f$ = {plus_minus(d, d_err)}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(r"box size $\varepsilon/R$")
        ax.set_ylabel(r"number of boxes $N(\varepsilon)$")
        ax.set_title(f"$N$ = {n:g}, $V_f$ = {vf:g}")
        if not getattr(fig, "legend_axes", None):
            legend_inside(ax)
    figs.save(fig, "box_counting")


def ed_references(rows, ts_line_rows):
    """The ED lines a TS line is compared with: those of its sweep at the same other grid
    values if any, else every ED line."""
    ed_rows = [r for r in rows if r.get("method") == "ed"]
    same = [r for r in ed_rows if r["_dir"] == ts_line_rows[0]["_dir"]]
    chosen = same or ed_rows
    return group(chosen, lambda r: r["_line"])


def fig_fractal_dimension(figs, rows):
    """Fig 12: D_f against N (left) and, when the sweeps hold TS and ED points at the same N
    and Vf, the relative difference of each TS line from ED (right)."""
    styles = ["-", "--", ":", "-."]
    vfs = sorted({vf_key(r) for r in rows})
    vf_text = (lambda vf: f", $V_f$ = {vf:g}") if len(vfs) > 1 else (lambda vf: "")
    left = []
    for (lab, vf), lrows in sorted(group(rows, lambda r: (r["_line"], vf_key(r))).items()):
        n, m, e = series(lrows, "box_counting_dimension")
        if len(n):
            left.append((lab, vf, n, m, e))
    right = []
    for (lab, vf), lrows in sorted(group([r for r in rows if r.get("method", "").startswith("ts")],
                                         lambda r: (r["_line"], vf_key(r))).items()):
        refs = ed_references(rows, lrows)
        for ed_lab, ed_rows in sorted(refs.items()):
            ed = {number(r, "n"): number(r, "box_counting_dimension_mean") for r in ed_rows if vf_key(r) == vf}
            xs, ys = [], []
            for r in sorted(lrows, key=lambda r: number(r, "n")):
                d, ref = number(r, "box_counting_dimension_mean"), ed.get(number(r, "n"), math.nan)
                if math.isfinite(ref) and ref != 0 and math.isfinite(d):
                    xs.append(number(r, "n"))
                    ys.append(abs(d - ref) / ref)
            if xs:
                text = lab + (f" vs {ed_lab}" if len(refs) > 1 else "")
                right.append((lab, text, vf, xs, ys))
    if not left:
        print("plot: fractal_dimension: no data (box_counting_dimension_mean is empty)")
        return
    entries = len(left) + len(right)
    fig, axes = figs.panels(2 if right else 1, legend_slot=entries > LEGEND_INSIDE_MAX)
    for lab, vf, n, m, e in left:
        axes[0].errorbar(n, m, yerr=e, marker="o", color=figs.colour(lab), ls=styles[vfs.index(vf) % len(styles)],
                         label=lab + vf_text(vf))
    axes[0].set_ylabel("fractal dimension $D_f$")
    markers = "os^vD"
    for k, (lab, text, vf, xs, ys) in enumerate(right):
        axes[1].plot(xs, ys, marker=markers[k % len(markers)], color=figs.colour(lab),
                     ls=styles[vfs.index(vf) % len(styles)], label=text + vf_text(vf))
    if right:
        axes[1].set_ylabel(r"$|D_f^{\rm TS} - D_f^{\rm ED}|\ /\ D_f^{\rm ED}$")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_xlabel("number of spheres $N$")
        if not getattr(fig, "legend_axes", None):
            legend_inside(ax)
    figs.save(fig, "fractal_dimension")


def read_tagged(sweep, name):
    rows, fields = read_csv(os.path.join(sweep, name))
    for r in rows:
        r["_dir"] = sweep
    return rows, fields


def load_sweeps(dirs):
    """The points of every sweep (with finished runs) and their curves, all read before anything is written."""
    rows, boxes, pairs, axes_of, runs_by_point = [], [], [], {}, {}
    for sweep in dirs:
        table, fields = read_tagged(sweep, "sweep.csv")
        if "runs" not in fields or "method" not in fields:
            fail(f"{os.path.join(sweep, 'sweep.csv')}: no runs or method column (not a ballagg sweep table)")
        first = 2 if fields[:2] == ["point", "variant"] else 1
        axes_of[sweep] = fields[first:fields.index("method")]
        rows += [r for r in table if number(r, "runs") > 0]
        boxes += read_tagged(sweep, "sweep_box_counting.csv")[0]
        pairs += read_tagged(sweep, "sweep_pair_distribution.csv")[0]
        if os.path.isfile(os.path.join(sweep, "runs.csv")):
            for r in read_tagged(sweep, "runs.csv")[0]:
                runs_by_point.setdefault((sweep, r.get("point")), []).append(r.get("run", ""))
    if not rows:
        fail(f"{', '.join(dirs)}: no finished run to plot (sweep.csv)")
    assign_lines(rows, axes_of)
    return rows, boxes, pairs, runs_by_point


def plot_sweeps(figs, data):
    rows, boxes, pairs, runs_by_point = data
    fig_against_n(figs, rows, "wall_seconds", "wall time / s", "wall_time", logy=True, fitted_exponent=True)
    fig_against_n(figs, rows, "contacts", r"relative contacts $N_c$ ($i \neq j$)", "contacts")
    fig_against_n(figs, rows, "contacts_with_self", r"relative contacts $N_c$ (with $i = j$)", "contacts_with_self",
                  (0.5, "paper: ≈ 0.5"))
    fig_pair_distribution(figs, rows, pairs)
    fig_box_counting(figs, rows, boxes, runs_by_point)
    fig_fractal_dimension(figs, rows)
    fig_against_n(figs, rows, "largest_aspect_ratio", "aspect ratio $A_r$ of the largest cluster", "aspect_ratio")
    dims = int(number(rows[0], "dimension")) if math.isfinite(number(rows[0], "dimension")) else 2
    fig_against_n(figs, rows, "largest_orientation_x_abs", "orientation $|D_x|$ of the largest cluster", "orientation",
                  (2 / math.pi, r"isotropic: $2/\pi$") if dims == 2 else (0.5, "isotropic: 1/2"))


# ---------------------------------------------------------------- runs

def run_label(d, dirs):
    names = [os.path.basename(os.path.normpath(x)) for x in dirs]
    name = os.path.basename(os.path.normpath(d))
    return name if names.count(name) == 1 else os.path.normpath(d)


def columns(rows, fields, names):
    """The columns `names` of a table as float arrays (those it has)."""
    return {k: np.array([number(r, k) for r in rows]) for k in names if k in fields}


def fig_time_series(figs, runs):
    """Clusters, largest cluster, kinetic energy and momentum against time; with a rigid-body
    run's columns also the velocity dispersion and the rotational energy."""
    has = lambda col: any(col in run["fields"] for run in runs)
    panels = [("clusters", "number of clusters", True), ("largest_cluster", "largest cluster / spheres", True),
              ("kinetic_energy", r"kinetic energy $E_{\rm kin}$", True), ("momentum", "total momentum $P$", False)]
    if has("sigma_vx"):
        panels.append(("sigma", r"velocity dispersion $\sigma_v$", False))
    if has("rotational_energy"):
        panels.append(("rotational_energy", r"rotational energy $E_{\rm rot}$", False))
    fig, axes = figs.panels(len(panels), columns=2)
    single = len(runs) == 1
    component_styles = {"x": "-", "y": "--", "z": ":"}
    for ax, (key, ylabel, logy) in zip(axes, panels):
        for run in runs:
            t, c = run["series"]["time"], run["series"]
            if key in ("momentum", "sigma"):
                prefix = "p" if key == "momentum" else "sigma_v"
                symbol = "P" if key == "momentum" else r"\sigma_v"
                for axis in "xyz":
                    if prefix + axis not in c:
                        continue
                    colour = figs.colour(f"component {axis}") if single else figs.colour(run["label"])
                    text = f"${symbol}^{axis}$" if key == "sigma" else f"${symbol}_{axis}$"
                    ax.plot(t, c[prefix + axis], color=colour, ls=component_styles[axis], drawstyle="steps-post",
                            label=text if single else f"{run['label']} {text}")
            elif key in c:
                y = c[key]
                if logy:
                    ok = y > 0
                    ax.plot(t[ok], y[ok], color=figs.colour(run["label"]), label=run["label"], drawstyle="steps-post")
                else:
                    ax.plot(t, y, color=figs.colour(run["label"]), label=run["label"], drawstyle="steps-post")
        if logy:
            ax.set_yscale("log")
        ax.set_xlabel("time $t$")
        ax.set_ylabel(ylabel)
        if key in ("momentum", "sigma") or not single:
            legend_inside(ax)
    figs.save(fig, "timeseries")


def fig_run_curves(figs, runs, name, table, x_col, y_cols, xlabel, ylabel, fit=None, fit_line=None, markers=False):
    """One end-state table of each run (analyze's files) against its x column, log-log.

    fit: the legend text of the fitted value; fitted rows (column `fitted`) get filled
    markers, the others open ones; fit_line(run, x): the fitted power law at x.
    """
    fig, axes = figs.panels(1)
    ax = axes[0]
    styles = ["-", "--"]
    for run in runs:
        rows, fields = run["tables"][table]
        x = np.array([number(r, x_col) for r in rows])
        for k, (col, what) in enumerate(y_cols):
            y = np.array([number(r, col) for r in rows])
            ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
            label = what if len(runs) == 1 else f"{run['label']}, {what}"
            if fit is not None and k == 0:
                label += fit(run)
            colour = figs.colour(what) if len(runs) == 1 else figs.colour(run["label"])
            marker = "o" if fit is not None or markers else None
            ax.plot(x[ok], y[ok], ls=styles[k % len(styles)], marker=marker, mfc="none" if fit else None, color=colour,
                    label=label)
            if fit is not None and "fitted" in fields:
                fitted = ok & (np.array([number(r, "fitted") for r in rows]) == 1)
                ax.plot(x[fitted], y[fitted], ls="none", marker="o", color=colour)
                line = fit_line(run, x[fitted]) if fit_line is not None and k == 0 and fitted.any() else None
                if line is not None:
                    ax.plot(x[fitted], line, ls=":", color="grey", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    legend_inside(ax)
    figs.save(fig, name)


def fit_text(section, key, error_key):
    def text(run):
        a = run["analysis"] or {}
        part = a.get(section) if isinstance(a.get(section), dict) else {}
        value = part.get(key) if isinstance(part, dict) else None
        error = part.get(error_key) if isinstance(part, dict) else None
        if not isinstance(value, (int, float)):
            return ""
        error = error if isinstance(error, (int, float)) else math.nan
        return f": {plus_minus(float(value), float(error))}"
    return text


def box_fit_line(run, eps_over_r):
    """N(eps) = a eps^-D_f of analysis.json at eps = eps_over_r R, or None."""
    a = run["analysis"] or {}
    b = (a.get("all_spheres") or {}).get("box_counting") or {}
    d, pre, unit = b.get("dimension"), b.get("prefactor"), a.get("length_unit")
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in (d, pre, unit)):
        return None
    return pre * (eps_over_r * unit) ** (-d)


def box_dimension_text(run):
    a = run["analysis"] or {}
    b = (a.get("all_spheres") or {}).get("box_counting") or {}
    d, e = b.get("dimension"), b.get("dimension_error")
    if not isinstance(d, (int, float)):
        return ""
    return f", $D_f$ = {plus_minus(float(d), float(e) if isinstance(e, (int, float)) else math.nan)}"


ANALYSIS_TABLES = ("pair_distribution.csv", "box_counting.csv", "mass_radius.csv", "mass_spectrum.csv")
FRAME_TABLES = ("frames.csv", "frames_mass_spectrum.csv", "frames_clusters.csv")
# The mass spectrum is drawn at this many frames at most, spread evenly over the run.
SPECTRUM_FRAMES = 4


def fig_frame_indicators(figs, runs):
    """The indicators of `ballagg analyze --frames` against time: D_f with its error band
    (all centres, and the largest cluster's mass-radius dimension), N_c, the cluster masses
    and the largest cluster's aspect ratio."""
    panels = [("dimension", "fractal dimension"), ("contacts", r"relative contacts $N_c$"),
              ("mass", "cluster mass / sphere masses"), ("aspect", r"largest cluster's $A_r$")]
    fig, axes = figs.panels(len(panels), columns=2)
    single = len(runs) == 1
    for ax, (key, ylabel) in zip(axes, panels):
        for run in runs:
            f = run["frames"]
            t = f["time"]
            def line(y, what, style="-", err=None):
                colour = figs.colour(what) if single else figs.colour(run["label"])
                ok = np.isfinite(y)
                ax.plot(t[ok], y[ok], ls=style, marker="o", ms=3, color=colour,
                        label=what if single else f"{run['label']}, {what}")
                if err is not None:
                    ok &= np.isfinite(err)
                    ax.fill_between(t[ok], (y - err)[ok], (y + err)[ok], color=colour, alpha=0.2, lw=0)
            if key == "dimension":
                line(f["box_counting_dimension"], r"$D_f$, all centres", err=f["box_counting_dimension_error"])
                line(f["largest_mass_radius_dimension"], r"$f_D$, largest cluster (mass-radius)", "--",
                     err=f["largest_mass_radius_dimension_error"])
            elif key == "contacts":
                line(f["contacts"], r"$N_c$")
            elif key == "mass":
                line(f["mean_cluster_mass"], r"mean $\langle M \rangle$")
                line(f["weight_average_mass"], r"weight average $\sum M^2 / \sum M$", "--")
                ax.set_yscale("log")
            else:
                line(f["largest_aspect_ratio"], r"$A_r$")
        ax.set_xlabel("time $t$")
        ax.set_ylabel(ylabel)
        legend_inside(ax)
    figs.save(fig, "frames_indicators")


def spectrum_times(times):
    """At most SPECTRUM_FRAMES of the frame times, evenly spread, the last always included."""
    unique = sorted(set(times))
    if len(unique) <= SPECTRUM_FRAMES:
        return unique
    picks = np.linspace(0, len(unique) - 1, SPECTRUM_FRAMES).round().astype(int)
    return [unique[k] for k in sorted(set(picks))]


def fig_frame_spectra(figs, runs):
    """The mass spectrum at a few frames (Richardson's Figs 3c-d at chosen times)."""
    fig, axes = figs.panels(1)
    ax = axes[0]
    for run in runs:
        rows = run["frame_spectrum"]
        times = [number(r, "time") for r in rows]
        for k, when in enumerate(spectrum_times(times)):
            chosen = [r for r in rows if number(r, "time") == when]
            size = np.array([number(r, "size") for r in chosen])
            count = np.array([number(r, "clusters") for r in chosen])
            label = f"$t$ = {when:.3g}" if len(runs) == 1 else f"{run['label']}, $t$ = {when:.3g}"
            ax.plot(size, count, marker="o", ms=3, ls=["-", "--", ":", "-."][k % 4],
                    color=figs.colour(label), label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cluster size $s$ / spheres")
    ax.set_ylabel("number of clusters")
    legend_inside(ax)
    figs.save(fig, "frames_mass_spectrum")


def fig_kinetics(figs, runs):
    """n(t) and E(t) on log axes with the laws `ballagg analyze --kinetics` fitted over its window."""
    panels = [("clusters", "clusters_decay_z", "number of clusters $n$", "z"),
              ("kinetic_energy", "energy_decay_theta", r"kinetic energy $E$", r"\theta")]
    fig, axes = figs.panels(len(panels), columns=2)
    for ax, (column, key, ylabel, symbol) in zip(axes, panels):
        for run in runs:
            t, y = run["series"]["time"], run["series"].get(column)
            if y is None:
                continue
            ok = (t > 0) & (y > 0)
            colour = figs.colour(run["label"])
            ax.plot(t[ok], y[ok], color=colour, label=run["label"] if len(runs) > 1 else None)
            k = run["kinetics"]
            fit, window = k.get(key) or {}, k.get("window") or {}
            z, pre, t0, t1 = fit.get("exponent"), fit.get("prefactor"), window.get("start"), window.get("end")
            if all(isinstance(v, (int, float)) for v in (z, pre, t0, t1)):
                tt = np.geomspace(t0, t1, 50)
                err = fit.get("exponent_error")
                ax.plot(tt, pre * tt ** (-z), ls="--", color="black", lw=0.8,
                        label=f"${symbol}$ = {plus_minus(z, err if isinstance(err, (int, float)) else math.nan)}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time $t$")
        ax.set_ylabel(ylabel)
        legend_inside(ax)
    figs.save(fig, "kinetics")


def fig_collapse(figs, runs):
    """The scaled size distribution S^2 n_k / N against k / S of every frame, coloured by time."""
    fig, axes = figs.panels(1)
    ax = axes[0]
    shown = None
    for run in runs:
        rows = run["collapse"]
        x = np.array([number(r, "scaled_size") for r in rows])
        y = np.array([number(r, "scaled_count") for r in rows])
        t = np.array([number(r, "time") for r in rows])
        ok = (x > 0) & (y > 0)
        shown = ax.scatter(x[ok], y[ok], c=t[ok], s=6, cmap="viridis")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("scaled size $k / S(t)$")
    ax.set_ylabel(r"scaled number $S^2 n_k / N$")
    if shown is not None:
        fig.colorbar(shown, ax=ax, label="time $t$")
    figs.save(fig, "kinetics_collapse")


def fig_frame_r_max(figs, runs):
    """R_max against N_a of every cluster in every frame, coloured by time."""
    fig, axes = figs.panels(1)
    ax = axes[0]
    shown = None
    for run in runs:
        rows = run["frame_clusters"]
        size = np.array([number(r, "size") for r in rows])
        r_max = np.array([number(r, "r_max") for r in rows])
        t = np.array([number(r, "time") for r in rows])
        ok = (size > 0) & (r_max > 0)
        shown = ax.scatter(size[ok], r_max[ok], c=t[ok], s=6, cmap="viridis")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cluster size $N_a$ / spheres")
    ax.set_ylabel(r"largest extent $R_{\max}$")
    if shown is not None:
        fig.colorbar(shown, ax=ax, label="time $t$")
    figs.save(fig, "frames_r_max")


def load_runs(dirs):
    """Each run's time series and, when analysed, its end-state tables, all read before anything is written."""
    runs = []
    for d in dirs:
        rows, fields = read_csv(os.path.join(d, "timeseries.csv"), "run")
        if "time" not in fields or "clusters" not in fields:
            fail(f"{os.path.join(d, 'timeseries.csv')}: no time or clusters column (not a ballagg time series)")
        if not rows:
            fail(f"{os.path.join(d, 'timeseries.csv')}: no rows")
        names = ["time", "clusters", "largest_cluster", "kinetic_energy", "px", "py", "pz", "sigma_vx", "sigma_vy",
                 "sigma_vz", "rotational_energy"]
        run = {"dir": d, "label": run_label(d, dirs), "fields": fields, "series": columns(rows, fields, names),
               "analysis": read_json(os.path.join(d, "analysis.json")), "tables": {}}
        if run["analysis"] is not None and all(os.path.isfile(os.path.join(d, t)) for t in ANALYSIS_TABLES):
            for t in ANALYSIS_TABLES:
                run["tables"][t] = read_csv(os.path.join(d, t), "run")
        run["kinetics"] = read_json(os.path.join(d, "kinetics.json"))
        if os.path.isfile(os.path.join(d, "kinetics_collapse.csv")):
            run["collapse"] = read_csv(os.path.join(d, "kinetics_collapse.csv"), "run")[0]
        if all(os.path.isfile(os.path.join(d, t)) for t in FRAME_TABLES):
            frames, frame_fields = read_csv(os.path.join(d, "frames.csv"), "run")
            run["frames"] = columns(frames, frame_fields, frame_fields) if frames else None
            run["frame_spectrum"] = read_csv(os.path.join(d, "frames_mass_spectrum.csv"), "run")[0]
            run["frame_clusters"] = read_csv(os.path.join(d, "frames_clusters.csv"), "run")[0]
        runs.append(run)
    return runs


def plot_runs(figs, runs):
    fig_time_series(figs, runs)
    with_kinetics = [r for r in runs if r.get("kinetics")]
    if with_kinetics:
        fig_kinetics(figs, with_kinetics)
    collapsed = [r for r in runs if r.get("collapse")]
    if collapsed:
        fig_collapse(figs, collapsed)
    framed = [r for r in runs if r.get("frames")]
    if framed:
        fig_frame_indicators(figs, framed)
        fig_frame_spectra(figs, framed)
        fig_frame_r_max(figs, framed)
    analysed = [r for r in runs if r["tables"]]
    for r in runs:
        if not r["tables"]:
            print(f"plot: {r['dir']}: no end-state figures (P(r), box counting, mass-radius, mass spectrum) "
                  f"without analysis.json: run `ballagg analyze {r['dir']}` first")
    if not analysed:
        return
    for run in analysed:
        unit = (run["analysis"] or {}).get("length_unit")
        rows, fields = run["tables"]["box_counting.csv"]
        for row in rows:
            row["eps_over_R"] = str(number(row, "eps") / unit) if isinstance(unit, (int, float)) and unit > 0 else "nan"
    fig_run_curves(figs, analysed, "pair_distribution", "pair_distribution.csv", "r_over_R",
                   [("P_all", "all spheres"), ("P_largest", "largest cluster")], "pair distance $r/R$",
                   "pair distribution $P(r)$")
    fig_run_curves(figs, analysed, "box_counting", "box_counting.csv", "eps_over_R",
                   [("boxes_all", "all spheres"), ("boxes_largest", "largest cluster")], r"box size $\varepsilon/R$",
                   r"number of boxes $N(\varepsilon)$", fit=box_dimension_text, fit_line=box_fit_line)
    fig_run_curves(figs, analysed, "mass_radius", "mass_radius.csv", "r_over_R", [("enclosed", "largest cluster")],
                   "distance from the centre of mass $r/R$", "enclosed spheres $n(r)$",
                   fit=lambda run: (lambda t: t.replace(": ", ", $f_D$ = ", 1) if t else "")(
                       fit_text("largest_cluster", "mass_radius_dimension", "mass_radius_dimension_error")(run)))
    fig_run_curves(figs, analysed, "mass_spectrum", "mass_spectrum.csv", "size", [("clusters", "clusters")],
                   "cluster size $s$ / spheres", "number of clusters", markers=True)


# ---------------------------------------------------------------- main

def kind_of(d):
    if not os.path.isdir(d):
        fail(f"{d}: not a directory")
    if os.path.lexists(os.path.join(d, "sweep.csv")) or os.path.isfile(os.path.join(d, "sweep.toml")):
        return "sweep"
    if os.path.lexists(os.path.join(d, "timeseries.csv")) or os.path.isfile(os.path.join(d, "summary.json")):
        return "run"
    fail(f"{os.path.join(d, 'sweep.csv')}: missing, and {os.path.join(d, 'timeseries.csv')} too: "
         "neither a sweep directory (ballagg sweep) nor a run directory (ballagg run)")


def main(argv):
    o = parse_options(argv[1:])
    kinds = {d: kind_of(d) for d in o.dirs}
    if len(set(kinds.values())) > 1:
        fail(f"{', '.join(o.dirs)}: sweep and run directories mixed (plot sweeps together, or runs together)")
    import_libraries()
    apply_style(o)
    data = load_sweeps(o.dirs) if kinds[o.dirs[0]] == "sweep" else load_runs(o.dirs)
    out = o.out or os.path.join(o.dirs[0], "figures")
    if os.path.exists(out) and not os.path.isdir(out):
        fail(f"--out {out}: exists and is not a directory")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        fail(f"--out {out}: cannot create the directory: {e.strerror}")
    if not os.access(out, os.W_OK):
        fail(f"--out {out}: cannot write in the directory")
    figs = Figures(o, out)
    if kinds[o.dirs[0]] == "sweep":
        plot_sweeps(figs, data)
    else:
        plot_runs(figs, data)


if __name__ == "__main__":
    main(sys.argv)
