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
