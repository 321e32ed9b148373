"""Self-gravitating sheets from Python: `Simulation.set_self_gravity`, the `self_gravity` and
`self_gravity_energy` properties, `sheet_positions()`, `from_arrays(self_gravity=...)` and
`edmd.gen.sheets`; three sheets on their parabolas (the force on a sheet is the coupling times
the mass on its right less the mass on its left), a water bag that keeps its energy and meets
the virial theorem, files with a `# edmd self-gravity` line read and written back, systems and
runs that agree with `edmd gen sheets` and `edmd run` to the byte, pickles that continue bit
for bit, and the refusals."""

import pickle
import subprocess

import numpy as np
import pytest

import edmd


def sheets_energy(y, coupling):
    """U = coupling * sum over pairs |y_i - y_j| for sheets of mass 1, by brute force."""
    y = np.asarray(y)
    return coupling * np.abs(y[:, None] - y[None, :]).sum() / 2.0


def test_three_sheets_fly_on_their_parabolas():
    # Sheets of mass 1 at 9, 10, 11 with coupling c: the left one is pulled right by 2c, the
    # middle one not at all, the right one left by 2c. Before any two meet, each flies
    # x = x0 + v0 t + a t^2 / 2; with v0 = (0.2, 0, -0.2) and c = 0.05 the outer ones meet the
    # middle one when 1 - 0.2 t - 0.05 t^2 = 0, at t = 2.899 (positive root).
    c = 0.05
    sim = edmd.Simulation.from_arrays([[9.0], [10.0], [11.0]], [[0.2], [0.0], [-0.2]],
                                      radii=1e-9, box=(20.0,), boundary="walls",
                                      self_gravity=c)
    assert sim.self_gravity == c
    e0 = sim.kinetic_energy + sheets_energy(sim.sheet_positions(), c)
    t = 2.5
    sim.run(until=t)
    want = [9.0 + 0.2 * t + c * t * t, 10.0, 11.0 - 0.2 * t - c * t * t]
    assert sim.positions[:, 0] == pytest.approx(want, abs=1e-12)
    assert sim.stats["disc_disc"] == 0
    # The sheets' positions are the rods' less the rods' lengths to the left; U their energy.
    y = sim.sheet_positions()
    assert y.shape == (3,)
    assert y == pytest.approx([want[0], want[1] - 2e-9, want[2] - 4e-9], abs=1e-12)
    assert sim.self_gravity_energy == pytest.approx(sheets_energy(y, c), rel=1e-12)
    assert sim.potential_energy == sim.self_gravity_energy
    # Past the meetings, the energy is still kinetic plus U.
    sim.run(until=20.0)
    assert sim.stats["disc_disc"] > 0
    assert sim.kinetic_energy + sim.potential_energy == pytest.approx(e0, rel=1e-12)


def test_a_water_bag_keeps_its_energy_and_meets_the_virial_theorem():
    bag = edmd.gen.sheets(n=300, seed=2)
    assert bag.self_gravity == pytest.approx(1.0 / 300)
    assert bag.dim == 1 and bag.n == 300
    assert np.all(bag.radii == 1e-7) and np.all(bag.masses == 1.0)
    e0 = bag.kinetic_energy + bag.potential_energy
    # 2 <K> = <U> for a potential homogeneous of degree 1 (the virial theorem on time
    # averages), over 40 dynamical times sampled every 0.1; 2K/U itself swings by about 10%.
    kinetic, potential = [], []
    for k in range(1, 401):
        bag.run(until=0.1 * k)
        kinetic.append(bag.kinetic_energy)
        potential.append(bag.self_gravity_energy)
    e1 = bag.kinetic_energy + bag.potential_energy
    assert abs(e1 - e0) < 1e-10 * e0
    ratio = 2.0 * np.mean(kinetic) / np.mean(potential)
    assert ratio == pytest.approx(1.0, abs=0.05)
    # The engine's U is the brute-force sum over pairs of the sheets' positions.
    y = bag.sheet_positions()
    assert bag.self_gravity_energy == pytest.approx(sheets_energy(y, 1.0 / 300), rel=1e-10)
    # Sheets keep their order: the rods' order is the sheets' order.
    assert np.array_equal(np.argsort(bag.positions[:, 0]), np.argsort(y))


def test_set_self_gravity_and_back():
    rods = edmd.gen.fluid(n=20, dim=1, seed=1, boundary="walls")
    assert rods.self_gravity is None and rods.sheet_positions() is None
    assert rods.self_gravity_energy == 0.0
    rods.set_self_gravity(0.5)
    assert rods.self_gravity == 0.5
    assert rods.self_gravity_energy > 0.0
    assert rods.potential_energy == rods.self_gravity_energy
    rods.set_self_gravity(0.5)  # the same again changes nothing
    rods.set_self_gravity(None)
    assert rods.self_gravity is None and rods.self_gravity_energy == 0.0


def test_pickles_continue_bit_for_bit():
    bag = edmd.gen.sheets(n=200, seed=4)
    bag.run(until=2.3)
    copy = pickle.loads(pickle.dumps(bag))
    assert copy.self_gravity == bag.self_gravity
    bag.run(until=6.0)
    copy.run(until=6.0)
    assert np.array_equal(bag.positions, copy.positions)
    assert np.array_equal(bag.velocities, copy.velocities)
    assert bag.stats == copy.stats


def test_files_keep_the_self_gravity(tmp_path):
    # The default rods, 2e-7 long: hard rods that short could not be placed by the clock past
    # about t = 0.1, but sheets keep their order and have no such limit.
    bag = edmd.gen.sheets(n=100, coupling=0.02, seed=5)
    bag.run(until=1.5)
    path = tmp_path / "bag.txt"
    bag.write(path)
    text = path.read_text()
    assert "# edmd dim 1\n" in text and "# edmd self-gravity 0.02\n" in text
    back = edmd.Simulation.from_file(path)
    assert back.self_gravity == 0.02 and back.time == 1.5
    assert np.array_equal(back.positions, bag.positions)
    for fmt in ("xyz", "gsd"):
        with pytest.raises(ValueError, match="no place for the self-gravity"):
            bag.write(tmp_path / f"state.{fmt}")


def test_python_and_the_command_line_agree_to_the_byte(tmp_path, edmd_cli):
    cli, py = tmp_path / "cli.txt", tmp_path / "py.txt"
    subprocess.run([edmd_cli, "gen", "sheets", "--n", "150", "--width", "2", "--speed", "0.5",
                    "--coupling", "0.01", "--seed", "9", "-o", str(cli)],
                   check=True, capture_output=True)
    bag = edmd.gen.sheets(n=150, width=2.0, speed=0.5, coupling=0.01, seed=9)
    bag.write(py)
    assert py.read_text() == cli.read_text()
    ran_cli, ran_py = tmp_path / "ran-cli.txt", tmp_path / "ran-py.txt"
    subprocess.run([edmd_cli, "run", str(cli), "--until", "3", "-o", str(ran_cli)], check=True,
                   capture_output=True)
    sim = edmd.Simulation.from_file(cli)
    sim.run(until=3.0)
    sim.write(ran_py)
    assert ran_py.read_text() == ran_cli.read_text()


def test_bad_self_gravity_is_refused_naming_the_argument():
    rods = edmd.gen.fluid(n=20, dim=1, seed=1, boundary="walls")
    for bad in ("1", True, [1.0]):
        with pytest.raises(TypeError, match="coupling: expected a number"):
            rods.set_self_gravity(bad)
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="coupling: the coupling must be a finite"):
            rods.set_self_gravity(bad)
    assert rods.self_gravity is None
    ring = edmd.gen.fluid(n=20, dim=1, seed=1)  # a periodic line unless told
    with pytest.raises(ValueError, match="coupling: self-gravity needs walls on the line"):
        ring.set_self_gravity(1.0)
    assert ring.self_gravity is None
    discs = edmd.gen.fluid(n=50, packing=0.2, seed=1)
    with pytest.raises(ValueError, match="coupling: self-gravity is one-dimensional"):
        discs.set_self_gravity(1.0)
    falling = edmd.gen.fluid(n=20, dim=1, seed=1, gravity=-1.0)
    with pytest.raises(ValueError, match="coupling: self-gravity does not go with a uniform"):
        falling.set_self_gravity(1.0)
    soft = edmd.gen.fluid(n=20, dim=1, seed=1, boundary="walls", restitution=0.9)
    with pytest.raises(ValueError, match="coupling: self-gravity does not go with inelastic"):
        soft.set_self_gravity(1.0)
    line = dict(positions=[[2.0], [6.0]], velocities=[[0.0], [0.0]], radii=0.1, box=(8.0,))
    args = dict(line, boundary="walls")
    with pytest.raises(TypeError, match="self_gravity: expected a number"):
        edmd.Simulation.from_arrays(**args, self_gravity="heavy")
    with pytest.raises(ValueError, match="self_gravity: the coupling must be"):
        edmd.Simulation.from_arrays(**args, self_gravity=-2.0)
    # A line is periodic unless told: self-gravity needs its walls.
    with pytest.raises(ValueError, match="self_gravity: self-gravity needs walls on the line"):
        edmd.Simulation.from_arrays(**line, self_gravity=1.0)
    with pytest.raises(ValueError, match="self_gravity: .*multi-disc"):
        edmd.Simulation.from_arrays(**args, multi=True, self_gravity=1.0)
    with pytest.raises(ValueError, match="self_gravity: self-gravity is one-dimensional"):
        edmd.Simulation.from_arrays([[2.0, 2.0]], [[0.0, 0.0]], radii=0.1, box=(8.0, 8.0),
                                    self_gravity=1.0)


def test_bad_generator_options_are_refused_naming_them():
    with pytest.raises(TypeError, match="width"):
        edmd.gen.sheets(width="wide")
    with pytest.raises(ValueError, match="coupling must be a finite number > 0"):
        edmd.gen.sheets(coupling=0.0)
    with pytest.raises(ValueError, match="width must be a finite number > 0"):
        edmd.gen.sheets(width=-1.0)
    with pytest.raises(ValueError, match="speed"):
        edmd.gen.sheets(speed=float("nan"))
    with pytest.raises(ValueError, match="n must be from 2"):
        edmd.gen.sheets(n=1)
    with pytest.raises(ValueError, match="radius"):
        edmd.gen.sheets(n=100, radius=0.01)
