"""The fractal validation set of Degond et al. 2023, Fig. 10, through `ballagg analyze`.

Usage: /usr/bin/python3 bench/fractal_validation.py [build/bin/ballagg]
Writes each set as a state file and a configuration into a temporary directory, analyses
it, and prints the table of docs/analysis.md (box-counting and mass-radius dimensions).
"""
import json
import math
import os
import subprocess
import sys
import tempfile

BINARY = sys.argv[1] if len(sys.argv) > 1 else "build/bin/ballagg"


def write_set(directory, name, centres, r, box, dimension=2):
    axes = "xyz"[:dimension]
    with open(os.path.join(directory, name + ".csv"), "w") as f:
        f.write(",".join(axes) + "," + ",".join("v" + a for a in axes) + ",radius,mass,cluster\n")
        for c in centres:
            f.write(",".join(f"{v!r}" for v in c) + "," + ",".join("0" for _ in axes) + f",{r!r},1,0\n")
    with open(os.path.join(directory, name + ".toml"), "w") as f:
        f.write(f"[system]\ndimension = {dimension}\nbox_length = {box!r}\nradius = {r!r}\n")


def sierpinski(levels, r):
    rows = 1 << levels
    return [(r + ((rows - 1 - i) + 2 * j) * r, r + (rows - 1 - i) * math.sqrt(3) * r)
            for i in range(rows) for j in range(i + 1) if (j & (i - j)) == 0]


def sets():
    L = 120.0
    for n, r in ((300, 0.2), (1000, 0.06)):
        yield (f"3 lines across the box, {3 * n} spheres, R = {r}",
               [(r + 2 * r * k, y) for y in (L / 6, L / 2, 5 * L / 6) for k in range(n)], r, L, 2, "1")
    yield ("1 line across the box, 300 spheres, R = 0.2", [(0.2 + 0.4 * k, 37.0) for k in range(300)], 0.2, L, 2, "1")
    r = 2.0
    yield ("30 x 30 touching spheres filling the box, R = 2",
           [(r + 2 * r * i, r + 2 * r * j) for i in range(30) for j in range(30)], r, L, 2, "2")
    r = 1.0
    yield ("30 x 30 touching spheres, R = 1, centred (side L/2)",
           [(30 + r + 2 * r * i, 30 + r + 2 * r * j) for i in range(30) for j in range(30)], r, L, 2, "2")
    r = 1.0
    yield ("32^3 touching spheres filling a box of 64, R = 1",
           [(r + 2 * r * i, r + 2 * r * j, r + 2 * r * k) for i in range(32) for j in range(32) for k in range(32)],
           r, 64.0, 3, "3")
    r = 0.5
    yield ("Sierpinski triangle, 3^7 = 2187 touching spheres, box one row wider", sierpinski(7, r), r, 2 * r * 129, 2,
           "log 3 / log 2 = 1.585")


def box_text(b):
    """D_f +- its error (levels fitted), as the tables print it."""
    if b["dimension"] is None:
        return f"withheld: {b['flaw']}"
    err = b["dimension_error"]
    return f"{b['dimension']:.3f}" + (f" ± {err:.3f}" if err and err >= 5e-4 else "") + f" ({b['levels_fitted']})"


def main():
    print("| set | box counting D_f, all spheres (levels fitted) | box counting D_f, the cluster (levels) "
          "| mass-radius f_D | expected |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        for k, (label, centres, r, box, dim, expected) in enumerate(sets()):
            name = f"set{k}"
            write_set(d, name, centres, r, box, dim)
            out = os.path.join(d, name + "_out")
            subprocess.run([BINARY, "analyze", "--state", os.path.join(d, name + ".csv"), "--config",
                            os.path.join(d, name + ".toml"), "--out", out], check=True, stdout=subprocess.DEVNULL)
            a = json.load(open(os.path.join(out, "analysis.json")))
            largest = a["largest_cluster"]
            mr = largest["mass_radius_dimension"]
            mr_text = f"{mr:.3f}" if mr is not None else \
                f"withheld: {largest['mass_radius_dimension_flaw']} (raw fit {largest['mass_radius_fit']['slope']:.3f})"
            print(f"| {label} | {box_text(a['all_spheres']['box_counting'])} | {box_text(largest['box_counting'])} "
                  f"| {mr_text} | {expected} |")


if __name__ == "__main__":
    main()
