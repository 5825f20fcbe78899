#!/usr/bin/python3
"""The paper's fractal dimension against N (Degond et al. 2023, §4.2, the D_f panel of the
Table 1 study): the 2D set-up of Table 1 (lattice start, speed 1, R = 0.2, walls, Vf = 0.2)
run to one cluster by the event-driven engine, D_f by box counting (4.7), mean and
standard error over realizations. docs/python.md walks through it.

Usage: PYTHONPATH=build/python /usr/bin/python3 python/examples/fractal_dimension.py [OUT.png]
"""
import sys

import numpy as np

import ballagg

SIZES = [100, 400, 900, 2500]
REALIZATIONS = 10
VOLUME_FRACTION = 0.2

rows = []
for n in SIZES:
    dims = []
    for k in range(REALIZATIONS):
        sim = ballagg.Simulation({"system": {"n": n, "volume_fraction": VOLUME_FRACTION},
                                  "initial": {"seed": 1 + k}})   # the seeds of docs/validation.md
        sim.run()                                                 # to one cluster
        dims.append(sim.analyze()["all_spheres"]["box_counting"]["dimension"])  # (4.7), 3R <= eps <= L/2
    dims = np.array(dims)
    rows.append((n, dims.mean(), dims.std(ddof=1) / np.sqrt(len(dims))))
    print(f"N = {n:5d}: D_f = {rows[-1][1]:.4f} +- {rows[-1][2]:.4f}")

if len(sys.argv) > 1:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n, mean, error = map(np.array, zip(*rows))
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.errorbar(n, mean, yerr=error, marker="o", capsize=3, label=f"ED, Vf = {VOLUME_FRACTION}")
    ax.set_xscale("log")
    ax.set_xlabel("N")
    ax.set_ylabel("box-counting dimension $D_f$")
    ax.legend()
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=120)
