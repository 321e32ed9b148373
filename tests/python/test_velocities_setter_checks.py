"""Regression (issue 24): the `velocities` setter accepted what `from_arrays` refuses.

Speeds of 1e200 (a kinetic energy that overflows) were accepted by `sim.velocities = v`, where
`Simulation.from_arrays` refuses them; afterwards the run never ended and the pickle could not
be read back. The setter now applies the same check as `from_arrays` (one shared function),
raising ValueError naming `velocities` and leaving the simulation unchanged.
"""

import pickle

import numpy as np
import pytest

import edmd

BAD = [1e200, -1e200, np.inf, -np.inf, np.nan]


@pytest.mark.parametrize("speed", BAD)
def test_the_setter_refuses_what_from_arrays_refuses(speed):
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    before = sim.velocities
    v = before.copy()
    v[3, 1] = speed
    with pytest.raises(ValueError, match="velocities") as setter:
        sim.velocities = v
    assert np.array_equal(sim.velocities, before)
    with pytest.raises(ValueError, match="velocities") as built:
        edmd.Simulation.from_arrays(sim.positions, v, sim.radii, masses=sim.masses, box=sim.box)
    assert str(setter.value) == str(built.value)
    assert "disc 3" in str(setter.value)
    # The simulation still runs, and its pickle reads back.
    sim.run(until=1.0)
    assert pickle.loads(pickle.dumps(sim)).time == 1.0


def test_a_heavy_disc_overflows_at_a_lower_speed():
    pos = [[2.0, 2.0], [6.0, 6.0]]
    sim = edmd.Simulation.from_arrays(pos, [[0, 0], [0, 0]], 0.5, masses=[1.0, 1e300],
                                      box=(10, 10))
    with pytest.raises(ValueError, match="velocities: disc 1.*kinetic energy"):
        sim.velocities = [[1e10, 0.0], [1e10, 0.0]]
    sim.velocities = [[1e10, 0.0], [1.0, 0.0]]  # m v^2 / 2 = 5e299: finite
    assert sim.velocities[0, 0] == 1e10


def test_the_setter_refuses_wrong_kinds_naming_velocities():
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    for bad in ["fast", np.zeros((20, 2), dtype=complex), None, [[1, 2], [3]]]:
        with pytest.raises((ValueError, TypeError), match="velocities"):
            sim.velocities = bad
