"""`make install` into a temporary prefix (cmake --install BUILD --prefix TMP): the binary,
the plotting script and the Python module land where they belong, the module imports from
outside the build tree with PYTHONPATH naming only the installed directory, runs a small
simulation, and the installed binary runs. With the default prefix /usr/local the same
directory is one that /usr/bin/python3 searches without PYTHONPATH.

Usage: check_install.py BUILD_DIR PYTHON_INSTALL_DIR (relative to the prefix)."""
import glob
import os
import subprocess
import sys
import tempfile

PYTHON = "/usr/bin/python3"

# A tiny run from the installed module: a few discs to one cluster, its file written.
SCRIPT = """
import sys, ballagg
assert ballagg.__file__.startswith(sys.argv[1]), ballagg.__file__
sim = ballagg.Simulation({"system": {"n": 30, "radius": 0.5, "volume_fraction": 0.1}})
result = sim.run()
assert result["stop_reason"] == "clusters" and sim.n_clusters == 1, result
print(ballagg.__version__, sim.n_clusters)
"""


def fail(message):
    print(f"check_install: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    build, module_dir = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory(prefix="ballagg-install-") as prefix:
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "DESTDIR")}
        subprocess.run(["cmake", "--install", build, "--prefix", prefix], check=True, env=env,
                       stdout=subprocess.DEVNULL)
        site = os.path.join(prefix, module_dir)
        modules = glob.glob(os.path.join(site, "ballagg*.so"))
        if len(modules) != 1:
            fail(f"expected one module ballagg*.so in {site}, found {modules}")
        for path in [os.path.join(prefix, "bin", "ballagg"), os.path.join(prefix, "share", "ballagg", "ballagg_plot.py")]:
            if not os.path.isfile(path):
                fail(f"{path} was not installed")
        # From a directory outside the build tree, PYTHONPATH naming only the installed one.
        run = subprocess.run([PYTHON, "-c", SCRIPT, site], cwd=prefix, env={**env, "PYTHONPATH": site},
                             capture_output=True, text=True)
        if run.returncode != 0:
            fail(f"the installed module does not run:\n{run.stderr}")
        binary = subprocess.run([os.path.join(prefix, "bin", "ballagg"), "run", "--quiet", "--set", "system.n=30",
                                 "--out", os.path.join(prefix, "run")], cwd=prefix, env=env, capture_output=True,
                                text=True)
        if binary.returncode != 0 or not os.path.isfile(os.path.join(prefix, "run", "summary.json")):
            fail(f"the installed binary does not run:\n{binary.stderr}")
    # The default prefix: a directory /usr/bin/python3 searches on its own.
    paths = subprocess.run([PYTHON, "-c", "import sys; print('\\n'.join(sys.path))"], env=env, check=True,
                           capture_output=True, text=True).stdout.split()
    default = os.path.join("/usr/local", module_dir)
    if default not in paths:
        fail(f"{default} (make install with the default prefix) is not on {PYTHON}'s sys.path: {paths}")
    print(f"installed and imported from {module_dir}: {run.stdout.strip()}")


if __name__ == "__main__":
    main()
