"""The viscosity measurement from Python: the Einstein-Helfand estimate in a periodic fluid,
and its refusal in a box with walls (as `edmd run --measure viscosity` refuses it)."""

import pytest

import edmd


def test_viscosity_of_a_periodic_fluid_is_near_enskog():
    sim = edmd.gen.fluid(dim=3, n=256, packing=0.25, boundary="periodic", seed=2)
    sim.run(until=5.0)
    sim.measure("viscosity", every=1.0)
    sim.run(until=sim.time + 60.0)
    v = sim.results()["viscosity"]
    eta = v["eta"]["value"] if isinstance(v["eta"], dict) else v["eta"]
    # Enskog at packing 0.25 (kT about 1): about 0.51; 256 spheres over 60 time units give a
    # few per cent; 25% bounds the estimate without letting a wrong formula through.
    assert 0.75 * v["eta_enskog"] < eta < 1.25 * v["eta_enskog"], v


def test_viscosity_is_refused_with_walls():
    sim = edmd.gen.fluid(n=100, packing=0.2, boundary="walls", seed=1)
    with pytest.raises(ValueError, match="measure: .*wall"):
        sim.measure("viscosity", every=1.0)
