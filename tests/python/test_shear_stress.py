"""The shear-stress measurement from Python: the viscosity -P_xy / gamma of a sheared fluid,
and its refusal without shear (as `edmd run --measure shear-stress` refuses it)."""

import math

import pytest

import edmd


def test_shear_stress_of_a_sheared_fluid_gives_a_positive_viscosity():
    sim = edmd.gen.fluid(n=100, packing=0.3, shear=0.2, seed=1)
    sim.measure("shear-stress", every=5.0)
    sim.run(until=sim.time + 50.0)
    s = sim.results()["shear_stress"]
    assert s["blocks"] == 10, s
    assert math.isfinite(s["eta"]) and s["eta"] > 0.0, s
    assert s["pxy"] < 0.0 and s["rate"] == 0.2, s


def test_shear_stress_is_refused_without_shear():
    sim = edmd.gen.fluid(n=100, packing=0.2, seed=1)
    with pytest.raises(ValueError, match="shear-stress: needs shear"):
        sim.measure("shear-stress", every=1.0)
