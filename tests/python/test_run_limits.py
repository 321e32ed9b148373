"""Regression (issue 24): limits of `edmd run` did not hold in Python.

`measure(every=1e-9)` followed by `run(until=1)` was never refused (a billion samples), where
`edmd run --sample-every` refuses more than 10^6 samples; and a trajectory of absurd size (a
tiny `every`, or a huge system) started writing. Python now applies the CLI's sample limit,
with its rule and message, and refuses before it starts a trajectory of more than 10^6 frames
or of an estimated size over 10 GB, giving the estimate.
"""

import numpy as np
import pytest

import edmd


def test_measurement_samples_beyond_the_cli_limit_are_refused():
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    sim.measure("temperature", every=1e-9)
    with pytest.raises(ValueError, match=r"1\.000e9 samples .* too many \(at most 1000000"):
        sim.run(until=1.0)
    assert sim.time == 0.0
    assert len(sim.results()["tables"]["temperature"]["time"]) == 0
    # A schedule within the limit runs.
    sim.measure("temperature", every=1e-6)
    sim.run(until=1e-4)
    assert len(sim.results()["tables"]["temperature"]["time"]) == 100


def test_too_many_trajectory_frames_are_refused(tmp_path):
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    with pytest.raises(ValueError, match=r"every: 1\.000e12 trajectory frames"):
        sim.run(until=1e3, trajectory=tmp_path / "t.xyz", every=1e-9)
    assert sim.time == 0.0


def lattice(k):
    """k * k discs on a square lattice, at rest."""
    x, y = np.meshgrid(np.arange(k) + 0.5, np.arange(k) + 0.5)
    pos = np.column_stack([x.ravel(), y.ravel()])
    return edmd.Simulation.from_arrays(pos, np.zeros_like(pos), 0.25, box=(k, k))


@pytest.mark.parametrize("name", ["t.xyz", "t.gsd"])
def test_a_trajectory_too_large_for_the_disc_is_refused_with_its_estimate(tmp_path, name):
    sim = lattice(100)  # 10^4 discs: 10^6 frames is 0.5 TB of GSD, 2 TB of XYZ
    with pytest.raises(ValueError, match=r"about [0-9.]+e1[12] bytes") as info:
        sim.run(until=1e4, trajectory=tmp_path / name, every=0.01)
    assert "10 GB" in str(info.value)
    assert sim.time == 0.0
    assert list(tmp_path.iterdir()) == []


# Regression (issue 24): a state file at `# edmd time 1e16` ran and wrote overlapping discs;
# at such times floating-point times are too far apart to place a disc at contact. Python
# refuses such a start time and such an end time with the CLI's reason.
def test_times_beyond_the_clock_limit_are_refused(tmp_path):
    for t in ["1e13", "1e16", "1e17"]:
        f = tmp_path / "late.txt"
        f.write_text(
            f"2\n# edmd time {t}\n0.25 0.5 0.01 0 0.02 1 0 0 0\n0.75 0.5 -0.01 0.001 0.02 1 0 0 0\n"
        )
        with pytest.raises(ValueError, match="too late for the clock"):
            edmd.Simulation.from_file(str(f))
    sim = edmd.Simulation.from_arrays(
        [[0.25, 0.5], [0.75, 0.5]], [[0.01, 0], [-0.01, 0.001]], radii=0.02, box=(1, 1)
    )
    for until in [1e16, 1e308]:
        with pytest.raises(ValueError, match="until: .*too late for the clock"):
            sim.run(until=until)
    assert sim.time == 0.0
    sim.run(until=1e3)
    assert sim.time == 1e3
