"""The thermal conductivity measurement from Python: the Einstein-Helfand estimate in a
periodic fluid, its refusal in a box with walls and for a mixture (as `edmd run --measure
conductivity` refuses them), the same numbers as the CLI, and pickles that carry it on."""

import json
import pickle
import subprocess

import numpy as np
import pytest

import edmd


def test_conductivity_of_a_periodic_fluid_is_near_enskog():
    sim = edmd.gen.fluid(dim=3, n=256, packing=0.25, boundary="periodic", seed=2)
    sim.run(until=5.0)
    sim.measure("conductivity", every=1.0)
    sim.run(until=sim.time + 120.0)
    c = sim.results()["conductivity"]
    # Enskog at packing 0.25 (kT about 1): about 2.0; 256 spheres over 120 time units (10
    # blocks of 80 mean collision times) give about 5 %; 25 % bounds the estimate without
    # letting a wrong formula (a missing factor kT, or 2 for the dimension) through.
    assert c["blocks"] >= 8, c
    assert 0.75 * c["lambda_enskog"] < c["lambda"] < 1.25 * c["lambda_enskog"], c
    assert c["lambda_error"] < 0.15 * c["lambda"], c
    tau = sim.results()["tables"]["conductivity"]["tau"]
    assert len(tau) == 40 and np.all(np.diff(tau) > 0)


def test_conductivity_is_refused_with_walls():
    sim = edmd.gen.fluid(n=100, packing=0.2, boundary="walls", seed=1)
    with pytest.raises(ValueError, match="measure: .*thermal conductivity needs a periodic box"):
        sim.measure("conductivity", every=1.0)


def test_conductivity_is_refused_for_a_mixture():
    pos = np.array([[1.0, 1.0], [4.0, 4.0]])
    vel = np.array([[1.0, 0.0], [-1.0, 0.0]])
    sim = edmd.Simulation.from_arrays(pos, vel, np.array([0.5, 0.4]), box=(10, 10),
                                      boundary="periodic")
    with pytest.raises(ValueError, match="one mass and one diameter"):
        sim.measure("conductivity", every=1.0)


def test_zero_particles_raise_no_panic():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      boundary="periodic")
    try:
        sim.measure("conductivity", every=0.1)
        sim.run(until=1.0)
        sim.results()
    except Exception:
        pass  # a clear refusal is fine; a PanicException (a BaseException) fails the test


def test_a_pickle_goes_on_measuring_as_the_original():
    sim = edmd.gen.fluid(dim=2, n=64, packing=0.3, boundary="periodic", seed=3)
    sim.measure("conductivity", "viscosity", every=0.5)
    sim.run(until=10.0)
    copy = pickle.loads(pickle.dumps(sim))
    sim.run(until=60.0)
    copy.run(until=60.0)
    a, b = sim.results(), copy.results()
    assert a["conductivity"]["blocks"] > 0
    assert a["conductivity"] == b["conductivity"] and a["viscosity"] == b["viscosity"]


def test_python_and_the_cli_agree(tmp_path, edmd_cli):
    path = tmp_path / "fluid.txt"
    subprocess.run([edmd_cli, "gen", "fluid", "--n", "64", "--packing", "0.3", "--boundary",
                    "periodic", "--seed", "4", "-o", str(path)], check=True, capture_output=True)
    out = subprocess.run([edmd_cli, "run", str(path), "--until", "40", "--measure",
                          "conductivity", "--sample-every", "1", "--json"],
                         capture_output=True, text=True, check=True)
    summary = json.loads(out.stdout)
    cli = summary.get("measurements", summary)["conductivity"]
    sim = edmd.Simulation.from_file(path)
    sim.measure("conductivity", every=1.0)
    sim.run(until=40.0)
    assert sim.results()["conductivity"] == cli
    assert cli["blocks"] > 0
