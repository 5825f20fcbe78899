#!/usr/bin/python3
"""The kinetic exponents of dilute ballistic aggregation, n(t) ~ t^-z and E(t) ~ t^-theta,
over realizations: coalescing spheres (rigid-body engine, collision.coagulation = "sphere",
constant density) and fractal rigid clusters (ed), in 2D and 3D.

Each realization is `ballagg run` (periodic box, random start, Gaussian velocities, zero
total momentum, to 20 clusters) and `ballagg analyze --kinetics` (the automatic window,
docs/analysis.md "Kinetics"). Prints a Markdown table: the mean of z and theta over the
realizations with the standard deviation of the mean, the mean of the per-run fit errors,
and the mean-field z for coalescing spheres, 2d/(d+2). For fractal clusters, also the
fractal dimension of the late clusters from their mass-radius relation: `ballagg analyze`
fits R_max ~ size^(1/D_f) over the 20 clusters left (population.r_max_vs_size), and the
mean over realizations of 1/slope is given with its SEM, beside the mean of the clusters'
own mass-radius dimensions (population.mean_mass_radius_dimension).

--vfs runs every chosen case at each of the given volume fractions instead of its own
(the density dependence of the exponents).

Usage: bench/kinetics_exponents.py [--realizations 10] [--cases 2d-spheres ...] [--n N] [--vfs VF ...]
Only the Python standard library is used.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ed_scaling import BINARY, machine  # noqa: E402

GAS = ["system.boundary=periodic", "initial.positions=random", "initial.velocities=gaussian",
       "initial.zero_momentum=true", "stop.clusters=20", "output.xyz=false"]
SPHERES = ["engine.kind=rigid-body", "collision.coagulation=sphere", "collision.merged_radius=constant-density"]
CASES = {
    "2d-spheres": ("2D, coalescing spheres", 2, 0.01, SPHERES),
    "3d-spheres": ("3D, coalescing spheres", 3, 0.005, SPHERES),
    "2d-fractal": ("2D, fractal rigid clusters (ed)", 2, 0.01, ["engine.kind=ed"]),
    "3d-fractal": ("3D, fractal rigid clusters (ed)", 3, 0.005, ["engine.kind=ed"]),
}


def realization(case, n, vf, seed):
    """kinetics.json of one run, and analysis.json's population section for fractal clusters."""
    _, dimension, _, sets = CASES[case]
    with tempfile.TemporaryDirectory() as out:
        run = os.path.join(out, "run")
        cmd = [BINARY, "run", "-q", "--out", run, "--seed", str(seed), "--set", f"system.dimension={dimension}",
               "--set", f"system.n={n}", "--set", f"system.volume_fraction={vf}"]
        for s in GAS + sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env={**os.environ, "OMP_NUM_THREADS": "1"})
        subprocess.run([BINARY, "analyze", "-q", run, "--kinetics"], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(run, "kinetics.json")) as f:
            kinetics = json.load(f)
        population = None
        if "spheres" not in case:
            subprocess.run([BINARY, "analyze", "-q", run], check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(run, "analysis.json")) as f:
                population = json.load(f)["population"]
        return kinetics, population


def mean_and_sem(values):
    if len(values) < 2:
        return (values[0] if values else float("nan")), float("nan")
    return statistics.mean(values), statistics.stdev(values) / len(values) ** 0.5


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--realizations", type=int, default=10)
    p.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    p.add_argument("--n", type=int, default=20000)
    p.add_argument("--vfs", nargs="+", type=float, help="volume fractions for every case (default: each case's own)")
    args = p.parse_args()
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run `make build` first")
    print(f"machine: {machine()}, load average {os.getloadavg()[0]:.1f} at the start")
    print(f"command: bench/kinetics_exponents.py {' '.join(sys.argv[1:])}".rstrip())
    print()
    print("| case | N | Vf | realizations | z (mean ± SEM) | mean fit error of z | theta (mean ± SEM) | "
          "mean-field z, coalescing spheres | D_f of the late clusters, 1 / slope of R_max(size) | "
          "mean mass-radius D_f of the clusters |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case in args.cases:
        label, dimension, own_vf, _ = CASES[case]
        for vf in args.vfs or [own_vf]:
            print(row(label, dimension, args.n, vf,
                      [realization(case, args.n, vf, seed) for seed in range(1, args.realizations + 1)]), flush=True)


def row(label, dimension, n, vf, results):
    fits = [k for k, _ in results]
    z = [f["clusters_decay_z"]["exponent"] for f in fits if f["clusters_decay_z"]["exponent"] is not None]
    theta = [f["energy_decay_theta"]["exponent"] for f in fits if f["energy_decay_theta"]["exponent"] is not None]
    fit_error = statistics.mean(f["clusters_decay_z"]["exponent_error"] for f in fits
                                if f["clusters_decay_z"]["exponent_error"] is not None)
    zm, ze = mean_and_sem(z)
    tm, te = mean_and_sem(theta)
    late = [1.0 / p["r_max_vs_size"]["slope"] for _, p in results if p and p["r_max_vs_size"]["slope"]]
    own = [p["mean_mass_radius_dimension"]["mean"] for _, p in results
           if p and p["mean_mass_radius_dimension"]["clusters"]]
    late_text = "{:.3f} ± {:.3f}".format(*mean_and_sem(late)) if late else ""
    own_text = "{:.3f} ± {:.3f}".format(*mean_and_sem(own)) if own else ""
    return (f"| {label} | {n} | {vf} | {len(z)} | {zm:.3f} ± {ze:.3f} | {fit_error:.3f} | {tm:.3f} ± {te:.3f} | "
            f"{2 * dimension / (dimension + 2):.3f} | {late_text} | {own_text} |")

if __name__ == "__main__":
    main()
