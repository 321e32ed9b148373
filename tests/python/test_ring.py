"""A patch of a planetary ring from Python: `Simulation.set_ring`, the `ring` and
`ring_energy` properties, `from_arrays(ring=...)` and `edmd.gen.ring`; a lone particle on
its epicycle (Hill's equations solved exactly), an inelastic patch whose dispersion settles,
files with a `# edmd ring` line read and written back, systems and runs that agree with
`edmd gen ring` and `edmd run` to the byte, pickles that continue bit for bit, and the
refusals."""

import math
import pickle
import subprocess

import numpy as np
import pytest

import edmd


def dispersion(sim):
    """sqrt(2 K' / (N D)): the velocity dispersion about the Keplerian flow (unit masses)."""
    return math.sqrt(2.0 * sim.peculiar_kinetic_energy / (sim.n * sim.positions.shape[1]))


def test_a_lone_particle_flies_its_epicycle():
    # Hill's equations from the centre with velocity (0, v): y = (v / omega) sin(omega t),
    # x = (2 v / omega) (cos(omega t) - 1) (an epicycle twice as long as it is wide, run
    # backwards along the orbit), here with v = 1, omega = 0.5.
    omega, v = 0.5, 1.0
    sim = edmd.Simulation.from_arrays([[20.0, 20.0]], [[0.0, v]], radii=0.5, box=(40.0, 40.0),
                                      ring=omega)
    assert sim.ring == omega
    assert sim.shear == (-1.5 * omega, 0.0)
    for t in (1.0, math.pi / omega, 7.5):
        sim.run(until=t)
        want = [20.0 + 2 * v / omega * (math.cos(omega * t) - 1), 20.0 + v / omega * math.sin(omega * t)]
        assert sim.positions[0] == pytest.approx(want, abs=1e-9)
        # The Jacobi integral, kinetic plus the ring's potential, is kept along a flight.
        assert sim.kinetic_energy + sim.ring_energy == pytest.approx(0.5 * v * v, abs=1e-9)


def test_an_inelastic_patch_cools_to_a_finite_dispersion():
    # Constant e = 0.5 (below Goldreich and Tremaine's critical ~0.63) with the TC model: a
    # patch started at 2 omega d loses more than the shear gives and settles near 1 omega d
    # instead of collapsing or heating (measured at n 300: 1.78, 1.49, 1.32, 1.18, 1.11 at
    # t = 10, 20, 30, 40, 50).
    sim = edmd.gen.ring(n=300, restitution={"all": 0.5, "tc": 1e-3}, seed=3)
    start = dispersion(sim)
    assert start == pytest.approx(2.0, rel=0.1)
    sim.run(until=40.0)
    mid = dispersion(sim)
    assert 0.3 * start < mid < 0.7 * start, mid
    sim.run(until=50.0)
    end = dispersion(sim)
    assert math.isfinite(end)
    # Levelling off: the last 10 / omega take off less than a fifth of it.
    assert 0.8 * mid < end <= mid, (mid, end)
    assert sim.dissipated > 0
    # The layer stays between the walls, about the mid-plane.
    z = sim.positions[:, 2] - 30.0
    assert np.abs(z).max() < 29.5


def test_set_ring_and_back():
    sim = edmd.gen.fluid(n=100, packing=0.2, seed=1)
    assert sim.ring is None and sim.ring_energy == 0.0
    sim.set_ring(2.0)
    assert sim.ring == 2.0
    assert sim.shear == (-3.0, 0.0)
    assert sim.ring_energy != 0.0
    assert sim.potential_energy == pytest.approx(sim.ring_energy)
    sim.set_ring(2.0)  # the same ring again changes nothing
    sim.set_ring(None)
    assert sim.ring is None and sim.shear is None and sim.ring_energy == 0.0


def test_pickles_continue_bit_for_bit():
    sim = edmd.gen.ring(n=300, dim=2, restitution={"all": {"bridges": 0.01}}, seed=4)
    sim.run(until=2.3)
    copy = pickle.loads(pickle.dumps(sim))
    assert copy.ring == 1.0 and copy.shear == sim.shear
    sim.run(until=6.0)
    copy.run(until=6.0)
    assert np.array_equal(sim.positions, copy.positions)
    assert np.array_equal(sim.velocities, copy.velocities)
    assert sim.stats == copy.stats


def test_files_keep_the_ring_and_its_offset(tmp_path):
    sim = edmd.gen.ring(n=300, dim=2, restitution={"all": {"bridges": 0.01}}, seed=5)
    sim.run(until=2.3)
    path = tmp_path / "patch.txt"
    sim.write(path)
    text = path.read_text()
    rate, offset = sim.shear
    assert f"# edmd ring 1.0 {offset!r}\n" in text
    assert "# edmd shear" not in text
    back = edmd.Simulation.from_file(path)
    assert back.ring == 1.0 and back.shear == sim.shear
    for fmt in ("xyz", "gsd"):
        with pytest.raises(ValueError, match="no place for the ring patch"):
            sim.write(tmp_path / f"state.{fmt}")


def test_python_and_the_command_line_agree_to_the_byte(tmp_path, edmd_cli):
    cli, py = tmp_path / "cli.txt", tmp_path / "py.txt"
    subprocess.run([edmd_cli, "gen", "ring", "--n", "300", "--tau", "0.3", "--omega", "2",
                    "--restitution", "bridges 0.02", "--seed", "9", "-o", str(cli)],
                   check=True, capture_output=True)
    sim = edmd.gen.ring(n=300, tau=0.3, omega=2.0, restitution={"all": {"bridges": 0.02}},
                        seed=9)
    sim.write(py)
    # The same system, each written through a simulation (whose positions on a ring are
    # taken about the patch's centre and back, which can move a last bit of what was read).
    via = tmp_path / "via.txt"
    edmd.Simulation.from_file(cli).write(via)
    assert py.read_text() == via.read_text()
    assert sim.positions == pytest.approx(np.loadtxt(cli, comments="#", skiprows=1)[:, :3],
                                          rel=0, abs=1e-12)
    ran_cli, ran_py = tmp_path / "ran-cli.txt", tmp_path / "ran-py.txt"
    subprocess.run([edmd_cli, "run", str(cli), "--until", "3", "-o", str(ran_cli)], check=True,
                   capture_output=True)
    sim = edmd.Simulation.from_file(cli)
    sim.run(until=3.0)
    sim.write(ran_py)
    assert ran_py.read_text() == ran_cli.read_text()


def test_bad_rings_are_refused_naming_the_argument():
    sim = edmd.gen.fluid(n=50, packing=0.2, seed=1)
    for bad in ("1", True, [1.0]):
        with pytest.raises(TypeError, match="omega: expected a number"):
            sim.set_ring(bad)
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="omega: the orbital frequency must be a finite"):
            sim.set_ring(bad)
    assert sim.ring is None
    walled = edmd.gen.fluid(n=50, packing=0.2, seed=1, boundary="walls")
    with pytest.raises(ValueError, match="omega: .*periodic x .* and y"):
        walled.set_ring(1.0)
    assert walled.ring is None and walled.shear is None
    column = edmd.gen.fluid(n=50, packing=0.2, seed=1, gravity=-1.0)
    with pytest.raises(ValueError, match="omega: "):
        column.set_ring(1.0)
    rods = edmd.gen.fluid(n=20, dim=1, seed=1, boundary="periodic")
    with pytest.raises(ValueError, match="omega: "):
        rods.set_ring(1.0)
    sim.set_ring(1.0)
    with pytest.raises(ValueError, match="omega: the system is a ring patch at omega 1.0 already"):
        sim.set_ring(2.0)
    assert sim.ring == 1.0
    with pytest.raises(ValueError, match="shear"):
        sim.set_shear(0.1)
    assert sim.shear == (-1.5, sim.shear[1])
    args = dict(positions=[[5.0, 5.0]], velocities=[[0.0, 0.0]], radii=0.5, box=(10.0, 10.0))
    with pytest.raises(TypeError, match="ring: expected a number"):
        edmd.Simulation.from_arrays(**args, ring="fast")
    with pytest.raises(ValueError, match="ring: the orbital frequency"):
        edmd.Simulation.from_arrays(**args, ring=-2.0)
    with pytest.raises(ValueError, match="ring: does not go with shear"):
        edmd.Simulation.from_arrays(**args, ring=1.0, shear=0.1)
    with pytest.raises(ValueError, match="ring: .*periodic x .* and y"):
        edmd.Simulation.from_arrays(**args, boundary="walls", ring=1.0)


def test_bad_generator_options_are_refused_naming_them():
    with pytest.raises(ValueError, match="TC model"):
        edmd.gen.ring(restitution=0.5)
    with pytest.raises(TypeError, match="tau"):
        edmd.gen.ring(tau="thick")
    with pytest.raises(ValueError, match="omega must be a finite number > 0"):
        edmd.gen.ring(omega=0.0)
    with pytest.raises(ValueError, match="dispersion"):
        edmd.gen.ring(dispersion=-1.0)
    with pytest.raises(ValueError, match="height"):
        edmd.gen.ring(dim=2, height=10.0)
    with pytest.raises(ValueError, match="2 or 3 dimensions"):
        edmd.gen.ring(dim=1)
    with pytest.raises(ValueError, match="optical depth"):
        edmd.gen.ring(tau=5.0)
