"""The Simulation class: construction, arrays, runs, writing, pickling, bad input."""

import copy
import re
import pickle
import subprocess

import numpy as np
import pytest

import edmd
from conftest import DATA


def small_fluid(dim=2, seed=1):
    return edmd.gen.fluid(n=64, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=seed)


def test_arrays_round_trip_exactly():
    rng = np.random.default_rng(5)
    # Discs on a grid, far apart, with random velocities and masses.
    g = np.arange(5) * 2.0 + 1.0
    pos = np.array([(x, y) for x in g for y in g]) + rng.uniform(-0.3, 0.3, (25, 2))
    vel = rng.normal(size=(25, 2))
    radii = rng.uniform(0.2, 0.4, 25)
    masses = rng.uniform(0.5, 2.0, 25)
    species = np.arange(25) % 3
    sim = edmd.Simulation.from_arrays(
        pos, vel, radii, masses=masses, box=(10.0, 10.0), boundary=("walls", "periodic"),
        species=species,
    )
    assert sim.dim == 2 and sim.n == 25 and len(sim) == 25
    assert np.array_equal(sim.positions, pos)
    assert np.array_equal(sim.velocities, vel)
    assert np.array_equal(sim.radii, radii)
    assert np.array_equal(sim.masses, masses)
    assert np.array_equal(sim.species, species)
    assert sim.positions.dtype == np.float64 and sim.positions.shape == (25, 2)
    assert sim.species.dtype == np.uint16
    assert tuple(sim.box) == (10.0, 10.0)
    assert tuple(sim.boundary) == ("walls", "periodic")
    assert sim.time == 0.0
    new_v = rng.normal(size=(25, 2))
    sim.velocities = new_v
    assert np.array_equal(sim.velocities, new_v)


def test_spheres_from_arrays():
    pos = [[2.0, 5.0, 5.0], [8.0, 5.0, 5.0]]
    vel = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    sim = edmd.Simulation.from_arrays(pos, vel, 1.0, box=(10, 10, 10), boundary="walls")
    assert sim.dim == 3
    sim.run(until=2.5)
    assert sim.stats["disc_disc"] == 1
    # Head-on, equal masses: the velocities are exchanged.
    assert np.array_equal(sim.velocities, [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    assert sim.time == 2.5


def test_chunks_do_not_change_the_trajectory():
    a = small_fluid()
    b = small_fluid()
    a.run(until=40.0)
    for t in np.linspace(0.3, 40.0, 37):
        b.run(until=float(t))
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.velocities, b.velocities)
    assert a.stats["disc_disc"] == b.stats["disc_disc"]


def test_run_events():
    sim = small_fluid(dim=3)
    sim.run(events=5000)
    s = sim.stats
    assert s["disc_disc"] + s["wall"] + s["cell_crossing"] + s["barrier"] == 5000


def test_velocity_change_reschedules():
    # Reversing every velocity and running as long again comes back to the start.
    sim = small_fluid()
    x0 = sim.positions
    sim.run(until=5.0)
    sim.velocities = -sim.velocities
    sim.run(until=10.0)
    assert np.allclose(sim.positions, x0, atol=1e-6)


@pytest.mark.parametrize("dim", [2, 3])
def test_pickle_mid_run_continues_bit_for_bit(dim):
    sim = small_fluid(dim)
    sim.run(until=7.3)
    restored = pickle.loads(pickle.dumps(sim))
    copied = copy.deepcopy(sim)
    assert restored.time == sim.time and restored.stats == sim.stats
    for s in (sim, restored, copied):
        s.run(until=30.0)
    for s in (restored, copied):
        assert np.array_equal(s.positions, sim.positions)
        assert np.array_equal(s.unwrapped_positions, sim.unwrapped_positions)
        assert np.array_equal(s.velocities, sim.velocities)
        assert s.stats == sim.stats


def test_pickle_after_new_velocities_continues_bit_for_bit():
    # A checkpoint carries the mean kinetic energy, checked on reading against the particles':
    # velocities set from Python (a quench or a heating) set it again, so the pickle reads back.
    sim = small_fluid(3)
    sim.run(until=2.0)
    sim.velocities = 2.5 * sim.velocities
    restored = pickle.loads(pickle.dumps(sim))
    for s in (sim, restored):
        s.run(until=6.0)
    assert np.array_equal(restored.positions, sim.positions)
    assert restored.stats == sim.stats


def test_pickle_keeps_the_measurements_under_way():
    sim = small_fluid()
    sim.measure("pressure", "collisions", "msd", every=0.5)
    sim.run(until=7.3)
    restored = pickle.loads(pickle.dumps(sim))
    for s in (sim, restored):
        s.run(until=20.0)
    a, b = sim.results(), restored.results()
    assert a["pressure"]["Z"]["blocks"] > 20
    assert a["pressure"] == b["pressure"] and a["collisions"] == b["collisions"]
    for name, table in a["tables"].items():
        for column, values in table.items():
            assert np.array_equal(values, b["tables"][name][column], equal_nan=True), (name, column)


def test_a_clock_that_stops_raises_value_error():
    # A column of touching discs filling the box's height between walls: every collision
    # happens at t = 0 again (README, "Exactness").
    n = 10
    pos = [[0.5, 0.5 + k] for k in range(n)]
    vel = [[0.0, 1.0 if k == 0 else 0.0] for k in range(n)]
    sim = edmd.Simulation.from_arrays(pos, vel, radii=0.5, box=(2.0, float(n)), boundary="walls")
    with pytest.raises(ValueError, match="clock stopped"):
        sim.run(until=1.0)


def test_checkpoint_file_continues(tmp_path):
    sim = small_fluid()
    sim.run(until=3.0)
    ck = tmp_path / "state.ck"
    sim.write(ck)
    later = edmd.Simulation.from_file(ck)
    assert later.time == 3.0
    sim.run(until=9.0)
    later.run(until=9.0)
    assert np.array_equal(sim.positions, later.positions)


def test_python_and_cli_end_in_the_same_state(tmp_path, edmd_cli):
    for name in ("gas-300.txt", "spheres-500.txt"):
        out = tmp_path / ("cli-" + name)
        subprocess.run(
            [edmd_cli, "run", str(DATA / name), "--until", "5", "--output", str(out)],
            check=True, capture_output=True,
        )
        sim = edmd.Simulation.from_file(DATA / name)
        sim.run(until=5.0)
        mine = tmp_path / ("py-" + name)
        sim.write(mine)
        assert mine.read_bytes() == out.read_bytes()
        cli = edmd.Simulation.from_file(out)
        assert np.array_equal(cli.positions, sim.positions)
        assert np.array_equal(cli.velocities, sim.velocities)


def test_swap_rule_course_file_and_trajectory_match_the_cli(tmp_path, edmd_cli):
    src = DATA / "course-7.txt"
    out, traj = tmp_path / "cli.txt", tmp_path / "cli.xyz"
    subprocess.run(
        [edmd_cli, "run", str(src), "--until", "3", "--rule", "swap", "--output", str(out),
         "--trajectory", str(traj), "--every", "0.25"],
        check=True, capture_output=True,
    )
    sim = edmd.Simulation.from_file(src, rule="swap")
    mine_traj = tmp_path / "py.xyz"
    sim.run(until=3.0, trajectory=mine_traj, every=0.25)
    mine = tmp_path / "py.txt"
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()
    assert mine_traj.read_bytes() == traj.read_bytes()


def test_generators_match_edmd_gen(tmp_path, edmd_cli):
    out = tmp_path / "fluid.txt"
    subprocess.run(
        [edmd_cli, "gen", "fluid", "--n", "100", "--packing", "0.4", "--seed", "7", "-o", str(out)],
        check=True, capture_output=True,
    )
    sim = edmd.gen.fluid(n=100, packing=0.4, seed=7)
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()


def test_every_generator_makes_a_simulation():
    sims = [
        edmd.gen.single(), edmd.gen.head_on(), edmd.gen.angled(angle=30.0),
        edmd.gen.one_red(n=20), edmd.gen.lattice(n=16), edmd.gen.diffusion1(n=20),
        edmd.gen.diffusion2(n=10), edmd.gen.dense(n=20, packing=0.5), edmd.gen.brownian(n=20),
        edmd.gen.fluid(n=20), edmd.gen.mixture(n=50), edmd.gen.mixture(n=200, dim=3),
    ]
    for s in sims:
        s.run(until=0.5)
        assert s.positions.shape == (s.n, s.dim)


def test_write_formats(tmp_path):
    sim = small_fluid()
    sim.run(until=1.0)
    sim.write(tmp_path / "a.txt")
    sim.write(tmp_path / "a.xyz")
    again = edmd.Simulation.from_file(tmp_path / "a.txt")
    assert np.array_equal(again.positions, sim.positions)
    assert (tmp_path / "a.xyz").read_text().splitlines()[0].strip() == "64"


def test_measurements_and_callback():
    sim = edmd.gen.fluid(n=200, packing=0.4, seed=3)
    sim.run(until=5.0)
    sim.measure("pressure", "speeds", "temperature", "collisions", "msd", every=1.0)
    seen = []
    sim.run(until=15.0, callback=lambda s: seen.append((s.time, s.positions.shape)),
            callback_every=2.5)
    assert [t for t, _ in seen] == [7.5, 10.0, 12.5, 15.0]
    r = sim.results()
    z = r["pressure"]["Z"]
    assert z["blocks"] == 10 and z["error"] > 0
    assert 2.0 < z["value"] < 4.0
    assert r["temperature"]["samples"] == 10
    t = r["tables"]["temperature"]
    assert np.array_equal(t["time"], np.arange(6.0, 16.0))
    assert set(r["tables"]) >= {"pressure", "speeds", "msd", "free_paths"}


def test_callback_exception_stops_the_run():
    sim = small_fluid()

    def boom(s):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        sim.run(until=10.0, callback=boom, callback_every=2.0)
    assert sim.time == 2.0


BAD_ARRAYS = [
    (dict(positions=[[0.5, 0.5], [0.6, 0.5]], velocities=[[0, 0], [0, 0]], radii=0.1,
          box=(1, 1)), "overlap"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0, 0]], radii=0.1, box=(1, 1)),
     "velocities: expected shape (1, 2)"),
    (dict(positions=[[0.5, 0.5, 0.5, 0.5]], velocities=[[0, 0, 0, 0]], radii=0.1, box=(1, 1)),
     "positions: expected shape"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=[0.1, 0.2], box=(1, 1)),
     "radii: expected N = 1"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=0.1, box=(1, 1, 1)),
     "box: expected 2 lengths"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=0.1, box=(1, 1),
          boundary="sticky"), "boundary"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=-0.1, box=(1, 1)), "radii"),
    (dict(positions=[[np.nan, 0.5]], velocities=[[0, 0]], radii=0.1, box=(1, 1)), "finite"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=0.1, box=(1, -1)), "box"),
    (dict(positions=[[0.5, 0.5]], velocities=[[0, 0]], radii=0.1, box=(1, 1), rule="sticky"),
     "rule"),
    (dict(positions="nonsense", velocities=[[0, 0]], radii=0.1, box=(1, 1)), "positions"),
]


@pytest.mark.parametrize("kwargs,message", BAD_ARRAYS)
def test_bad_arrays_raise_value_error(kwargs, message):
    # A str where numbers belong is a TypeError; every other refusal here a ValueError.
    with pytest.raises((ValueError, TypeError), match=re.escape(message)):
        edmd.Simulation.from_arrays(**kwargs)


def test_bad_files_raise_value_error_with_the_cli_message(tmp_path, edmd_cli):
    bad = tmp_path / "bad.txt"
    bad.write_text("2\n0.5 0.5 0 0 0.1 1 0 0 0\n0.55 0.5 0 0 0.1 1 0 0 0\n")
    with pytest.raises(ValueError) as e:
        edmd.Simulation.from_file(bad)
    cli = subprocess.run([edmd_cli, "run", str(bad), "--until", "1"], capture_output=True,
                         text=True)
    assert cli.returncode == 2
    assert str(e.value) in cli.stderr
    assert ":3:" in str(e.value)
    with pytest.raises(ValueError, match="cannot read"):
        edmd.Simulation.from_file(tmp_path / "missing.txt")
    (tmp_path / "binary.txt").write_bytes(b"\x00\x01")
    with pytest.raises(ValueError, match="not a text file"):
        edmd.Simulation.from_file(tmp_path / "binary.txt")


def test_bad_run_and_gen_options_raise_value_error():
    sim = small_fluid()
    sim.run(until=1.0)
    with pytest.raises(ValueError, match="before the current time"):
        sim.run(until=0.5)
    with pytest.raises(ValueError, match="either until or events"):
        sim.run()
    with pytest.raises(ValueError, match="trajectory and every"):
        sim.run(until=2.0, trajectory="x.xyz")
    with pytest.raises(ValueError, match="velocities"):
        sim.velocities = np.zeros((3, 2))
    with pytest.raises(ValueError, match="unknown measurement"):
        sim.measure("weather", every=1.0)
    with pytest.raises(ValueError, match="no measurements"):
        sim.results()
    with pytest.raises(ValueError, match="n must be"):
        edmd.gen.fluid(n=0)
    with pytest.raises(ValueError, match="dimension must be 1, 2 or 3"):
        edmd.gen.fluid(n=10, dim=4)
    with pytest.raises(ValueError, match="checkpoint"):
        edmd.Simulation.from_checkpoint(b"EDMDCK" + b"\0" * 40)
    with pytest.raises(TypeError):
        edmd.gen.fluid(n=10, colour="red")


def test_samples_after_run_events_do_not_pile_up():
    sim = small_fluid()
    sim.measure("temperature", every=0.5)
    sim.run(events=5000)  # passes several sample times without taking samples
    t = sim.time
    assert t > 1.0
    sim.run(until=t + 1.0)
    times = sim.results()["tables"]["temperature"]["time"]
    assert len(times) >= 2 and np.all(np.diff(times) > 0)
