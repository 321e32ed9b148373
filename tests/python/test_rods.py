"""Hard rods on a line from Python: `edmd.gen.fluid(dim=1)` and `from_arrays` with arrays of
shape (N, 1), 1D files read and written, Tonks's equation of state from the measured pressure,
pickles that continue bit for bit, agreement with `edmd gen --dim 1` to the byte, and a
ValueError naming the argument for what a line cannot do."""

import pickle
import subprocess

import numpy as np
import pytest

import edmd


def test_generated_rods_have_shape_n_by_1_and_are_seeded():
    sim = edmd.gen.fluid(dim=1, n=100, packing=0.4, seed=3)
    assert sim.dim == 1
    assert sim.positions.shape == (100, 1)
    assert sim.velocities.shape == (100, 1)
    assert sim.box == (250.0,)
    assert sim.boundary == ("periodic",)
    assert abs((sim.velocities[:, 0]).sum()) < 1e-12
    again = edmd.gen.fluid(dim=1, n=100, packing=0.4, seed=3)
    assert np.array_equal(again.velocities, sim.velocities)
    other = edmd.gen.fluid(dim=1, n=100, packing=0.4, seed=4)
    assert not np.array_equal(other.velocities, sim.velocities)


def test_equal_rods_exchange_velocities_head_on():
    sim = edmd.Simulation.from_arrays(positions=[[1.0], [3.0]], velocities=[[1.0], [-1.0]],
                                      radii=[0.5, 0.5], box=(10,), boundary="periodic")
    sim.run(until=1.5)
    assert sim.stats["disc_disc"] == 1
    assert np.allclose(sim.velocities[:, 0], [-1.0, 1.0], rtol=0, atol=1e-15)


def test_the_virial_pressure_follows_tonks():
    # Z = 1 / (1 - eta) exactly (Tonks 1936); 400 rods over about 100 collisions each give Z
    # to about 0.5 %: 2 % is the bound.
    sim = edmd.gen.fluid(dim=1, n=400, packing=0.6, seed=1)
    sim.run(until=20.0)
    sim.measure("pressure", every=2.0)
    sim.run(until=120.0)
    z = sim.results()["pressure"]["Z"]["value"]
    assert abs(z / 2.5 - 1.0) < 0.02, z


def test_a_pickle_of_rods_continues_bit_for_bit():
    sim = edmd.gen.fluid(dim=1, n=200, packing=0.7, seed=2, boundary="walls")
    sim.run(until=5.0)
    copy = pickle.loads(pickle.dumps(sim))
    assert copy.dim == 1
    sim.run(until=15.0)
    copy.run(until=15.0)
    assert np.array_equal(sim.positions, copy.positions)
    assert np.array_equal(sim.velocities, copy.velocities)
    assert sim.stats == copy.stats


def test_1d_files_round_trip(tmp_path):
    sim = edmd.gen.fluid(dim=1, n=30, packing=0.5, seed=5)
    sim.run(until=3.0)
    path = tmp_path / "rods.txt"
    sim.write(str(path))
    assert path.read_text().startswith("30\n# edmd dim 1\n")
    back = edmd.Simulation.from_file(str(path))
    assert back.dim == 1
    assert np.array_equal(back.positions, sim.positions)
    assert np.array_equal(back.velocities, sim.velocities)
    assert back.time == sim.time


def test_python_and_the_cli_generate_the_same_line(edmd_cli, tmp_path):
    out = tmp_path / "cli.txt"
    subprocess.run([edmd_cli, "gen", "fluid", "--dim", "1", "--n", "64", "--packing", "0.3",
                    "--seed", "9", "-o", str(out)], check=True, capture_output=True)
    mine = tmp_path / "py.txt"
    edmd.gen.fluid(dim=1, n=64, packing=0.3, seed=9).write(str(mine))
    assert mine.read_text() == out.read_text()


def test_what_a_line_cannot_do_is_a_value_error_naming_the_argument(tmp_path):
    sim = edmd.gen.fluid(dim=1, n=20, packing=0.5, seed=1)
    with pytest.raises(ValueError, match="shear"):
        edmd.gen.fluid(dim=1, n=20, shear=1.0)
    with pytest.raises(ValueError, match="^dim: the dimension must be 1, 2 or 3"):
        edmd.gen.fluid(dim=4)
    with pytest.raises(ValueError, match="speeds: not on a line"):
        sim.measure("speeds", every=1.0)
    with pytest.raises(ValueError, match="^start: rods on a line"):
        edmd.pack(start=sim)
    with pytest.raises(ValueError, match="GSD .* not 1D"):
        sim.write(str(tmp_path / "x.gsd"))
    with pytest.raises(ValueError, match="course format holds 2D systems only, not 1D"):
        sim.write(str(tmp_path / "x.txt"), format="course")
    with pytest.raises(ValueError, match="^positions: expected shape"):
        edmd.Simulation.from_arrays(positions=np.zeros((2, 4)), velocities=np.zeros((2, 4)),
                                    radii=[0.1, 0.1], box=(1, 1, 1, 1))
    assert not any(tmp_path.iterdir())
