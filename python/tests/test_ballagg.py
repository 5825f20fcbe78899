"""The ballagg Python module: configurations, simulations with callbacks, numpy state,
the analysis functions and run directories, checked against physics and against the
command line (the same configuration and seed give the same bytes)."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import ballagg

BINARY = os.environ.get("BALLAGG_BINARY", "ballagg")


def small(**sections):
    """A small 2D system: 200 discs of radius 0.5 at volume fraction 0.2, random start."""
    config = {"system": {"n": 200, "radius": 0.5, "volume_fraction": 0.2},
              "initial": {"positions": "random", "seed": 3}}
    for section, keys in sections.items():
        config.setdefault(section, {}).update(keys)
    return config


# ---- configurations ----------------------------------------------------------------------

def test_config_from_dict_resolves_every_key():
    c = ballagg.Config({"system": {"n": 400, "dimension": 3}, "engine": {"kind": "ts"}})
    d = c.to_dict()
    assert d["system"]["n"] == 400 and d["system"]["dimension"] == 3
    assert d["engine"]["kind"] == "ts"
    assert c.dimension == 3
    assert "[output]" in c.to_toml()


def test_config_from_toml_file_with_overrides(tmp_path):
    path = tmp_path / "run.toml"
    path.write_text("[system]\nn = 50\nradius = 0.25\n")
    c = ballagg.Config(path, overrides={"stop": {"clusters": 5}})
    assert c.to_dict()["system"]["radius"] == 0.25
    assert c.to_dict()["stop"]["clusters"] == 5


def test_bad_values_raise_input_error_naming_the_key():
    with pytest.raises(ballagg.InputError, match="system.n"):
        ballagg.Config({"system": {"n": -3}})
    with pytest.raises(ballagg.InputError, match="nonsense"):
        ballagg.Config({"system": {"nonsense": 1}})
    with pytest.raises(ValueError):  # InputError is a ValueError
        ballagg.Config({"engine": {"kind": "warp"}})
    with pytest.raises(TypeError):
        ballagg.Config({"system": {"n": object()}})


# ---- simulations -------------------------------------------------------------------------

def test_state_arrays_have_the_shapes_and_values_of_the_configuration():
    sim = ballagg.Simulation(small())
    n = 200
    assert sim.positions.shape == (n, 2) and sim.velocities.shape == (n, 2)
    assert np.all(sim.radii == 0.5) and np.all(sim.masses == 1.0)
    assert np.all((sim.positions >= 0) & (sim.positions <= sim.box_length))
    assert len(np.unique(sim.cluster_ids)) == sim.n_clusters == n
    # Speed 1 in random directions (the default fixed_speed start).
    assert np.allclose(np.linalg.norm(sim.velocities, axis=1), 1.0)


def test_callback_every_k_events_sees_clusters_merge_with_momentum_conserved():
    sim = ballagg.Simulation(small(system={"boundary": "periodic"}, initial={"zero_momentum": True}))
    seen = []

    def watch(s):
        p = (s.masses[:, None] * s.velocities).sum(axis=0)
        seen.append((s.time, s.n_clusters, len(np.unique(s.cluster_ids)), np.abs(p).max()))

    result = sim.run(watch, every=10)
    assert result["stop_reason"] == "clusters" and sim.n_clusters == 1
    assert len(seen) == result["events"] // 10
    times, clusters, labels, momentum = zip(*seen)
    assert list(times) == sorted(times)
    assert list(clusters) == sorted(clusters, reverse=True)  # merging only
    assert clusters == labels                                  # cluster_ids agree with the count
    assert max(momentum) < 1e-9                                # a periodic box conserves momentum


def test_callback_returning_false_stops_the_run_and_run_continues():
    sim = ballagg.Simulation(small())
    result = sim.run(lambda s: s.n_clusters > 150)
    assert result["stop_reason"] == "callback" and sim.n_clusters == 150
    assert sim.run(clusters=100)["stop_reason"] == "clusters" and sim.n_clusters == 100


def test_run_from_its_own_callback_raises_and_the_simulation_goes_on():
    sim = ballagg.Simulation({"system": {"n": 100}})
    errors = []

    def reenter(s):
        try:
            s.run(time=1.0)
        except RuntimeError as e:
            errors.append(str(e))
        return False

    assert sim.run(reenter)["stop_reason"] == "callback"
    assert len(errors) == 1 and "from its callback" in errors[0]
    # Uncaught, the error ends the outer run; the simulation is still usable.
    with pytest.raises(RuntimeError, match="from its callback"):
        sim.run(lambda s: s.run(time=1.0))
    assert sim.run()["stop_reason"] == "clusters" and sim.n_clusters == 1


@pytest.mark.parametrize("argument, value", [
    ("clusters", 0), ("clusters", -5), ("time", math.nan), ("time", -1.0), ("time", 0.0), ("time", -math.inf),
    ("wall_seconds", math.nan), ("wall_seconds", -1.0), ("wall_seconds", 0.0)])
def test_run_refuses_the_stop_values_the_configuration_refuses(argument, value):
    sim = ballagg.Simulation({"system": {"n": 100}})
    with pytest.raises(ballagg.InputError) as python_error:
        sim.run(**{argument: value})
    with pytest.raises(ballagg.InputError) as config_error:
        ballagg.Config({"stop": {argument: value}})
    # The same rule and the same words, naming the Python argument.
    python_message, config_message = str(python_error.value), str(config_error.value)
    assert python_message.startswith(f"Simulation.run argument {argument} = ")
    assert python_message.split(": ")[-1] == config_message.split(": ")[-1]
    assert sim.time == 0.0 and sim.n_clusters == 100  # nothing ran


def test_state_file_with_overlapping_or_disconnected_glued_spheres_is_refused(tmp_path):
    def simulation_of(rows):
        path = tmp_path / "in.csv"
        path.write_text("x,y,vx,vy,radius,mass,cluster\n" + rows)
        return ballagg.Simulation({"system": {"box_length": 10.0},
                                   "initial": {"positions": "file", "file": str(path)}})

    assert simulation_of("1,1,0,0,0.5,1,0\n2,1,0,0,0.5,1,0\n").n_clusters == 1
    with pytest.raises(ballagg.InputError, match=r"in.csv:2: this sphere overlaps the sphere of line 3"):
        simulation_of("1,1,0,0,0.5,1,0\n1,1,0,0,0.5,1,0\n")
    with pytest.raises(ballagg.InputError, match=r"in.csv:3: this sphere of cluster 0 is not joined"):
        simulation_of("1,1,0,0,0.5,1,0\n3,1,0,0,0.5,1,0\n")


def test_run_accepts_an_unlimited_time():
    sim = ballagg.Simulation(small())
    assert sim.run(time=math.inf, wall_seconds=math.inf, clusters=150)["stop_reason"] == "clusters"


def test_time_stepping_engine_with_a_callback_every_step():
    sim = ballagg.Simulation(small(engine={"kind": "ts"}, stop={"clusters": 50}))
    steps = []
    result = sim.run(lambda s: steps.append(s.time), every=1)
    assert sim.engine == "ts" and result["steps"] == len(steps) > 0
    assert sim.max_overlap() <= sim.config.to_dict()["ts"]["eps_c"]


def test_3d_simulation_with_walls_accounts_for_wall_impulse():
    sim = ballagg.Simulation({"system": {"dimension": 3, "n": 300, "radius": 0.5},
                              "initial": {"positions": "random", "seed": 2}})
    p0 = sim.momentum
    sim.run()
    assert sim.dimension == 3 and sim.positions.shape == (300, 3)
    # Collisions conserve momentum; only the walls change it.
    assert np.allclose(sim.momentum - p0, sim.wall_impulse, atol=1e-9)


def test_python_run_equals_the_command_line_byte_for_byte(tmp_path):
    config = small()
    out = tmp_path / "cli"
    subprocess.run([BINARY, "run", "--quiet", "--out", str(out), "--set", "system.n=200", "--set",
                    "system.radius=0.5", "--set", "system.volume_fraction=0.2", "--set",
                    'initial.positions="random"', "--set", "initial.seed=3"], check=True)
    sim = ballagg.Simulation(config)
    sim.run()
    sim.write_state(str(tmp_path / "python.csv"))
    assert (tmp_path / "python.csv").read_bytes() == (out / "final.csv").read_bytes()


# ---- run directories ---------------------------------------------------------------------

def test_load_a_run_directory_and_verify_it(tmp_path):
    out = ballagg.run(small(output={"snapshot_every": 5.0}), out=str(tmp_path / "run"))
    run = ballagg.load(out)
    assert run.summary["n_clusters"] == 1
    assert run.timeseries["clusters"][0] == 200 and run.timeseries["clusters"][-1] == 1
    assert run.final["positions"].shape == (200, 2)
    assert run.n_frames >= 2
    first, last = run.frame(0), run.frame(-1)
    assert first["time"] == 0.0 and first["n_clusters"] == 200
    # trajectory.h5md stores single precision by default (output.snapshot_precision)
    assert np.array_equal(last["positions"], run.final["positions"].astype(np.float32))
    assert run.analyze()["n_spheres"] == 200
    report = ballagg.verify(out)
    assert report["violations"] == [] and report["checks"] > 10


def test_load_refuses_a_directory_that_is_not_a_run(tmp_path):
    with pytest.raises(ballagg.InputError, match="not a run directory"):
        ballagg.load(tmp_path)


@pytest.mark.parametrize("corrupt, message", [
    (lambda fields: ["abc"] + fields[1:], "timeseries.csv:3: column time: 'abc' is not a number"),
    (lambda fields: fields[:1] + [""] + fields[2:], "timeseries.csv:3: column clusters: '' is not a number"),
    (lambda fields: fields[:-1], "timeseries.csv:3: "),
], ids=["letters", "empty", "short-row"])
def test_load_refuses_a_time_series_with_a_field_that_is_not_a_number(tmp_path, corrupt, message):
    # The strict CSV reader of the command line: a bad field is an error naming the file
    # line and the column, never a 0 in the arrays or a shifted column.
    out = ballagg.run(small(), out=str(tmp_path / "run"))
    path = os.path.join(out, "timeseries.csv")
    with open(path) as f:
        lines = f.read().splitlines()
    lines[2] = ",".join(corrupt(lines[2].split(",")))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    with pytest.raises(ballagg.InputError, match=message):
        ballagg.load(out)


# ---- analysis functions ------------------------------------------------------------------

def test_gyration_of_a_rectangle_of_points():
    x = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 2.0]])
    g = ballagg.gyration_shape(x)
    assert np.allclose(g["centroid"], [2.0, 1.0])
    assert np.allclose(g["eigenvalues"], [4.0, 1.0])        # variances 2^2 and 1^2
    assert g["aspect_ratio"] == pytest.approx(4.0)
    assert g["radius_of_gyration"] == pytest.approx(math.sqrt(5.0))
    assert abs(g["orientation"][0]) == pytest.approx(1.0)


def test_box_counting_of_a_line_and_of_a_filled_square():
    t = np.linspace(0.0, 64.0, 4097)[:-1]
    line = np.column_stack([t, np.full_like(t, 32.0)])
    assert ballagg.box_counting(line, box_length=64.0, length_unit=0.1)["dimension"] == pytest.approx(1.0, abs=0.02)
    g = np.arange(0.0, 64.0, 0.25) + 0.125
    square = np.array([[a, b] for a in g for b in g])
    assert ballagg.box_counting(square, box_length=64.0, length_unit=0.1)["dimension"] == pytest.approx(2.0, abs=0.02)


def test_contacts_of_a_chain_of_three_touching_discs():
    x = np.array([[1.0, 1.0], [2.0, 1.0], [3.0, 1.0], [8.0, 8.0]])
    r = np.full(4, 0.5)
    c = ballagg.count_contacts(x, r, np.array([0, 0, 0, 1]), box_length=10.0)
    assert list(c["all"]) == [1, 2, 1, 0] and list(c["same_cluster"]) == [1, 2, 1, 0]
    assert c["relative"] == pytest.approx(4 / (4 * 6))
    assert ballagg.relative_contacts(4, 4, 2) == pytest.approx(c["relative"])


def test_partition_spectrum_and_largest_cluster():
    ids = np.array([7, 7, 3, 7, 3, 9])
    p = ballagg.partition_clusters(ids)
    assert list(p["label"]) == [0, 0, 1, 0, 1, 2]
    assert list(p["start"]) == [0, 3, 5, 6] and list(p["members"]) == [0, 1, 3, 2, 4, 5]
    spectrum = ballagg.mass_spectrum(ids)
    assert list(spectrum["size"]) == [1, 2, 3] and list(spectrum["clusters"]) == [1, 1, 1]
    assert ballagg.kth_largest_cluster(ids, 1) == 0 and ballagg.kth_largest_cluster(ids, 2) == 1


def test_unwrap_a_pair_across_the_periodic_face():
    x = np.array([[0.2, 5.0], [9.4, 5.0]])  # touching through x = 0 in a box of 10
    unwrapped, percolating = ballagg.unwrap_clusters(x, np.full(2, 0.4), np.array([0, 0]), box_length=10.0)
    assert abs(unwrapped[0, 0] - unwrapped[1, 0]) == pytest.approx(0.8)
    assert not percolating[0]


def test_mass_radius_and_pair_distribution_of_a_dense_disc_of_spheres():
    g = np.arange(-20.0, 20.5, 1.0)
    x = np.array([[a, b] for a in g for b in g if a * a + b * b <= 400.0]) + 50.0
    n = len(x)
    m = ballagg.mass_radius(np.arange(n), x, np.full(n, 0.5), np.ones(n), length_unit=0.5,
                            radius_of_gyration=ballagg.gyration_shape(x)["radius_of_gyration"])
    assert m["mass"] == n and m["dimension"] == pytest.approx(2.0, abs=0.1)  # a filled disc
    p = ballagg.pair_distribution(x, 0.5, np.zeros(n, dtype=int), 0, box_length=100.0)
    assert len(p["r"]) == len(p["all"]) == len(p["cluster"]) > 0


def test_fit_line_is_exact_on_a_line():
    f = ballagg.fit_line([1.0, 2.0, 3.0, 4.0], [3.0, 5.0, 7.0, 9.0])
    assert f["slope"] == pytest.approx(2.0) and f["intercept"] == pytest.approx(1.0)
    assert f["slope_error"] == pytest.approx(0.0, abs=1e-12)
    assert ballagg.fit_line([1.0], [1.0]) is None


def test_analyze_of_a_simulation_matches_the_loaded_run(tmp_path):
    out = ballagg.run(small(stop={"clusters": 20}), out=str(tmp_path / "run"))
    sim = ballagg.Simulation(small(stop={"clusters": 20}))
    sim.run()
    (a, a_tables), (b, b_tables) = sim.analyze(tables=True), ballagg.load(out).analyze(tables=True)
    assert a["all_spheres"]["contacts"] == b["all_spheres"]["contacts"]
    assert np.array_equal(a_tables["clusters"]["size"], b_tables["clusters"]["size"])
    assert a["all_spheres"]["box_counting"]["dimension"] == b["all_spheres"]["box_counting"]["dimension"]
    c = ballagg.analyze(sim.positions, sim.radii, sim.cluster_ids, sim.box_length, masses=sim.masses)
    assert c["all_spheres"]["contacts"] == a["all_spheres"]["contacts"]


def key_tree(value):
    """The keys and nesting of a JSON-like value: dicts by key, lists by position."""
    if isinstance(value, dict):
        return {k: key_tree(v) for k, v in value.items()}
    if isinstance(value, list):
        return [key_tree(v) for v in value]
    return None


def test_analyze_has_the_schema_and_values_of_analysis_json(tmp_path):
    for dimension in (2, 3):
        config = small(system={"dimension": dimension, "n": 150}, stop={"clusters": 30})
        out = ballagg.run(config, out=str(tmp_path / f"run{dimension}"))
        subprocess.run([BINARY, "analyze", "--quiet", out], check=True)
        with open(os.path.join(out, "analysis.json")) as f:
            written = json.load(f)
        sim = ballagg.Simulation(config)
        sim.run()
        from_simulation = sim.analyze()
        from_run = ballagg.load(out).analyze()
        assert list(from_simulation) == list(written)  # the same keys in the same order
        assert key_tree(from_simulation) == key_tree(written) == key_tree(from_run)
        assert from_run == written
        assert from_simulation["state_file"] is None
        assert {**from_simulation, "state_file": written["state_file"]} == written
        _, tables = ballagg.load(out).analyze(tables=True)
        assert sorted(f"{name}.csv" for name in tables) == sorted(written["files"])
        for name, columns in tables.items():
            on_disk = np.genfromtxt(os.path.join(out, f"{name}.csv"), delimiter=",", names=True, dtype=None,
                                    encoding="utf-8")
            assert list(columns) == list(on_disk.dtype.names)
            for column, values in columns.items():
                expected = np.atleast_1d(on_disk[column])
                if values.dtype.kind in "iuf":
                    assert np.array_equal(values, expected.astype(values.dtype), equal_nan=True), (name, column)
                else:
                    assert list(values) == [str(v) for v in expected], (name, column)


def test_kinetics_of_a_loaded_run_is_what_analyze_kinetics_writes(tmp_path):
    config = small(system={"n": 600, "volume_fraction": 0.05}, output={"snapshot_every": 20.0})
    out = ballagg.run(config, out=str(tmp_path / "run"))
    subprocess.run([BINARY, "analyze", "--quiet", "--frames", out], check=True)
    for window in (None, (5.0, 200.0)):
        args = ["--window", f"{window[0]},{window[1]}"] if window else []
        subprocess.run([BINARY, "analyze", "--quiet", "--kinetics", *args, out], check=True)
        with open(os.path.join(out, "kinetics.json")) as f:
            written = json.load(f)
        fits, tables = ballagg.load(out).kinetics(window=window, tables=True)
        assert fits == written == ballagg.load(out).kinetics(window)
        assert fits["clusters_decay_z"]["exponent"] > 0  # clusters only ever merge
        on_disk = np.genfromtxt(os.path.join(out, "kinetics_collapse.csv"), delimiter=",", names=True)
        assert list(tables["kinetics_collapse"]) == list(on_disk.dtype.names)
        for column, values in tables["kinetics_collapse"].items():
            assert np.array_equal(values, on_disk[column]), column
    with pytest.raises(ballagg.InputError, match="--window 3,2"):
        ballagg.load(out).kinetics(window=(3.0, 2.0))


# ---- rigid bodies (engine.kind = "rigid-body") -------------------------------------------

def rigid(dimension=3, **sections):
    config = {"system": {"dimension": dimension, "n": 300, "radius": 0.5, "volume_fraction": 0.03,
                         "boundary": "periodic"},
              "initial": {"positions": "random", "velocities": "gaussian", "zero_momentum": True, "seed": 4},
              "engine": {"kind": "rigid-body"}, "stop": {"clusters": 100}}
    for section, keys in sections.items():
        config.setdefault(section, {}).update(keys)
    return config


def test_rigid_bodies_seen_from_a_callback_rotate_rigidly_without_overlaps():
    sim = ballagg.Simulation(rigid())
    seen = []

    def look(s):
        # Positions are those of the callback's instant (the engine rotates the bodies for
        # it): no overlap beyond the contact tolerance, and each sphere moves as a point of
        # its rigid body, v_i - v_j = omega x (x_i - x_j).
        assert (s.max_overlap() or 0.0) < 1e-9
        x, v, w, ids = s.unwrapped_positions, s.velocities, s.angular_velocities, s.cluster_ids
        big = np.bincount(ids).argmax()
        members = np.flatnonzero(ids == big)
        assert np.all(w[members] == w[members[0]])
        if len(members) > 1:
            i, j = members[0], members[-1]
            assert np.allclose(v[i] - v[j], np.cross(w[i], x[i] - x[j]), rtol=0, atol=1e-9 * (1 + np.abs(v).max()))
        seen.append(s.kinetic_energy + s.rotational_energy)

    result = sim.run(look, every=200)
    assert result["stop_reason"] == "clusters" and sim.n_clusters == 100
    assert len(seen) > 3
    assert all(b <= a * (1 + 1e-12) for a, b in zip(seen, seen[1:]))  # sticking dissipates
    assert sim.rotational_energy > 0.0 and sim.angular_velocities.shape == (300, 3)
    assert np.abs(sim.momentum).max() < 1e-9 * np.abs(sim.velocities).sum()  # zero total, kept


def test_rigid_body_run_loads_with_spins_and_verifies(tmp_path):
    for dimension, shape in [(3, (300, 3)), (2, (300,))]:
        out = ballagg.run(rigid(dimension), out=str(tmp_path / f"run{dimension}"))
        run = ballagg.load(out)
        w, ids = run.final["angular_velocities"], run.final["cluster_ids"]
        assert w.shape == shape
        for c in np.unique(ids):
            assert np.all(w[ids == c] == w[ids == c][0])  # one spin per body
        assert np.abs(w).max() > 0.0
        report = ballagg.verify(out)
        assert report["violations"] == [] and report["checks"] > 20
    assert "angular_velocities" not in ballagg.load(ballagg.run(small(), out=str(tmp_path / "ed"))).final


# ---- where the module writes -------------------------------------------------------------

def test_write_state_never_replaces_a_fifo_or_a_link(tmp_path):
    sim = ballagg.Simulation(small())
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    with pytest.raises(ballagg.OutputError, match="it is a FIFO"):
        sim.write_state(str(fifo))
    assert os.path.exists(fifo) and not os.path.isfile(fifo)
    target = tmp_path / "target.csv"
    target.write_text("the target\n")
    (tmp_path / "link.csv").symlink_to(target)
    with pytest.raises(OSError, match="it is a symbolic link"):
        sim.write_state(str(tmp_path / "link.csv"))
    assert os.path.islink(tmp_path / "link.csv") and target.read_text() == "the target\n"


# Run by ctest as a test of its own (PythonModuleAsRoot), so that its skip is reported.
def test_write_state_never_replaces_a_device(tmp_path):
    if os.geteuid() != 0:
        pytest.skip("creating a device node (mknod) needs root")
    sim = ballagg.Simulation(small())
    device = tmp_path / "full"
    os.mknod(device, 0o666 | 0o020000, os.makedev(1, 7))  # a copy of /dev/full
    with pytest.raises(ballagg.OutputError, match="it is a character device"):
        sim.write_state(str(device))
    assert not os.path.isfile(device) and os.path.exists(device)


def test_run_refuses_a_directory_holding_another_run_unless_overwrite(tmp_path):
    out = str(tmp_path / "run")
    ballagg.run(small(stop={"clusters": 150}), out=out)
    summary = (tmp_path / "run" / "summary.json").read_text()
    with pytest.raises(ballagg.InputError, match="holds another run"):
        ballagg.run(small(initial={"seed": 9}), out=out)
    assert (tmp_path / "run" / "summary.json").read_text() == summary
    ballagg.run(small(initial={"seed": 9}, stop={"clusters": 150}), out=out, overwrite=True)
    assert '"seed": 9' in (tmp_path / "run" / "summary.json").read_text()


# ---- values and keys as Python gives them ------------------------------------------------

@pytest.mark.parametrize("sections, message", [
    ({"system": {"nn": 1}}, r"^system\.nn: unknown key 'system\.nn' \(keys of \[system\]"),
    ({"system": {"n": -3}}, r"^system\.n = -3: must be an integer from 1 to"),
    ({"stop": {"time": "x"}}, r"^stop\.time = \"x\": must be a number > 0"),
    ({"warp": {"a": 1}}, r"^warp: unknown section \[warp\]"),
])
def test_errors_name_the_python_key_not_the_command_line(sections, message):
    for given in ({"config": sections}, {"config": None, "overrides": sections}):
        with pytest.raises(ballagg.InputError, match=message) as error:
            ballagg.Config(given["config"], overrides=given.get("overrides"))
        assert "--set" not in str(error.value) and "\n" not in str(error.value)


def test_numpy_scalars_and_arrays_are_configuration_values():
    c = ballagg.Config({"system": {"n": np.int64(50), "dimension": np.int32(3), "radius": np.float32(0.5),
                                   "mass": np.float64(2.0)},
                        "initial": {"seed": np.uint16(7), "zero_momentum": np.bool_(True)},
                        "output": {"snapshot_formats": np.array(["h5md", "xyz"])}}).to_dict()
    assert c["system"]["n"] == 50 and c["system"]["dimension"] == 3
    assert c["system"]["radius"] == 0.5 and c["system"]["mass"] == 2.0
    assert c["initial"]["seed"] == 7 and c["initial"]["zero_momentum"] is True
    assert c["output"]["snapshot_formats"] == ["h5md", "xyz"]
    sim = ballagg.Simulation({"system": {"n": np.int64(30)}})
    assert sim.n_spheres == 30


@pytest.mark.parametrize("value", [100.0, np.float64(100.0), np.float32(100.0)])
def test_a_float_for_an_integer_key_is_refused(value):
    with pytest.raises(ballagg.InputError, match=r"^system\.n = 100\.0: must be an integer \(a Python int or a numpy "
                                                  r"integer\), not a float$"):
        ballagg.Config({"system": {"n": value}})
    with pytest.raises(ballagg.InputError, match=r"^stop\.clusters = 100\.0: must be an integer"):
        ballagg.Simulation(None, overrides={"stop": {"clusters": value}})
    assert ballagg.Config({"stop": {"time": 3}}).to_dict()["stop"]["time"] == 3.0  # an int for a float key


def test_a_section_that_is_not_a_dict_is_a_type_error():
    with pytest.raises(TypeError, match=r"^n: a int where a section's dict of keys belongs"):
        ballagg.Config({"n": 100})
    with pytest.raises(TypeError, match=r"^system\.n: a object is not a configuration value"):
        ballagg.Config({"system": {"n": object()}})


def test_box_counting_length_unit_defaults_to_the_sphere_radius():
    t = np.linspace(0.0, 64.0, 4097)[:-1]
    line = np.column_stack([t, np.full_like(t, 32.0)])
    radii = np.full(len(t), 0.1)
    by_radii = ballagg.box_counting(line, box_length=64.0, radii=radii)
    by_unit = ballagg.box_counting(line, box_length=64.0, length_unit=0.1)
    assert np.array_equal(by_radii["fitted"], by_unit["fitted"]) and by_radii["dimension"] == by_unit["dimension"]
    default = ballagg.box_counting(line, box_length=64.0)  # R = 0.2, the default system.radius
    assert np.array_equal(default["fitted"], ballagg.box_counting(line, box_length=64.0, length_unit=0.2)["fitted"])
    assert not np.array_equal(default["fitted"], by_unit["fitted"])  # the unit sets the fitted range
    # As `ballagg analyze`: its box counting over all spheres uses R of the spheres.
    sim = ballagg.Simulation(small(stop={"clusters": 20}))
    sim.run()
    a = sim.analyze()
    ours = ballagg.box_counting(sim.positions, sim.box_length, radii=sim.radii)
    assert ours["dimension"] == a["all_spheres"]["box_counting"]["dimension"]
    with pytest.raises(ValueError, match="length_unit = -1: must be a number > 0"):
        ballagg.box_counting(line, box_length=64.0, length_unit=-1.0)


# ---- callbacks in simulated time, output files ---------------------------------------------

@pytest.mark.parametrize("engine", ["ed", "ts", "rigid-body"])
def test_callback_every_time_sees_the_state_at_exact_multiples(tmp_path, engine):
    config = small(engine={"kind": engine}, stop={"time": 3.0},
                   output={"snapshot_every": 0.5, "snapshot_precision": "double"})
    seen = []
    sim = ballagg.Simulation(config)
    result = sim.run(lambda s: seen.append((s.time, s.positions, s.velocities, s.n_clusters)), every_time=0.5)
    assert result["stop_reason"] == "time" and sim.time == 3.0
    assert [t for t, *_ in seen] == [0.5 * k for k in range(1, 7)]
    # The frames of `ballagg run` at the same times (double precision) hold the same state.
    run = ballagg.load(ballagg.run(config, out=str(tmp_path / "run")))
    for k, (t, x, v, clusters) in enumerate(seen, start=1):
        frame = run.frame(k)
        assert frame["time"] == t
        assert np.array_equal(frame["positions"], x) and np.array_equal(frame["velocities"], v)
        assert frame["n_clusters"] == clusters
    again = []
    ballagg.Simulation(config).run(lambda s: again.append((s.time, s.positions)), every_time=0.5)
    assert all(a[0] == b[0] and np.array_equal(a[1], b[1]) for a, b in zip(seen, again))  # deterministic


def test_callback_every_time_ends_the_run_at_its_time_and_run_goes_on():
    sim = ballagg.Simulation(small(stop={"time": 4.0}))
    times = []

    def until_1_5(s):
        times.append(s.time)
        return s.time < 1.5

    assert sim.run(until_1_5, every_time=0.25)["stop_reason"] == "callback"
    assert sim.time == 1.5 and times[-1] == 1.5
    x = sim.positions
    assert sim.run(lambda s: times.append(s.time), every_time=0.25, time=2.0)["stop_reason"] == "time"
    assert times == [0.25 * k for k in range(1, 9)]
    assert not np.array_equal(x, sim.positions)


@pytest.mark.parametrize("arguments, error, message", [
    ({"every": 2, "every_time": 0.5}, ValueError, "not both"),
    ({"every_time": 0.0}, ballagg.InputError, r"every_time = 0: must be a number > 0"),
    ({"every_time": -1.0}, ballagg.InputError, r"every_time = -1: must be a number > 0"),
    ({"every_time": math.nan}, ballagg.InputError, r"every_time = nan: must be a number > 0"),
    ({"every_time": math.inf}, ballagg.InputError, r"every_time = inf: must be finite"),
    ({"every": 0}, ValueError, r"every = 0: must be an integer >= 1"),
])
def test_run_refuses_bad_callback_intervals(arguments, error, message):
    sim = ballagg.Simulation(small())
    with pytest.raises(error, match=message):
        sim.run(lambda s: None, **arguments)
    assert sim.time == 0.0


def test_simulation_writes_the_output_files_of_ballagg_run(tmp_path):
    config = small(output={"snapshot_every": 2.0, "snapshot_formats": ["h5md", "xyz", "gsd"],
                           "timeseries_interval": 1.0})
    cli = ballagg.run(config, out=str(tmp_path / "cli"))
    sim = ballagg.Simulation(config)
    seen = []
    assert sim.run(lambda s: seen.append(s.time), every_time=1.0, out=tmp_path / "python")["stop_reason"] == "clusters"
    written = sorted(os.listdir(tmp_path / "python"))
    assert written == ["timeseries.csv", "trajectory.gsd", "trajectory.h5md", "trajectory.xyz"]
    for name in written:
        assert (tmp_path / "python" / name).read_bytes() == open(os.path.join(cli, name), "rb").read(), name
    assert len(seen) == int(sim.time)
    # Another run's files are kept unless overwrite=True.
    with pytest.raises(ballagg.InputError, match="holds another run"):
        ballagg.Simulation(config).run(out=tmp_path / "python")
    ballagg.Simulation(config).run(out=tmp_path / "python", overwrite=True)


def test_output_of_a_run_whose_callback_fails_is_not_left_behind(tmp_path):
    sim = ballagg.Simulation(small(output={"snapshot_every": 0.5}))

    def fail(s):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        sim.run(fail, every_time=1.0, out=tmp_path / "out")
    assert not os.path.exists(tmp_path / "out")


def test_output_of_a_run_ended_by_its_callback_ends_at_that_time(tmp_path):
    config = small(output={"snapshot_every": 0.5, "snapshot_precision": "double"})
    sim = ballagg.Simulation(config)
    assert sim.run(lambda s: s.time < 2.0, every_time=1.0, out=tmp_path / "out")["stop_reason"] == "callback"
    import h5py  # Debian's python3-h5py, as tests/io/check_h5md.py
    with h5py.File(tmp_path / "out" / "trajectory.h5md", "r") as f:
        times = list(f["particles/all/position/time"][()])
        last = f["particles/all/position/value"][-1]
    assert times == [0.5 * k for k in range(5)]
    assert np.array_equal(last, sim.positions)


# ---- a state from numpy arrays -----------------------------------------------------------

def test_state_from_arrays_runs_as_the_same_state_file(tmp_path):
    """Arrays and the state file of the same spheres give the same run, byte for byte."""
    start = ballagg.Simulation(small(system={"boundary": "periodic"}))
    start.run(clusters=150)  # some glued clusters
    x, v, r, m, ids = start.positions, start.velocities, start.radii, start.masses, start.cluster_ids
    start.write_state(str(tmp_path / "start.csv"))
    physics = {"system": {"boundary": "periodic"}, "output": {"timeseries_interval": 0.5}}
    from_file = ballagg.Simulation({**physics, "system": {"boundary": "periodic", "box_length": start.box_length},
                                    "initial": {"positions": "file", "file": str(tmp_path / "start.csv")}})
    state = ballagg.State.from_arrays(x, v, r, m, ids, box_length=start.box_length)
    assert state.dimension == 2 and state.n_spheres == 200 and state.box_length == start.box_length
    from_arrays = ballagg.Simulation(physics, state=state)
    assert from_arrays.n_clusters == from_file.n_clusters == 150
    from_file.run(out=tmp_path / "file")
    from_arrays.run(out=tmp_path / "arrays")
    from_file.write_state(str(tmp_path / "file" / "final.csv"))
    from_arrays.write_state(str(tmp_path / "arrays" / "final.csv"))
    for name in ["final.csv", "timeseries.csv"]:
        assert (tmp_path / "file" / name).read_bytes() == (tmp_path / "arrays" / name).read_bytes(), name
    assert from_arrays.n_clusters == 1


def test_state_from_arrays_in_3d_with_spins_and_integer_ids_of_any_kind():
    x = np.array([[2.0, 2.0, 2.0], [3.0, 2.0, 2.0], [7.0, 7.0, 7.0]])
    v = np.array([[0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [-0.5, -0.5, 0.0]])
    w = np.array([[0.0, 0.0, 0.1], [0.0, 0.0, 0.1], [0.0, 0.0, 0.0]])
    state = ballagg.State.from_arrays(x, v, np.full(3, 0.5), np.ones(3), np.array([4, 4, 9], dtype=np.int32),
                                      box_length=10.0, angular_velocities=w)
    sim = ballagg.Simulation({"system": {"dimension": 3}, "engine": {"kind": "rigid-body"}}, state=state)
    assert sim.n_clusters == 2 and sim.dimension == 3
    assert np.allclose(sim.angular_velocities[:2], [[0.0, 0.0, 0.1]] * 2)


@pytest.mark.parametrize("change, message", [
    (lambda a: a["radii"].__setitem__(3, 1e102), r"^radii\[3\]: 1e\+102 is outside \["),
    (lambda a: a["masses"].__setitem__(5, 0.0), r"^masses\[5\]: 0 is outside \["),
    (lambda a: a["velocities"].__setitem__(2, [1e300, 0.0]), r"^velocities\[2\]: the speed 1e\+300 is above"),
    (lambda a: a["positions"].__setitem__(1, [np.nan, 1.0]), r"^positions\[1, 0\] = nan: must be a finite number"),
    (lambda a: a["radii"].__setitem__(0, np.inf), r"^radii\[0\] = inf: must be a finite number"),
    (lambda a: a["positions"].__setitem__(1, a["positions"][0] + [0.1, 0.0]),
     r"^sphere 0: this sphere overlaps sphere 1 by 0\.9 of their contact distance"),
    (lambda a: a["positions"].__setitem__(2, [-30.0, 5.0]), r"^positions\[2, 0\]: -30 is more than \S+ box length"),
])
def test_state_from_arrays_errors_name_the_array_and_the_index(change, message):
    arrays = {"positions": np.array([[1.0 + 2.0 * k, 5.0] for k in range(6)]), "velocities": np.zeros((6, 2)),
              "radii": np.full(6, 0.5), "masses": np.ones(6)}
    change(arrays)
    with pytest.raises(ballagg.InputError, match=message) as error:
        state = ballagg.State.from_arrays(**arrays, box_length=12.0)
        ballagg.Simulation({"system": {"boundary": "periodic"}}, state=state)
    assert "\n" not in str(error.value)


def test_state_from_arrays_refuses_shapes_and_kinds_that_do_not_fit():
    x, v, r, m = np.array([[1.0, 1.0], [3.0, 1.0]]), np.zeros((2, 2)), np.full(2, 0.5), np.ones(2)
    with pytest.raises(ValueError, match=r"velocities must be an \(2, 2\) array"):
        ballagg.State.from_arrays(x, np.zeros((2, 3)), r, m, box_length=10.0)
    with pytest.raises(ValueError, match="radii must be a 1-d array of length 2"):
        ballagg.State.from_arrays(x, v, np.full(3, 0.5), m, box_length=10.0)
    with pytest.raises(TypeError, match="cluster_ids must be an array of integers"):
        ballagg.State.from_arrays(x, v, r, m, np.array([0.0, 1.0]), box_length=10.0)
    with pytest.raises(ballagg.InputError, match=r"box_length = -1: must be a number > 0"):
        ballagg.State.from_arrays(x, v, r, m, box_length=-1.0)
    state = ballagg.State.from_arrays(x, v, r, m, box_length=10.0)
    with pytest.raises(ballagg.InputError, match=r"the state is 2D .*, the configuration 3D"):
        ballagg.Simulation({"system": {"dimension": 3}}, state=state)
    with pytest.raises(ballagg.InputError, match=r"sphere 1: velocity \(1, 0\) differs from \(0, 0\)"):
        ballagg.Simulation(None, state=ballagg.State.from_arrays(x, np.array([[0.0, 0.0], [1.0, 0.0]]), r, m,
                                                                  [7, 7], box_length=10.0))
