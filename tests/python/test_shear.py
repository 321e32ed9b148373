"""Lees-Edwards boundaries from Python: `Simulation.set_shear`, the `shear`,
`peculiar_velocities` and `peculiar_kinetic_energy` properties, `from_arrays(shear=...)` and
the generators' `shear=`; a disc crossing the sliding boundary where the images say, the
streaming profile held by the thermostat, files with a `# edmd shear` line read and written
back, generated systems and runs that agree with `edmd gen --shear` and `edmd run` to the
byte, pickles that continue bit for bit, and the refusals."""

import pickle
import subprocess

import numpy as np
import pytest

import edmd


def sheared(rate=0.2, n=400, seed=1, **kw):
    return edmd.gen.fluid(n=n, packing=0.3, seed=seed, shear=rate, **kw)


def profile_slope(sim):
    """The least-squares slope of the x velocities against y."""
    y = sim.positions[:, 1]
    vx = sim.velocities[:, 0]
    y0 = y - y.mean()
    return float((y0 * (vx - vx.mean())).sum() / (y0 * y0).sum())


def kt_about_the_profile(sim):
    return 2.0 * sim.peculiar_kinetic_energy / (sim.positions.shape[1] * sim.n)


# --- one disc, exactly -----------------------------------------------------------------------


def test_a_disc_crossing_the_top_comes_back_through_the_slid_bottom():
    # Box 10 x 10 at rate 0.1: the images above slide at +1 along x. The disc leaves the top
    # at t = 0.5, when they have slid by 0.5: it comes back at x = 4.5 with its x velocity
    # less 1, and at t = 1 it is at (4, 0.5).
    sim = edmd.Simulation.from_arrays([[5.0, 9.5]], [[0.0, 1.0]], radii=0.5,
                                      box=(10.0, 10.0), shear=0.1)
    assert sim.shear == (0.1, 0.0)
    # Relative to the profile 0.1 (y - 5): -0.45 at y = 9.5.
    assert sim.peculiar_velocities[0, 0] == pytest.approx(-0.45, abs=1e-15)
    sim.run(until=1.0)
    np.testing.assert_allclose(sim.positions[0], [4.0, 0.5], atol=1e-12)
    np.testing.assert_allclose(sim.velocities[0], [-1.0, 1.0], atol=1e-15)
    assert sim.peculiar_velocities[0, 0] == pytest.approx(-0.55, abs=1e-12)
    assert sim.shear[0] == 0.1 and sim.shear[1] == pytest.approx(1.0, abs=1e-12)
    assert sim.peculiar_kinetic_energy == pytest.approx(0.5 * (0.55**2 + 1.0), abs=1e-12)


def test_set_shear_keeps_the_offset_and_removes_the_shear():
    sim = edmd.Simulation.from_arrays([[5.0, 5.0]], [[0.0, 0.0]], radii=0.5, box=(10.0, 10.0))
    assert sim.shear is None
    np.testing.assert_array_equal(sim.peculiar_velocities, sim.velocities)
    assert sim.peculiar_kinetic_energy == sim.kinetic_energy
    sim.set_shear(0.1, offset=2.0)
    assert sim.shear == (0.1, 2.0)
    sim.run(until=1.0)
    rate, offset = sim.shear
    assert offset == pytest.approx(3.0, abs=1e-12)
    # A new rate from where the images are; the same one changes nothing.
    sim.set_shear(*sim.shear)
    assert sim.shear == (rate, offset)
    sim.set_shear(-0.2)
    assert sim.shear == (-0.2, offset)
    sim.set_shear((0.3, 0.0))
    assert sim.shear == (0.3, 0.0)
    sim.set_shear(None)
    assert sim.shear is None


# --- fluids in steady shear --------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_gen_starts_on_the_streaming_profile(dim):
    sim = edmd.gen.fluid(n=400, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=2, shear=0.25)
    assert sim.shear == (0.25, 0.0)
    plain = edmd.gen.fluid(n=400, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=2)
    np.testing.assert_array_equal(sim.positions, plain.positions)
    # The generator's velocities, about the profile: the same temperature, and the slope of
    # the x velocities is the rate within the thermal noise (rms 1 over some 400 discs spread
    # over a height of 20 to 30).
    assert sim.peculiar_kinetic_energy == pytest.approx(plain.kinetic_energy, rel=1e-12)
    np.testing.assert_allclose(sim.peculiar_velocities, plain.velocities, atol=1e-12)
    assert profile_slope(sim) == pytest.approx(0.25, abs=0.03)
    # The shift itself is the profile exactly: linear in y with slope 0.25.
    shift = sim.velocities - plain.velocities
    assert np.all(shift[:, 1:] == 0.0)
    slope, _ = np.polyfit(sim.positions[:, 1], shift[:, 0], 1)
    assert slope == pytest.approx(0.25, rel=1e-12)


def test_the_thermostat_holds_the_profile_and_the_temperature():
    # Rate 0.2 in a fluid at packing 0.3, the Andersen thermostat at kT = 1 redrawing each
    # disc once per unit time about the profile: after a strain of 4, the slope of the x
    # velocities against y averaged over 40 snapshots is the rate within 5% (the snapshots'
    # noise is about 1% of it), and the temperature about the profile is a little above 1:
    # the viscous heating eta gamma^2 V against the redraws' pull, nu N (kT - 1), raises it
    # by some eta / 10, about 5% here.
    sim = sheared(rate=0.2, n=400, seed=3)
    sim.set_thermostat(kT=1.0, rate=1.0, seed=5)
    sim.run(until=20.0)
    slopes, kts = [], []
    for k in range(40):
        sim.run(until=21.0 + k)
        slopes.append(profile_slope(sim))
        kts.append(kt_about_the_profile(sim))
    assert np.mean(slopes) == pytest.approx(0.2, rel=0.05), np.mean(slopes)
    assert 1.0 < np.mean(kts) < 1.1, np.mean(kts)
    # The lab-frame kinetic energy holds the flow's besides.
    assert sim.kinetic_energy > sim.peculiar_kinetic_energy


def test_inelastic_grains_in_shear_reach_a_steady_temperature():
    sim = sheared(rate=0.3, n=300, seed=4, restitution=0.8)
    sim.run(until=30.0)
    first = kt_about_the_profile(sim)
    sim.run(until=60.0)
    second = kt_about_the_profile(sim)
    assert sim.dissipated > 0.0
    # Cooled from kT = 1 to a balance of shear heating and collisional loss.
    assert 0.0 < second < 0.5 and second == pytest.approx(first, rel=0.5), (first, second)


def test_a_pickle_continues_bit_for_bit():
    sim = sheared(rate=0.4, n=200, seed=6, restitution=0.9)
    sim.set_thermostat(kT=0.5, rate=0.3, seed=2)
    sim.run(until=5.0)
    copy = pickle.loads(pickle.dumps(sim))
    assert copy.shear == sim.shear
    sim.run(until=12.0)
    copy.run(until=12.0)
    np.testing.assert_array_equal(copy.positions, sim.positions)
    np.testing.assert_array_equal(copy.velocities, sim.velocities)
    assert copy.shear == sim.shear
    assert copy.dissipated == sim.dissipated
    assert copy.stats == sim.stats


# --- files and the command line ----------------------------------------------------------------


def test_a_written_state_reads_back_with_its_offset(tmp_path):
    sim = sheared(rate=-0.3, n=200, seed=7)
    sim.run(until=3.0)
    path = tmp_path / "state.txt"
    sim.write(path)
    text = path.read_text()
    rate, offset = sim.shear
    assert f"# edmd shear {rate!r} {offset!r}\n" in text
    back = edmd.Simulation.from_file(path)
    assert back.shear == sim.shear and back.time == sim.time
    np.testing.assert_array_equal(back.positions, sim.positions)
    # Runs on in the same flow.
    back.run(until=6.0)
    sim.run(until=6.0)
    assert back.shear[1] == pytest.approx(sim.shear[1], abs=1e-9)
    for fmt in ("xyz", "gsd"):
        with pytest.raises(ValueError, match="no place for the shear"):
            sim.write(tmp_path / f"state.{fmt}")


def test_python_and_the_command_line_agree_to_the_byte(tmp_path, edmd_cli):
    cli, py = tmp_path / "cli.txt", tmp_path / "py.txt"
    subprocess.run([edmd_cli, "gen", "fluid", "--n", "200", "--packing", "0.3", "--shear",
                    "-0.5", "--restitution", "0.8", "--seed", "9", "-o", str(cli)],
                   check=True, capture_output=True)
    sim = edmd.gen.fluid(n=200, packing=0.3, shear=-0.5, restitution=0.8, seed=9)
    sim.write(py)
    assert py.read_text() == cli.read_text()
    ran_cli, ran_py = tmp_path / "ran-cli.txt", tmp_path / "ran-py.txt"
    subprocess.run([edmd_cli, "run", str(cli), "--until", "5", "-o", str(ran_cli)], check=True,
                   capture_output=True)
    sim = edmd.Simulation.from_file(cli)
    sim.run(until=5.0)
    sim.write(ran_py)
    assert ran_py.read_text() == ran_cli.read_text()


# --- refusals --------------------------------------------------------------------------------


def test_what_shear_does_not_go_with_is_refused_and_changes_nothing():
    walled = edmd.gen.fluid(n=20, packing=0.3, seed=1, boundary="walls")
    with pytest.raises(ValueError, match="rate: Lees-Edwards boundaries need periodic x and y"):
        walled.set_shear(0.1)
    assert walled.shear is None
    well = edmd.gen.fluid(n=20, packing=0.3, seed=1, well=1.5)
    with pytest.raises(ValueError, match="rate: shear does not go with a stepped potential"):
        well.set_shear(0.1)
    multi = edmd.gen.fluid(n=20, packing=0.3, seed=1, multi=True)
    with pytest.raises(ValueError, match="multi-disc collisions"):
        multi.set_shear(0.1)
    column = edmd.gen.fluid(n=20, packing=0.3, seed=1, gravity=-1.0)
    with pytest.raises(ValueError, match="rate: Lees-Edwards boundaries need periodic"):
        column.set_shear(0.1)
    with pytest.raises(ValueError, match="shear: Lees-Edwards boundaries need periodic"):
        edmd.Simulation.from_arrays([[5.0, 5.0]], [[0.0, 0.0]], radii=0.5, box=(10.0, 10.0),
                                    boundary="walls", shear=0.1)
    for kw, words in [(dict(boundary="walls"), "shear needs a periodic box"),
                      (dict(gravity=-1.0), "shear does not go with gravity"),
                      (dict(well=1.5), "shear does not go with well or shoulder")]:
        with pytest.raises(ValueError, match=words):
            edmd.gen.fluid(n=20, shear=0.1, **kw)
    with pytest.raises(ValueError, match="fluids and mixtures only"):
        edmd.gen._generate("lattice", shear=0.1)


def test_discs_are_checked_against_the_slid_images():
    # Box 4 x 4: discs at (1, 0.2) and (1, 3.9) touch across the plain boundary, but at an
    # offset of 2 the upper one's image below is at (-1, -0.1), far away: accepted then.
    touching = dict(positions=[[1.0, 0.2], [1.0, 3.9]], velocities=[[0.0, 0.0]] * 2,
                    radii=0.5, box=(4.0, 4.0))
    sim = edmd.Simulation.from_arrays(**touching, shear=(0.1, 2.0))
    assert sim.shear == (0.1, 2.0)
    with pytest.raises(ValueError, match="overlap"):
        edmd.Simulation.from_arrays(**touching, shear=0.1)
    # And the other way round: the upper disc moved to x = 3 meets the slid image.
    slid = dict(touching, positions=[[1.0, 0.2], [3.0, 3.9]])
    edmd.Simulation.from_arrays(**slid, shear=0.1)
    with pytest.raises(ValueError, match="shear\\[1\\]: at this offset discs 0 and 1 overlap"):
        edmd.Simulation.from_arrays(**slid, shear=(0.1, 2.0))
    plain = edmd.Simulation.from_arrays(**slid)
    with pytest.raises(ValueError, match="offset: at this offset"):
        plain.set_shear(0.1, offset=2.0)
    assert plain.shear is None


def test_bad_directives_name_their_line(tmp_path):
    path = tmp_path / "bad.txt"
    for text, words in [
        ("1\n# edmd shear 1\n.5 .5 0 0 .1 1 0 0 0\n", r"bad.txt:2: .*periodic x and y"),
        ("1\n# edmd boundary periodic\n# edmd shear 1 2\n.5 .5 0 0 .1 1 0 0 0\n",
         r"bad.txt:3: .*offset must be in"),
        ("1\n# edmd boundary periodic\n# edmd shear nan\n.5 .5 0 0 .1 1 0 0 0\n",
         r"bad.txt:3: RATE is not"),
    ]:
        path.write_text(text)
        with pytest.raises(ValueError, match=words):
            edmd.Simulation.from_file(path)
