#!/usr/bin/python3
"""The test models of Richardson (1995), Table I, with the rigid-body engine.

Runs examples/richardson1995/model-i.toml ... model-v.toml (three seeds for models i-iv,
one for v, as in the paper), draws the paper's figures into docs/figures/ and prints the
Markdown tables of docs/validation.md ("Richardson 1995 test models").

  * model (i): N(t) against the analytic solution (30) of the coagulation equation with a
    constant kernel, within the standard deviation of the mean over the seeds, and the mass
    spectrum at t = 1.6 and 8.2 against (31);
  * model (ii): the same quantities (the kernel is no longer constant);
  * models (iii)-(v): R_max against N_a with its power-law exponent, the fractal dimension
    of each aggregate, the density exponent gamma and f_D = 3 / (1 - gamma), next to the
    paper's values; model (v): velocity dispersion against time, energy against mass.

Usage: bench/richardson1995.py [--out DIR] [--models i ii iii iv v] [--seeds 3]
Needs Debian's python3-numpy and python3-matplotlib (scripts/setup installs them).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "bin", "ballagg")
EXAMPLES = os.path.join(ROOT, "examples", "richardson1995")
FIGURES = os.path.join(ROOT, "docs", "figures")

# Richardson's values (§3) for the aggregate models.
PAPER = {
    "iii": {"r_max": "0.57 ± 0.01", "f_d": "1.8 ± 0.4", "gamma": "-0.71 ± 0.03", "coag": "100%"},
    "iv": {"r_max": "0.573 ± 0.009", "f_d": "1.7 ± 0.3", "gamma": "-0.72 ± 0.03", "coag": "60%"},
    "v": {"r_max": "0.52 ± 0.01", "f_d": "2.0 ± 0.2", "gamma": "-0.55 ± 0.04", "coag": "62%"},
}


def run(model, seed, out, extra=()):
    directory = os.path.join(out, f"model-{model}-seed{seed}" + ("-" + "-".join(e.replace("=", "") for e in extra) if extra else ""))
    if not os.path.exists(os.path.join(directory, "analysis.json")):
        cmd = [BINARY, "run", os.path.join(EXAMPLES, f"model-{model}.toml"), "-q", "--seed", str(seed),
               "--out", directory, "--set", "output.xyz=false"]
        for e in extra:
            cmd += ["--set", e]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return directory


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def summary(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def analysis(directory):
    """The end statistics (the files of `ballagg analyze`, written by the run)."""
    with open(os.path.join(directory, "analysis.json")) as f:
        return json.load(f)


def on_grid(rows, column, times):
    """The value of a column at each time (timeseries rows are piecewise constant)."""
    t = np.array([float(r["time"]) for r in rows])
    v = np.array([float(r[column]) for r in rows])
    return np.array([v[np.searchsorted(t, x, side="right") - 1] for x in times])


def spectrum(directory):
    """Bodies of each mass, in units of the initial sphere mass."""
    m0 = summary(directory)["config"]["system"]["mass"]
    counts = {}
    for r in read_csv(os.path.join(directory, "mass_spectrum.csv")):
        k = int(round(float(r["mass"]) / m0))
        counts[k] = counts.get(k, 0) + int(r["clusters"])
    return counts


def mean_and_error(samples):
    a = np.array(samples, dtype=float)
    if len(a) < 2:
        return a.mean(axis=0), np.zeros_like(a.mean(axis=0))
    return a.mean(axis=0), a.std(axis=0, ddof=1) / math.sqrt(len(a))


def constant_kernel(config_speed, radius, box, n0, maxwellian):
    # alpha = sigma <v_rel> / V (Richardson §3): <v_rel> = 4/3 v0 for equal speeds in random
    # directions, sqrt(2) sqrt(8 / (3 pi)) v_rms for Maxwellian velocities.
    mean_relative = 4.0 / 3.0 * config_speed if not maxwellian else math.sqrt(2) * math.sqrt(8 / (3 * math.pi)) * config_speed
    return math.pi * (2 * radius) ** 2 * mean_relative / box ** 3


def coagulation_figure(model, dirs, early_dirs, figure, maxwellian):
    s0 = summary(dirs[0])
    cfg = s0["config"]
    n0, radius, box, speed = cfg["system"]["n"], cfg["system"]["radius"], cfg["system"]["box_length"], cfg["initial"]["speed"]
    alpha = constant_kernel(speed, radius, box, n0, maxwellian)
    t_end = cfg["stop"]["time"]
    times = np.linspace(0.0, t_end, 42)
    series = [read_csv(os.path.join(d, "timeseries.csv")) for d in dirs]
    n_mean, n_error = mean_and_error([on_grid(r, "clusters", times) for r in series])
    nc_mean, _ = mean_and_error([on_grid(r, "collisions", times) for r in series])
    nc1_mean, _ = mean_and_error([on_grid(r, "first_time_collisions", times) for r in series])
    mass_mean, mass_error = mean_and_error([on_grid(r, "max_mass", times) for r in series])
    theory = n0 / (1 + 0.5 * alpha * n0 * times)
    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5))
    a = ax[0, 0]
    a.errorbar(times, n_mean, yerr=n_error, fmt="o", ms=3, label="N (mean of seeds)")
    a.plot(times, theory, "k-", label="eq. (30)")
    a.plot(times, nc_mean, ":", label="$N_C$")
    a.plot(times, nc1_mean, "--", label="$N_{C_1}$")
    t_half = 2 / (alpha * n0)
    if t_half < t_end:
        a.axvline(t_half, color="grey", ls="-.", lw=0.8)
        a.axhline(n0 / 2, color="grey", ls="-.", lw=0.8)
    a.set_xlabel("t")
    a.set_ylabel("number")
    a.legend(fontsize=8)
    a.set_title(f"model ({model}): N(t), {len(dirs)} seeds")
    a = ax[0, 1]
    a.errorbar(times, mass_mean, yerr=mass_error, fmt="o-", ms=3)
    a.set_xlabel("t")
    a.set_ylabel("maximum mass / m0")
    a.set_title("largest body")
    deviations = []
    for a, spectra, t in ((ax[1, 0], [spectrum(d) for d in early_dirs], 1.6), (ax[1, 1], [spectrum(d) for d in dirs], t_end)):
        kmax = max(max(s) for s in spectra)
        k = np.arange(1, kmax + 1)
        counts = np.array([[s.get(int(m), 0) for m in k] for s in spectra], dtype=float)
        mean, error = mean_and_error(counts)
        f = 1 / (1 + 0.5 * alpha * n0 * t)
        analytic = n0 * f ** 2 * (1 - f) ** (k - 1)
        a.bar(k, mean, width=1.0, alpha=0.5, label="runs")
        a.errorbar(k, mean, yerr=error, fmt="none", ecolor="k", lw=0.8)
        a.plot(k, analytic, "r-", label="eq. (31)")
        a.set_xlim(0.5, min(kmax, 40) + 0.5)
        a.set_xlabel("mass / m0")
        a.set_ylabel("bodies")
        a.set_title(f"mass spectrum at t = {t:g}")
        a.legend(fontsize=8)
        deviations.append((t, k[: min(len(k), 8)], mean[:8], error[:8], analytic[:8]))
    fig.tight_layout()
    fig.savefig(figure, dpi=90)
    plt.close(fig)
    return times, n_mean, n_error, theory, deviations


def aggregate_figure(models, out_dirs, figure):
    fig, ax = plt.subplots(1, 3, figsize=(13, 4.2))
    for model, dirs in zip(models, out_dirs):
        bodies = []
        for d in dirs:
            bodies += [r for r in read_csv(os.path.join(d, "clusters.csv")) if int(r["size"]) >= 2]
        n = np.array([int(r["size"]) for r in bodies])
        r_max = np.array([float(r["r_max"]) for r in bodies])
        rho = np.array([float(r["density"]) for r in bodies])
        fd = np.array([float(r["richardson_dimension"]) for r in bodies])
        fe = np.array([float(r["richardson_dimension_error"]) for r in bodies])
        has = np.isfinite(fd) & (fe > 0)
        ax[0].loglog(n, r_max, "o", ms=3, label=f"({model})")
        ax[1].errorbar(n[has], fd[has], yerr=fe[has], fmt="o", ms=3, label=f"({model})")
        ax[2].loglog(n, rho, "o", ms=3, label=f"({model})")
    ax[0].set_xlabel("$N_a$")
    ax[0].set_ylabel("$R_{max}$")
    ax[0].set_title("size (Fig. 6a)")
    ax[1].set_xscale("log")
    ax[1].set_ylim(0.5, 3.5)
    ax[1].set_xlabel("$N_a$")
    ax[1].set_ylabel("$f_D$ (mass-radius, every centre)")
    ax[1].set_title("fractal dimension (Fig. 6b)")
    ax[2].set_xlabel("$N_a$")
    ax[2].set_ylabel(r"$\rho = M / (4/3 \pi R_{max}^3)$")
    ax[2].set_title("density (Fig. 6c)")
    for a in ax:
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=90)
    plt.close(fig)


def model_v_figure(directory, early, figure):
    rows = read_csv(os.path.join(directory, "timeseries.csv"))
    t = [float(r["time"]) for r in rows]
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for axis in "xyz":
        ax[0].plot(t, [float(r["sigma_v" + axis]) for r in rows], label=axis)
    ax[0].set_xlabel("t")
    ax[0].set_ylabel(r"$\sigma_v$")
    ax[0].set_title("model (v): velocity dispersion (Fig. 11a)")
    ax[0].legend()
    bodies = read_csv(os.path.join(early, "clusters.csv"))
    m = [float(r["mass"]) for r in bodies]
    e = [float(r["translational_energy"]) + float(r["rotational_energy"]) for r in bodies]
    ax[1].loglog(m, e, "o", ms=2)
    ax[1].set_xlabel("mass / m0")
    ax[1].set_ylabel("kinetic energy (translation + rotation)")
    ax[1].set_title("model (v) at t = 8.2 (Fig. 11b)")
    fig.tight_layout()
    fig.savefig(figure, dpi=90)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(ROOT, "out", "richardson1995"))
    p.add_argument("--models", nargs="+", default=["i", "ii", "iii", "iv", "v"])
    p.add_argument("--seeds", type=int, default=3)
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    os.makedirs(FIGURES, exist_ok=True)
    print(f"command: bench/richardson1995.py {' '.join(sys.argv[1:])}".rstrip())
    seeds = range(1, args.seeds + 1)
    dirs = {}
    for model in args.models:
        dirs[model] = [run(model, s, args.out) for s in (seeds if model != "v" else [1])]

    for model, maxwellian in (("i", False), ("ii", True)):
        if model not in dirs:
            continue
        early = [run(model, s, args.out, ["stop.time=1.6"]) for s in seeds]
        times, n, err, theory, spectra = coagulation_figure(model, dirs[model], early,
                                                           os.path.join(FIGURES, f"richardson1995-model-{model}.png"), maxwellian)
        print(f"\n### Model ({model}): N(t), mean of {len(dirs[model])} seeds ± standard deviation of the mean\n")
        print("| t | N (runs) | eq. (30) | (N - eq. 30) / error |")
        print("|---|---|---|---|")
        for k in range(0, len(times), 5):
            z = (n[k] - theory[k]) / err[k] if err[k] > 0 else 0.0
            print(f"| {times[k]:.2f} | {n[k]:.1f} ± {err[k]:.1f} | {theory[k]:.1f} | {z:+.2f} |")
        for t, k, mean, error, analytic in spectra:
            print(f"\nmass spectrum at t = {t:g}: " + ", ".join(
                f"k={kk}: {mm:.1f}±{ee:.1f} (eq. 31: {aa:.1f})" for kk, mm, ee, aa in zip(k, mean, error, analytic)))

    aggregate_models = [m for m in ("iii", "iv", "v") if m in dirs]
    if aggregate_models:
        aggregate_figure(aggregate_models, [dirs[m] for m in aggregate_models],
                         os.path.join(FIGURES, "richardson1995-aggregates.png"))
        print("\n### Aggregate properties at the end (ours: mean ± standard deviation of the mean over the seeds)\n")
        print("| model | R_max exponent | paper | mean f_D, every centre (aggregates) | paper | mean f_D, 4R..R_g (aggregates) | gamma | paper | 3 / (1 - gamma) | coagulating collisions | paper | collisions | aggregated mass |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for m in aggregate_models:
            ss = [summary(d) for d in dirs[m]]
            aa = [analysis(d) for d in dirs[m]]
            pop = [a["population"] for a in aa]
            r_e = mean_and_error([p["r_max_vs_size"]["slope"] for p in pop])
            fd = mean_and_error([p["mean_richardson_dimension"]["mean"] for p in pop])
            spread = np.mean([p["mean_richardson_dimension"]["spread"] for p in pop])
            with_fd = np.mean([p["mean_richardson_dimension"]["clusters"] for p in pop])
            windowed = [p["mean_mass_radius_dimension"] for p in pop]
            fw = np.mean([w["mean"] for w in windowed])
            fw_spread = np.mean([w["spread"] for w in windowed])
            fw_n = np.mean([w["clusters"] for w in windowed])
            gamma = mean_and_error([p["density_vs_size"]["slope"] for p in pop])
            fit_error = np.mean([p["r_max_vs_size"]["slope_error"] for p in pop])
            gamma_fit = np.mean([p["density_vs_size"]["slope_error"] for p in pop])
            coag = np.mean([s["merges"] / max(1, s["collisions"]) for s in ss])
            collisions = np.mean([s["collisions"] for s in ss])
            aggregated = np.mean([a["aggregated_mass_fraction"] for a in aa])
            pm = PAPER[m]
            def fmt(v, e, fit):
                return f"{v:.3f} ± {max(e, fit):.3f}"
            print(f"| ({m}) | {fmt(*r_e, fit_error)} | {pm['r_max']} | {fd[0]:.2f} ± {spread:.2f} ({with_fd:.0f}) | {pm['f_d']} | "
                  f"{fw:.2f} ± {fw_spread:.2f} ({fw_n:.0f}) | "
                  f"{fmt(*gamma, gamma_fit)} | {pm['gamma']} | {3 / (1 - gamma[0]):.2f} | {100 * coag:.0f}% | {pm['coag']} | "
                  f"{collisions:.0f} | {100 * aggregated:.2f}% |")
    if "v" in dirs:
        early = run("v", 1, args.out, ["stop.time=8.2"])
        model_v_figure(dirs["v"][0], early, os.path.join(FIGURES, "richardson1995-model-v.png"))
        s, a = summary(dirs["v"][0]), analysis(dirs["v"][0])
        print(f"\nmodel (v): {s['collisions']} collisions, {s['merges']} merges, {s['bounces']} bounces, "
              f"heaviest body {a['heaviest_mass_fraction'] * 100:.1f}% of the mass, "
              f"{a['aggregated_mass_fraction'] * 100:.2f}% aggregated, wall {s['wall_seconds']:.2f} s")


if __name__ == "__main__":
    main()
