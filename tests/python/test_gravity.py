"""A uniform field from Python: `Simulation.set_gravity`, the `gravity` and `field_energy`
properties, `from_arrays(gravity=...)`, the generators' `gravity=`, in 2D and 3D; a dropped
disc that lands when the parabola says and bounces back to its height, columns of fluid that
keep kinetic plus potential energy, files with a `# edmd gravity` line read and written back,
generated systems and their runs that agree with `edmd gen --gravity` and `edmd run` to the
byte, pickles that continue bit for bit, and the refusal of every bad argument by name."""

import copy
import math
import pickle
import re
import subprocess

import numpy as np
import pytest

import edmd

NAN, INF = math.nan, math.inf


def drop(dim=2, g=-2.0, height=8.0, axis=None, **kw):
    """One disc of radius 1/2 and mass 3 at rest at `height` along the field's axis (the last
    unless told) in a box of 10 with walls: it falls 7.5 to the floor's contact."""
    along = dim - 1 if axis is None else "xyz".index(axis) if isinstance(axis, str) else axis
    pos = [5.0] * dim
    pos[along] = height
    args = dict(positions=[pos], velocities=[[0.0] * dim], radii=0.5, masses=3.0,
                box=(10.0,) * dim, boundary="walls")
    args.update(kw)
    sim = edmd.Simulation.from_arrays(**args)
    sim.set_gravity(g, axis=axis)
    return sim


def energy(sim):
    return sim.kinetic_energy + sim.potential_energy


def column(dim=2, n=200, seed=1, g=-1.0, **kw):
    return edmd.gen.fluid(n=n, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=seed, gravity=g,
                          **kw)


# --- one disc, exactly -----------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("g,axis", [(-2.0, None), (-0.5, None), (-2.0, "x"), (-2.0, 0)])
def test_a_dropped_disc_lands_at_the_time_of_the_parabola_and_bounces_back(dim, g, axis):
    sim = drop(dim, g=g, axis=axis)
    k = dim - 1 if axis is None else 0
    assert sim.gravity == {"axis": k, "g": g}
    e0 = energy(sim)
    # All the energy is the field's: -m g x, with x = 8 from the wall at 0.
    assert sim.field_energy == sim.potential_energy == -3.0 * g * 8.0 == e0
    assert sim.kinetic_energy == 0.0
    fall = math.sqrt(2.0 * 7.5 / abs(g))
    sim.run(until=fall * (1.0 - 1e-9))
    assert sim.stats["wall"] == 0
    assert sim.velocities[0, k] == pytest.approx(g * fall, rel=1e-8)
    sim.run(until=fall * (1.0 + 1e-9))
    assert sim.stats["wall"] == 1
    assert sim.velocities[0, k] == pytest.approx(-g * fall, rel=1e-8)
    assert sim.positions[0, k] == pytest.approx(0.5, abs=1e-7)
    # Back at the top of its flight, at rest, after another fall's time; the other axes never
    # moved.
    sim.run(until=2.0 * fall)
    assert sim.positions[0, k] == pytest.approx(8.0, rel=1e-12)
    assert sim.velocities[0, k] == pytest.approx(0.0, abs=1e-12 * abs(g) * fall)
    others = [a for a in range(dim) if a != k]
    assert np.all(sim.positions[0, others] == 5.0)
    assert np.all(sim.velocities[0, others] == 0.0)
    assert abs(energy(sim) - e0) <= 1e-12 * e0
    # And again, for many bounces.
    sim.run(until=40.5 * fall)
    assert sim.stats["wall"] == 20
    assert abs(energy(sim) - e0) <= 1e-12 * e0


def test_a_positive_field_pulls_towards_the_far_wall():
    sim = drop(g=2.0, height=2.0)
    assert sim.field_energy == -3.0 * 2.0 * 2.0
    fall = math.sqrt(2.0 * 7.5 / 2.0)  # from 2 to 9.5
    sim.run(until=fall * (1.0 + 1e-9))
    assert sim.stats["wall"] == 1 and sim.velocities[0, 1] < 0.0
    assert sim.positions[0, 1] == pytest.approx(9.5, abs=1e-7)


def test_a_thrown_disc_flies_on_a_parabola():
    # Thrown up at 3 from height 2 under g = -1: at t it is at 2 + 3 t - t^2 / 2 (its top, 6.5,
    # at t = 3), moving sideways at 1 all along.
    sim = edmd.Simulation.from_arrays([[1.0, 2.0]], [[1.0, 3.0]], radii=0.5, box=(10.0, 10.0),
                                      boundary="walls", gravity=-1.0)
    for t in (0.5, 3.0, 5.0):
        sim.run(until=t)
        assert sim.positions[0] == pytest.approx([1.0 + t, 2.0 + 3.0 * t - t * t / 2.0],
                                                 abs=1e-12)
        assert sim.velocities[0] == pytest.approx([1.0, 3.0 - t], abs=1e-12)
    assert sim.stats["wall"] == 0


def test_two_discs_falling_together_meet_as_without_the_field():
    # A uniform field accelerates both alike: their relative motion, and so their collision,
    # is that of free flight.
    args = dict(positions=[[2.0, 8.0], [8.0, 8.0]], velocities=[[1.0, 0.0], [-1.0, 0.0]],
                radii=1.0, box=(10.0, 20.0), boundary="walls")
    free = edmd.Simulation.from_arrays(**args)
    field = edmd.Simulation.from_arrays(**args, gravity={"g": -0.5})
    for s in (free, field):
        s.run(until=3.0)
        assert s.stats["disc_disc"] == 1 and s.stats["wall"] == 0
    assert field.velocities[:, 0] == pytest.approx(free.velocities[:, 0], abs=1e-14)
    assert field.velocities[:, 1] == pytest.approx([-1.5, -1.5], abs=1e-14)
    assert field.positions[:, 1] == pytest.approx([8.0 - 0.25 * 9.0] * 2, abs=1e-14)


# --- columns of fluid ------------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("boundary", [None, "walls"])
def test_a_column_of_fluid_keeps_kinetic_plus_potential_energy(dim, boundary):
    sim = column(dim, boundary=boundary)
    assert sim.boundary[-1] == "walls"
    assert sim.boundary[0] == (boundary or "periodic")
    assert sim.gravity == {"axis": dim - 1, "g": -1.0}
    e0, field0 = energy(sim), sim.field_energy
    assert sim.potential_energy == field0 > 0.0
    sim.run(until=10.0)
    assert sim.stats["disc_disc"] > 1000 and sim.stats["wall"] > 0
    assert abs(energy(sim) - e0) < 1e-11 * e0
    # The column settles: the field's energy goes into motion.
    assert sim.field_energy < field0
    assert np.all(sim.positions[:, -1] > sim.radii - 1e-9)
    assert np.all(sim.positions[:, -1] < sim.box[-1] - sim.radii + 1e-9)


def test_a_granular_column_loses_energy_only_in_its_collisions():
    sim = column(restitution={"all": 0.8, "walls": 0.9, "tc": 1e-3})
    e0 = energy(sim)
    sim.run(until=10.0)
    assert 0.1 * e0 < sim.dissipated < e0
    assert abs(energy(sim) + sim.dissipated - e0) < 1e-9 * e0


def test_set_gravity_sets_moves_and_removes_the_field_keeping_the_velocities():
    sim = edmd.gen.fluid(n=200, packing=0.3, boundary="walls", seed=2)
    assert sim.gravity is None and sim.field_energy == 0.0
    e0 = sim.kinetic_energy
    sim.run(until=1.0)
    v = sim.velocities
    sim.set_gravity(-0.5)
    assert np.array_equal(sim.velocities, v)
    assert sim.gravity == {"axis": 1, "g": -0.5}
    heights = sim.positions[:, 1]
    assert sim.field_energy == pytest.approx(0.5 * np.sum(sim.masses * heights), rel=1e-12)
    e1 = energy(sim)
    assert e1 == pytest.approx(e0 + sim.field_energy, rel=1e-12)
    sim.run(until=3.0)
    assert abs(energy(sim) - e1) < 1e-11 * e1
    # From its own dict, as keywords or whole: the field it has, which changes nothing, to
    # the bit; along x by name.
    before = sim.checkpoint()
    sim.set_gravity(**sim.gravity)
    assert sim.gravity == {"axis": 1, "g": -0.5}
    sim.set_gravity(sim.gravity)
    assert sim.gravity == {"axis": 1, "g": -0.5}
    assert sim.checkpoint() == before
    sim.set_gravity(np.float32(2.0), axis="x")
    assert sim.gravity == {"axis": 0, "g": 2.0}
    sim.set_gravity({"axis": np.int64(1), "g": -1})
    assert sim.gravity == {"axis": 1, "g": -1.0}
    e2 = energy(sim)
    sim.run(until=4.0)
    assert abs(energy(sim) - e2) < 1e-11 * e2
    # Removed: straight flights from the velocities the discs have now.
    v = sim.velocities
    sim.set_gravity(None)
    assert sim.gravity is None and sim.field_energy == 0.0
    assert np.array_equal(sim.velocities, v)
    e3 = sim.kinetic_energy
    sim.run(until=6.0)
    assert sim.kinetic_energy == pytest.approx(e3, rel=1e-12)


def test_the_energy_measurement_counts_the_field():
    sim = column(n=100)
    sim.measure("energy", every=0.5)
    sim.run(until=5.0)
    table = sim.results()["tables"]["energy"]
    total = [k for k in table if "total" in k]
    assert total, list(table)
    t = table[total[0]]
    assert np.allclose(t, t[0], rtol=1e-10, atol=0.0)


# --- pickles, checkpoints and files ----------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_pickles_carry_the_field_and_continue_bit_for_bit(dim):
    sim = column(dim, seed=5, restitution={"all": 0.9, "tc": 1e-2})
    sim.run(until=2.0)
    restored = pickle.loads(pickle.dumps(sim))
    copied = copy.deepcopy(sim)
    for s in (restored, copied):
        assert s.gravity == sim.gravity
        assert s.field_energy.hex() == sim.field_energy.hex()
        assert np.array_equal(s.velocities, sim.velocities)
    for s in (sim, restored, copied):
        s.run(until=4.0)
    for s in (restored, copied):
        assert np.array_equal(s.positions, sim.positions)
        assert np.array_equal(s.velocities, sim.velocities)
        assert s.field_energy.hex() == sim.field_energy.hex()
        assert s.dissipated.hex() == sim.dissipated.hex()
        assert s.stats == sim.stats
        assert s.checkpoint() == sim.checkpoint()


def test_a_checkpoint_file_carries_the_field(tmp_path):
    sim = column(seed=6)
    sim.run(until=1.0)
    sim.write(tmp_path / "s.ck")
    back = edmd.Simulation.from_file(tmp_path / "s.ck")
    assert back.gravity == sim.gravity
    for s in (sim, back):
        s.run(until=2.0)
    assert np.array_equal(back.positions, sim.positions)
    assert np.array_equal(back.velocities, sim.velocities)


# The dropped disc of the first test, a disc thrown sideways, and a periodic x axis.
PRINCETON = """\
2
# edmd box 10 10
# edmd boundary periodic walls
# edmd gravity y -2
5.0 8.0 0.0 0.0 0.5 3.0 0 0 255
2.0 3.0 1.0 2.0 0.5 1.0 255 0 0
"""


def test_from_file_reads_the_field_and_write_puts_it_back(tmp_path):
    path = tmp_path / "drop.txt"
    path.write_text(PRINCETON)
    sim = edmd.Simulation.from_file(path)
    assert sim.gravity == {"axis": 1, "g": -2.0}
    assert sim.boundary == ("periodic", "walls")
    e0 = energy(sim)
    assert sim.field_energy == 2.0 * (3.0 * 8.0 + 1.0 * 3.0)
    # The same system from arrays runs the same, bit for bit.
    arrays = edmd.Simulation.from_arrays(sim.positions, sim.velocities, sim.radii,
                                         masses=sim.masses, box=sim.box, boundary=sim.boundary,
                                         gravity=sim.gravity)
    for s in (sim, arrays):
        s.run(until=5.0)
    assert np.array_equal(arrays.positions, sim.positions)
    assert np.array_equal(arrays.velocities, sim.velocities)
    assert abs(energy(sim) - e0) <= 1e-12 * e0
    out = tmp_path / "out.txt"
    sim.write(out)
    text = out.read_text()
    assert "# edmd gravity y -2.0\n" in text
    back = edmd.Simulation.from_file(out)
    assert back.gravity == sim.gravity
    assert np.array_equal(back.velocities, sim.velocities)
    again = tmp_path / "again.txt"
    back.write(again)
    assert again.read_bytes() == out.read_bytes()
    # A text file is no checkpoint: each disc's clock starts again at the file's time, so the
    # parabolas are computed from other points, equal to rounding.
    for s in (sim, back):
        s.run(until=9.0)
    assert np.allclose(back.positions, sim.positions, rtol=0.0, atol=1e-12)
    # What from_arrays makes with a field along x writes it so.
    sideways = drop(axis="x")
    sideways.write(out)
    assert "# edmd gravity x -2.0\n" in out.read_text()
    assert edmd.Simulation.from_file(out).gravity == {"axis": 0, "g": -2.0}


def test_a_3d_file_with_a_field_along_z(tmp_path):
    sim = drop(3)
    path = tmp_path / "drop3.txt"
    sim.write(path)
    assert "# edmd gravity z -2.0\n" in path.read_text()
    back = edmd.Simulation.from_file(path)
    assert back.gravity == {"axis": 2, "g": -2.0} and back.dim == 3


def test_a_file_whose_field_cannot_be_is_refused_naming_the_line(tmp_path):
    path = tmp_path / "bad.txt"
    for old, new, words in [
        ("gravity y -2", "gravity x -2", r"bad\.txt:4: .*axis x must have walls"),
        ("gravity y -2", "gravity y 0", r"bad\.txt:4: "),
        ("gravity y -2", "gravity z -2", r"bad\.txt:4: "),
        ("gravity y -2", "gravity y -2\n# edmd gravity y -1", r"bad\.txt:5: "),
        ("gravity y -2", "gravity y -2\n# edmd restitution 0.5", r"bad\.txt:4: .*TC model"),
    ]:
        path.write_text(PRINCETON.replace(old, new))
        with pytest.raises(ValueError, match=words):
            edmd.Simulation.from_file(path)
    path.write_text(PRINCETON)
    with pytest.raises(ValueError, match=r"bad\.txt: gravity: .*multi-disc"):
        edmd.Simulation.from_file(path, multi=True)


def test_states_without_a_place_for_the_field_are_refused(tmp_path):
    # GSD, XYZ and course states hold no field: writing one would lose it without a word, so
    # it is refused, and nothing is written.
    sim = drop()
    for kind in ("gsd", "xyz", "course"):
        out = tmp_path / f"state.{kind}"
        with pytest.raises(ValueError, match="no place for the field"):
            sim.write(str(out), format=kind)
        assert not out.exists()
    kept = tmp_path / "s.txt"
    kept.write_text("keep me\n")
    with pytest.raises(ValueError, match="course format.*field"):
        sim.write(kept, format="course")
    assert kept.read_text() == "keep me\n"
    sim.set_gravity(None)
    sim.write(tmp_path / "state.xyz")  # no field: any format


# --- the generators and the command line -----------------------------------------------------


@pytest.mark.parametrize("kind,kw,cli", [
    ("fluid", dict(n=200, packing=0.3), ["--n", "200", "--packing", "0.3"]),
    ("fluid", dict(n=200, packing=0.3, boundary="walls"),
     ["--n", "200", "--packing", "0.3", "--boundary", "walls"]),
    ("fluid", dict(n=200, dim=3), ["--n", "200", "--dim", "3"]),
    ("mixture", dict(n=200, size_ratio=1.4), ["--n", "200", "--size-ratio", "1.4"]),
    ("single", dict(speed=1.0), ["--speed", "1"]),
    ("head_on", dict(), []),
    ("lattice", dict(n=100), ["--n", "100"]),
])
def test_generated_systems_and_their_runs_match_the_cli(tmp_path, edmd_cli, kind, kw, cli):
    gen_file = tmp_path / "cli.txt"
    subprocess.run([edmd_cli, "gen", kind.replace("_", "-"), *cli, "--gravity", "-1.5",
                    "--seed", "7", "-o", str(gen_file)], check=True, capture_output=True)
    sim = getattr(edmd.gen, kind)(seed=7, gravity=-1.5, **kw)
    dim = kw.get("dim", 2)
    assert sim.gravity == {"axis": dim - 1, "g": -1.5}
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == gen_file.read_bytes()
    out = tmp_path / "cli-out.txt"
    subprocess.run([edmd_cli, "run", str(gen_file), "--until", "3", "--output", str(out)],
                   check=True, capture_output=True)
    ran = edmd.Simulation.from_file(gen_file)
    for s in (ran, sim):
        s.run(until=3.0)
        s.write(mine)
        assert mine.read_bytes() == out.read_bytes()


def test_a_granular_column_matches_the_cli(tmp_path, edmd_cli):
    gen_file = tmp_path / "cli.txt"
    subprocess.run([edmd_cli, "gen", "fluid", "--n", "200", "--gravity", "-1",
                    "--restitution", "0.8", "--restitution", "tc 0.001", "--seed", "3",
                    "-o", str(gen_file)], check=True, capture_output=True)
    sim = edmd.gen.fluid(n=200, seed=3, gravity=-1, restitution={"all": 0.8, "tc": 1e-3})
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == gen_file.read_bytes()
    out = tmp_path / "cli-out.txt"
    subprocess.run([edmd_cli, "run", str(gen_file), "--until", "3", "--output", str(out)],
                   check=True, capture_output=True)
    sim.run(until=3.0)
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()


def test_a_checkpoint_written_in_a_field_continues_in_the_cli(tmp_path, edmd_cli):
    sim = column(seed=4)
    sim.run(until=1.0)
    sim.write(tmp_path / "s.ck")
    out = tmp_path / "cli-out.txt"
    subprocess.run([edmd_cli, "run", str(tmp_path / "s.ck"), "--until", "2", "--output",
                    str(out)], check=True, capture_output=True)
    sim.run(until=2.0)
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()


def test_generators_refuse_a_field_with_what_the_command_refuses_it_with():
    with pytest.raises(ValueError, match="gen fluid: gravity does not go with well or shoulder"):
        edmd.gen.fluid(n=20, well=1.5, gravity=-1.0)
    with pytest.raises(ValueError, match=r"^gen fluid: gravity 0: .*other than 0"):
        edmd.gen.fluid(n=20, gravity=0.0)
    with pytest.raises(ValueError, match=r"^gravity: .*finite"):
        edmd.gen.fluid(n=20, gravity=INF)
    with pytest.raises(TypeError, match=r"^gravity: expected a number"):
        edmd.gen.fluid(n=20, gravity="-1")
    # Inelastic collisions in a field without the TC model collapse on the floor: refused as
    # `edmd gen --gravity --restitution` refuses them.
    with pytest.raises(ValueError, match=r"^restitution: .*need the TC model"):
        edmd.gen.fluid(n=20, gravity=-1.0, restitution=0.9)
    with pytest.raises(ValueError, match=r"^restitution: .*walls' restitution must be above 0"):
        edmd.gen.fluid(n=20, gravity=-1.0, restitution={"walls": 0.0, "tc": 1e-3})
    # Elastic restitution is none, and goes with a field.
    assert edmd.gen.fluid(n=20, gravity=-1.0, restitution=1.0).restitution is None
    assert edmd.gen.fluid(n=20, gravity=None).gravity is None


def test_the_command_refuses_what_the_generators_refuse(tmp_path, edmd_cli):
    out = tmp_path / "x.txt"
    run = subprocess.run([edmd_cli, "gen", "fluid", "--n", "20", "--gravity", "-1",
                          "--restitution", "0.9", "-o", str(out)], capture_output=True, text=True)
    assert run.returncode != 0 and "TC model" in run.stderr
    assert not out.exists()


# --- what a field does not go with -----------------------------------------------------------


def pair(**kw):
    args = dict(positions=[[2.0, 5.0], [8.0, 5.0]], velocities=[[1.0, 0.0], [-1.0, 0.0]],
                radii=1.0, box=(10.0, 10.0), boundary="walls")
    args.update(kw)
    return edmd.Simulation.from_arrays(**args)


def test_a_field_along_a_periodic_axis_is_refused():
    with pytest.raises(ValueError, match=r"^gravity: the field's axis y must have walls"):
        pair(boundary="periodic", gravity=-1.0)
    with pytest.raises(ValueError, match=r"^gravity\['axis'\]: the field's axis x must have"):
        pair(boundary=("periodic", "walls"), gravity={"axis": "x", "g": -1.0})
    sim = pair(boundary=("periodic", "walls"))
    for axis in (0, "x"):
        with pytest.raises(ValueError, match=r"^axis: the field's axis x must have walls"):
            sim.set_gravity(-1.0, axis=axis)
    assert sim.gravity is None
    sim.set_gravity(-1.0)  # y has walls
    with pytest.raises(ValueError, match=r"^axis: "):
        sim.set_gravity(-1.0, axis=0)
    assert sim.gravity == {"axis": 1, "g": -1.0}


@pytest.mark.parametrize("kwargs,words", [
    (dict(potential={(0, 0): [(2.5, -1.0)]}), "stepped potential"),
    (dict(multi=True), "multi-disc collisions"),
])
def test_a_field_needs_hard_cores_and_binary_collisions(kwargs, words):
    with pytest.raises(ValueError, match=rf"^gravity: .*{words}"):
        pair(gravity=-1.0, **kwargs)
    sim = pair(**kwargs)
    with pytest.raises(ValueError, match=rf"^g: .*{words}"):
        sim.set_gravity(-1.0)
    assert sim.gravity is None


def test_inelastic_collisions_in_a_field_need_the_tc_model():
    # Set either way round, and through from_arrays: refused, and nothing changes.
    with pytest.raises(ValueError, match=r"^restitution: inelastic collisions in a field need "
                                         r"the TC model"):
        pair(gravity=-1.0, restitution=0.5)
    field = pair(gravity=-1.0)
    with pytest.raises(ValueError, match=r"^restitution: .*TC model"):
        field.set_restitution(0.5)
    with pytest.raises(ValueError, match=r"^restitution: .*walls' restitution must be above 0"):
        field.set_restitution({"walls": 0.0, "tc": 0.1})
    assert field.restitution is None and field.gravity == {"axis": 1, "g": -1.0}
    field.set_restitution({"all": 0.5, "tc": 0.1})
    assert field.restitution["tc"] == 0.1
    inelastic = pair(restitution=0.5)
    with pytest.raises(ValueError, match=r"^g: inelastic collisions in a field need the TC"):
        inelastic.set_gravity(-1.0)
    assert inelastic.gravity is None and inelastic.restitution["all"] == 0.5
    # With the TC model (and in from_arrays, the field is set first, as in a file).
    both = pair(gravity=-1.0, restitution={"all": 0.5, "tc": 0.1})
    assert both.gravity == {"axis": 1, "g": -1.0} and both.restitution["all"] == 0.5
    with pytest.raises(ValueError, match=r"^restitution: .*TC model"):
        both.set_restitution(0.5)
    assert both.restitution["tc"] == 0.1


# --- bad input -------------------------------------------------------------------------------

BAD_G = [0, 0.0, -0.0, NAN, INF, -INF, "1", b"1", True, 1 + 1j, [1.0], (1.0,), np.array([1.0]),
         object(), {"g": 0.0}, {"g": "1"}, {"axis": 1}, {"g": 1.0, "gravity": 1.0}, {}]
BAD_AXIS = [3, -1, 2**70, 1.5, True, "w", "X", "", b"x", [1], None.__class__, object()]


@pytest.mark.parametrize("k", range(len(BAD_G)))
def test_bad_g_raises_naming_the_argument(k):
    value = BAD_G[k]
    sim = drop()
    sim.run(until=1.0)
    before = sim.checkpoint()
    with pytest.raises((ValueError, TypeError)) as info:
        sim.set_gravity(value)
    message = str(info.value)
    assert message.startswith("g: "), message
    one_line(message)
    assert sim.checkpoint() == before
    with pytest.raises((ValueError, TypeError)) as info:
        pair(gravity=value)
    assert str(info.value).startswith("gravity"), str(info.value)
    one_line(str(info.value))


@pytest.mark.parametrize("k", range(len(BAD_AXIS)))
def test_bad_axis_raises_naming_the_argument(k):
    value = BAD_AXIS[k]
    sim = drop()
    before = sim.checkpoint()
    with pytest.raises((ValueError, TypeError)) as info:
        sim.set_gravity(-1.0, axis=value)
    assert str(info.value).startswith("axis: "), str(info.value)
    one_line(str(info.value))
    assert sim.checkpoint() == before
    with pytest.raises((ValueError, TypeError)) as info:
        pair(gravity={"axis": value, "g": -1.0})
    assert str(info.value).startswith("gravity['axis']: "), str(info.value)


def one_line(message):
    assert "\n" not in message, message
    assert not re.search(r"[0-9]{30}", message), message
    assert "Can't extract" not in message and "panic" not in message.lower(), message


def test_the_kinds_of_error():
    sim = drop()
    with pytest.raises(TypeError, match=r"^g: expected a number"):
        sim.set_gravity("1")
    with pytest.raises(ValueError, match=r"^g: the acceleration must be a finite number other "
                                         r"than 0 \(negative pulls towards 0\), got 0\.0$"):
        sim.set_gravity(0)
    with pytest.raises(ValueError, match=r"^axis: a 2D simulation has axes 0, 1 \('x', 'y'\), "
                                         r"got 2$"):
        sim.set_gravity(-1.0, axis=2)
    with pytest.raises(ValueError, match=r"^axis: a 2D simulation has axes"):
        sim.set_gravity(-1.0, axis="z")
    with pytest.raises(TypeError, match=r"^axis: expected 0, 1, 2 or 'x', 'y', 'z', got float"):
        sim.set_gravity(-1.0, axis=1.0)
    with pytest.raises(ValueError, match=r"^axis: goes with g"):
        sim.set_gravity(None, axis=1)
    with pytest.raises(ValueError, match=r"^axis: give the axis in the dict"):
        sim.set_gravity({"axis": 1, "g": -1.0}, axis=1)
    with pytest.raises(ValueError, match=r"^g: unknown key 'G'"):
        sim.set_gravity({"G": -1.0})
    with pytest.raises(ValueError, match=r"^gravity: the dict form needs 'g'"):
        pair(gravity={"axis": 1})
    with pytest.raises(ValueError, match=r"^gravity\['g'\]: the acceleration must be"):
        pair(gravity={"g": NAN})
    with pytest.raises(ValueError, match=r"^gravity: the acceleration must be .*got -inf$"):
        pair(gravity=-INF)
    with pytest.raises(TypeError, match="missing 1 required positional argument"):
        sim.set_gravity()
    with pytest.raises(TypeError):
        sim.set_gravity(-1.0, 1)  # axis is keyword-only
    assert sim.gravity == {"axis": 1, "g": -2.0}


def test_zero_particles_in_a_field():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      boundary="walls", gravity=-1.0)
    assert sim.field_energy == 0.0 and sim.potential_energy == 0.0
    sim.run(until=1.0)
    sim.run(events=10)
    assert pickle.loads(pickle.dumps(sim)).gravity == sim.gravity
    sim.set_gravity(None)
    sim.set_gravity(1.0, axis="x")
