"""GSD files written by edmd, read back by the HOOMD team's `gsd` package."""

import numpy as np
import pytest

import edmd

gsd_hoomd = pytest.importorskip("gsd.hoomd")


@pytest.mark.parametrize("dim", [2, 3])
def test_gsd_frame_read_by_the_gsd_package(tmp_path, dim):
    sim = edmd.gen.fluid(n=50, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=4)
    sim.run(until=12.0)
    path = tmp_path / "state.gsd"
    sim.write(path)
    with gsd_hoomd.open(path, "r") as f:
        assert len(f) == 1
        frame = f[0]
    box = list(sim.box) + [0.0] * (3 - dim)
    assert np.allclose(frame.configuration.box[:3], box, rtol=1e-6)
    assert frame.configuration.dimensions == dim
    assert frame.particles.N == sim.n
    centred = sim.positions - np.array(sim.box) / 2
    assert np.allclose(frame.particles.position[:, :dim], centred, atol=1e-5)
    assert np.allclose(frame.particles.velocity[:, :dim], sim.velocities, rtol=1e-6, atol=1e-6)
    assert np.allclose(frame.particles.diameter, 2 * sim.radii)
    assert np.allclose(frame.particles.mass, sim.masses)
    assert frame.log["edmd/time"][0] == sim.time
    # Image flags give the unwrapped positions.
    unwrapped = frame.particles.position[:, :dim] + frame.particles.image[:, :dim] * np.array(sim.box)
    assert np.allclose(unwrapped, sim.unwrapped_positions - np.array(sim.box) / 2, atol=1e-4)


def test_gsd_trajectory_during_a_run(tmp_path):
    sim = edmd.Simulation.from_arrays(
        [[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]], 1.0, box=(10, 10),
        boundary="walls",
    )
    path = tmp_path / "t.gsd"
    sim.run(until=5.0, trajectory=path, every=0.5)
    with gsd_hoomd.open(path, "r") as f:
        assert len(f) == 11
        times = [fr.log["edmd/time"][0] for fr in f]
        assert np.allclose(times, np.arange(11) * 0.5)
        assert list(f[0].log["edmd/walls"]) == [1, 1, 0]
        assert np.allclose(f[-1].particles.position[:, :2] + 5.0, sim.positions, atol=1e-5)


# Regression (issue 24): a position just below L on an axis was written as +L/2 after the
# rounding to float32, outside HOOMD's box, whose valid range is [-L/2, L/2). Positions are
# now put in the half-open box after the rounding: wrapped to -L/2 on a periodic axis (its
# image flag one more), moved to the nearest float32 inside on a walled one.
@pytest.mark.parametrize("boundary", ["periodic", "walls"])
@pytest.mark.parametrize("how", ["write", "trajectory"])
def test_gsd_positions_stay_inside_hoomds_half_open_box(tmp_path, boundary, how):
    L = 10.0
    x = L - 1e-9  # (x - L/2) rounds to float32 +L/2
    assert np.float32(x - L / 2) == np.float32(L / 2)
    sim = edmd.Simulation.from_arrays(
        [[x, x], [2.0, 3.0]], [[0.0, 0.0], [0.0, 0.0]], 1e-10, box=(L, L), boundary=boundary,
    )
    path = tmp_path / "edge.gsd"
    if how == "write":
        sim.write(path)
    else:
        sim.run(until=1.0, trajectory=path, every=0.5)
    with gsd_hoomd.open(path, "r") as f:
        frames = list(f)
    assert frames
    for frame in frames:
        half = frame.configuration.box[:2] / 2
        p = frame.particles.position[:, :2]
        assert np.all(p >= -half) and np.all(p < half), p
        # Still where the disc is: on a periodic axis the image flag keeps its unwrapped place.
        unwrapped = p + frame.particles.image[:, :2] * frame.configuration.box[:2]
        assert np.allclose(unwrapped, sim.unwrapped_positions - L / 2, atol=1e-5)


# A system prepared with HOOMD-blue continues in edmd: a frame written by the `gsd` package
# (HOOMD's centred box, diameters, types, image flags) is read by `Simulation.from_file`, and a
# state edmd writes as GSD reads back exactly.
@pytest.mark.parametrize("dim", [2, 3])
def test_a_gsd_frame_reads_back_as_a_simulation(tmp_path, dim):
    sim = edmd.gen.fluid(n=50, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=4)
    sim.run(until=3.0)
    path = tmp_path / "state.gsd"
    sim.write(path)
    back = edmd.Simulation.from_file(str(path))
    assert back.dim == dim and back.n == sim.n and back.time == sim.time
    assert np.array_equal(back.positions, sim.positions)
    assert np.array_equal(back.velocities, sim.velocities)
    assert np.array_equal(back.radii, sim.radii)


def test_a_frame_written_by_the_gsd_package_is_read(tmp_path):
    frame = gsd_hoomd.Frame()
    frame.configuration.box = [10, 10, 0, 0, 0, 0]
    frame.configuration.dimensions = 2
    frame.particles.N = 2
    frame.particles.types = ["A", "B"]
    frame.particles.typeid = [0, 1]
    frame.particles.position = [[-4.0, 0.0, 0.0], [4.5, 0.0, 0.0]]
    frame.particles.velocity = [[1.0, 0.0, 0.0], [-1.0, 0.5, 0.0]]
    frame.particles.diameter = [1.0, 2.0]
    frame.particles.image = [[1, 0, 0], [0, 0, 0]]
    path = tmp_path / "hoomd.gsd"
    with gsd_hoomd.open(path, "w") as f:
        f.append(frame)
        frame.particles.position = [[-3.0, 0.0, 0.0], [4.0, 0.0, 0.0]]
        f.append(frame)
    first = edmd.Simulation.from_file(str(path), frame=0)
    last = edmd.Simulation.from_file(str(path))
    assert first.box == (10.0, 10.0) and first.boundary == ("periodic", "periodic")
    assert np.allclose(first.positions, [[1.0, 5.0], [9.5, 5.0]])
    assert np.allclose(last.positions, [[2.0, 5.0], [9.0, 5.0]])
    assert list(first.species) == [0, 1]
    assert np.allclose(first.radii, [0.5, 1.0])
    last.run(until=1.0)
    with pytest.raises(ValueError, match="frame"):
        edmd.Simulation.from_file(str(path), frame=2)
    (tmp_path / "bad.gsd").write_bytes(b"not a gsd file at all")
    with pytest.raises(ValueError, match="bad.gsd"):
        edmd.Simulation.from_file(str(tmp_path / "bad.gsd"))
