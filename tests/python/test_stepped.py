"""Stepped pair potentials (square wells, shoulders, ramps of steps) and the Andersen thermostat
from Python: `from_arrays(potential=...)`, `gen.fluid(well=..., shoulder=...)`, the
`potential`, `potential_energy`, `shells`, `shell_counts` and `thermostat` properties,
`set_thermostat`, the "step" and "thermostat" counts in `stats`, files with a
`# edmd potential` line read and written, and pickles that carry it all."""

import copy
import math
import pickle
import re
import subprocess

import numpy as np
import pytest

import edmd

NAN, INF = math.nan, math.inf
WELL = {(0, 0): [(1.5, -1.0)]}


def pair(**kw):
    """Two discs of diameter 1, 3 apart, closing at speed 1, in a 20 x 20 periodic box."""
    args = dict(positions=[[5.0, 10.0], [8.0, 10.0]], velocities=[[0.5, 0.0], [-0.5, 0.0]],
                radii=0.5, box=(20.0, 20.0))
    args.update(kw)
    return edmd.Simulation.from_arrays(**args)


def total(sim):
    return sim.kinetic_energy + sim.potential_energy


# --- kinematics from arrays ------------------------------------------------------------------


def test_square_well_pair_enters_collides_and_leaves():
    sim = pair(potential=WELL)
    assert sim.potential == WELL
    assert sim.potential_energy == 0.0
    e0 = total(sim)
    sim.run(until=10.0)
    # In at t = 1.5 (closing speed 1 up to sqrt(5)), a hard-core collision at about 1.72, out
    # again at about 1.95.
    assert abs(total(sim) - e0) < 1e-12
    assert sim.potential_energy == 0.0
    assert sim.stats["step"] == 2
    assert sim.stats["disc_disc"] == 1
    assert sim.stats["thermostat"] == 0
    assert sim.shells.shape == (0, 3) and sim.shell_counts == {}
    # Leaving the well costs what entering gave: the discs recede at speed 1/2 each again.
    assert np.allclose(sim.velocities, [[-0.5, 0.0], [0.5, 0.0]], atol=1e-12)


def test_square_well_pair_inside_the_well():
    sim = pair(potential=WELL)
    sim.run(until=1.6)  # in the well from t = 1.5, before the collision at about 1.72
    assert sim.stats["disc_disc"] == 0
    assert sim.potential_energy == -1.0
    assert sim.kinetic_energy == pytest.approx(1.25, abs=1e-12)
    assert sim.shells.tolist() == [[0, 1, 1]]
    assert sim.shells.dtype == np.int64
    assert sim.shell_counts == {1: 1}
    assert sim.stats["step"] == 1


def test_a_shoulder_too_high_to_climb_turns_the_pair_back():
    sim = pair(potential={(0, 0): [(1.5, 1.0)]})  # relative KE 1/4 < 1: a bounce at 1.5
    sim.run(until=10.0)
    assert sim.stats["step"] == 1 and sim.stats["disc_disc"] == 0
    assert sim.potential_energy == 0.0
    assert np.allclose(sim.velocities, [[-0.5, 0.0], [0.5, 0.0]], atol=1e-12)
    # Three steps apart, both discs of species 0, with the dict form and its core.
    ramp = pair(potential={(0, 0): {"core": 1.0, "steps": [(1.2, -0.5), (1.5, 0.1), (2.0, -0.2)]}})
    e0 = total(ramp)
    ramp.run(until=2.0)  # in, through all three, a collision, and out past 1.2 again
    assert ramp.shell_counts == {2: 1}
    assert ramp.potential_energy == pytest.approx(-0.1, abs=1e-15)
    assert abs(total(ramp) - e0) < 1e-12
    assert ramp.potential == {(0, 0): [(1.2, -0.5), (1.5, 0.1), (2.0, -0.2)]}


def test_two_species_only_the_named_pair_interacts():
    # Species 0 and 1 have a well; 0-0 and 1-1 pairs are hard cores.
    pos = [[2.0, 10.0], [5.0, 10.0], [2.0, 2.0], [5.0, 2.0]]
    vel = [[0.5, 0.0], [-0.5, 0.0], [0.5, 0.0], [-0.5, 0.0]]
    sim = edmd.Simulation.from_arrays(pos, vel, radii=0.5, box=(20, 20), species=[0, 1, 0, 0],
                                      potential={(0, 1): {"core": 1.0, "steps": [(1.5, -1.0)]}})
    sim.run(until=1.8)
    assert sim.shells.tolist() == [[0, 1, 1]]
    assert sim.potential == {(0, 1): [(1.5, -1.0)]}
    assert sim.stats["step"] == 1 and sim.stats["disc_disc"] == 1  # 0-1 in the well; 2-3 hard


def test_spheres_from_arrays_with_a_well():
    sim = edmd.Simulation.from_arrays([[5.0, 10.0, 10.0], [8.0, 10.0, 10.0]],
                                      [[0.5, 0.0, 0.0], [-0.5, 0.0, 0.0]], radii=0.5,
                                      box=(20.0, 20.0, 20.0), potential=WELL)
    e0 = total(sim)
    sim.run(until=10.0)
    assert abs(total(sim) - e0) < 1e-12
    assert sim.stats["step"] == 2 and sim.potential_energy == 0.0


def test_hard_cores_have_no_potential():
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    assert sim.potential is None
    assert sim.potential_energy == 0.0
    assert sim.shells.shape == (0, 3)
    assert sim.shell_counts == {}
    assert sim.thermostat is None
    assert pair(potential={}).potential is None
    assert pair(potential={(0, 0): []}).potential is None


def test_pairs_given_no_steps_are_hard_cores_and_not_given_back(tmp_path):
    sim = pair(species=[0, 1], potential={(0, 0): [], (0, 1): [(1.5, -1.0)]})
    assert sim.potential == {(0, 1): [(1.5, -1.0)]}
    sim.write(tmp_path / "s.txt")
    assert edmd.Simulation.from_file(tmp_path / "s.txt").potential == sim.potential
    assert pair(potential=None).potential is None


# --- generated fluids ------------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_square_well_fluid_conserves_kinetic_plus_potential_energy(dim):
    sim = edmd.gen.fluid(n=300, packing=0.3 if dim == 2 else 0.2, dim=dim, well=1.5, seed=2)
    assert sim.potential == {(0, 0): [(1.5, -1.0)]}  # the generator's diameter is 1
    assert sim.potential_energy < 0
    assert sum(sim.shell_counts.values()) == len(sim.shells) == -sim.potential_energy
    e0 = total(sim)
    sim.run(until=20.0)
    assert sim.stats["step"] > 1000 and sim.stats["thermostat"] == 0
    assert abs(total(sim) - e0) < 1e-9 * abs(e0) + 1e-9
    assert sum(sim.shell_counts.values()) == -sim.potential_energy


def test_shoulder_depth_and_kt():
    sim = edmd.gen.fluid(n=100, packing=0.3, shoulder=1.2, depth=0.5, kt=2.0, seed=3)
    assert sim.potential == {(0, 0): [(1.2, 0.5)]}
    assert sim.kinetic_energy / sim.n == pytest.approx(2.0)
    assert sim.potential_energy == 0.5 * len(sim.shells)
    hot = edmd.gen.fluid(n=100, packing=0.3, kt=2.0, seed=3)
    assert hot.potential is None
    assert np.array_equal(hot.velocities, sim.velocities)


def test_the_measurements_energy_and_rdf():
    sim = edmd.gen.fluid(n=200, packing=0.3, well=1.5, seed=4)
    sim.measure("energy", "rdf", every=0.5)
    sim.run(until=5.0)
    r = sim.results()
    e = r["energy"]
    assert e["samples"] == 10
    assert e["total_per_particle"]["value"] == pytest.approx(total(sim) / sim.n, rel=1e-9)
    assert e["relative_drift"] < 1e-9
    tables = r["tables"]
    assert set(tables["energy"]) >= {"time", "kinetic_per_particle", "potential_per_particle",
                                     "total_per_particle"}
    assert len(tables["energy"]["time"]) == 10
    g = tables["rdf"]
    assert len(g["r"]) == len(g["g"]) > 10
    # No pair closer than the hard core; g jumps at the well's edge (more pairs inside).
    assert np.all(g["g"][g["r"] < 0.95] == 0)
    inside = g["g"][(g["r"] > 1.05) & (g["r"] < 1.45)].mean()
    outside = g["g"][(g["r"] > 1.55) & (g["r"] < 1.95)].mean()
    assert inside > outside


# --- the thermostat --------------------------------------------------------------------------


def test_the_thermostat_holds_kt():
    sim = edmd.gen.fluid(n=500, packing=0.3, well=1.5, seed=3)
    assert sim.thermostat is None
    sim.set_thermostat(kT=2.0, rate=1.0, seed=5)
    assert sim.thermostat == {"kT": 2.0, "rate": 1.0, "seed": 5}
    sim.run(until=10.0)  # from kT = 1 to the bath's
    samples = []
    sim.run(until=50.0, callback=lambda s: samples.append(s.kinetic_energy / s.n),
            callback_every=0.1)
    assert len(samples) == 400
    assert np.mean(samples) == pytest.approx(2.0, rel=0.03)
    assert sim.stats["thermostat"] > 0.8 * 500 * 50
    sim.set_thermostat(None)
    assert sim.thermostat is None
    count = sim.stats["thermostat"]
    e0 = total(sim)
    sim.run(until=55.0)
    assert sim.stats["thermostat"] == count
    assert abs(total(sim) - e0) < 1e-9 * abs(e0)


def test_set_thermostat_again_from_its_own_dict():
    sim = edmd.gen.fluid(n=50, packing=0.3, seed=1)
    sim.set_thermostat(kT=1.5, rate=0.5)
    assert sim.thermostat == {"kT": 1.5, "rate": 0.5, "seed": 1}
    other = edmd.gen.fluid(n=50, packing=0.3, seed=1)
    other.set_thermostat(**sim.thermostat)
    for s in (sim, other):
        s.run(until=5.0)
    assert np.array_equal(sim.positions, other.positions)
    assert sim.stats["thermostat"] > 0


# --- pickling --------------------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_pickle_carries_potential_shells_and_thermostat(dim):
    sim = edmd.gen.fluid(n=200, packing=0.3 if dim == 2 else 0.2, dim=dim, well=1.5, seed=6)
    sim.set_thermostat(kT=1.3, rate=0.7, seed=9)
    sim.measure("energy", every=0.5)
    sim.run(until=4.3)
    restored = pickle.loads(pickle.dumps(sim))
    copied = copy.deepcopy(sim)
    for s in (restored, copied):
        assert s.potential == sim.potential
        assert s.thermostat == sim.thermostat
        assert np.array_equal(s.shells, sim.shells)
        assert s.potential_energy == sim.potential_energy
        assert s.stats == sim.stats
    for s in (sim, restored, copied):
        s.run(until=12.0)
    for s in (restored, copied):
        assert np.array_equal(s.positions, sim.positions)
        assert np.array_equal(s.velocities, sim.velocities)
        assert np.array_equal(s.shells, sim.shells)
        assert s.stats == sim.stats
        assert s.results()["energy"] == sim.results()["energy"]


def test_checkpoint_file_carries_it_all(tmp_path):
    sim = pair(potential=WELL)
    sim.run(until=1.6)  # inside the well
    sim.set_thermostat(kT=0.5, rate=0.2, seed=3)
    sim.write(tmp_path / "s.ck")
    back = edmd.Simulation.from_file(tmp_path / "s.ck")
    assert back.potential == WELL and back.thermostat == sim.thermostat
    assert back.shells.tolist() == [[0, 1, 1]]
    for s in (sim, back):
        s.run(until=20.0)
    assert np.array_equal(back.positions, sim.positions)


# --- files -----------------------------------------------------------------------------------

PRINCETON = """\
3
# edmd box 20 20
# edmd boundary periodic periodic
# edmd potential 0 0 1.2 -0.5 1.5 0.25
# edmd potential 0 1 1.5 -1
5.0 10.0 0.5 0.0 0.5 1.0 0 0 0 0
6.3 10.0 -0.5 0.0 0.5 1.0 0 0 0 0
10.0 5.0 0.0 0.0 0.5 2.0 0 0 0 1
"""


def test_from_file_reads_the_potential(tmp_path):
    path = tmp_path / "w.txt"
    path.write_text(PRINCETON)
    sim = edmd.Simulation.from_file(path)
    assert sim.potential == {(0, 0): [(1.2, -0.5), (1.5, 0.25)], (0, 1): [(1.5, -1.0)]}
    # 1.3 apart: inside the outer step, outside the inner one.
    assert sim.shells.tolist() == [[0, 1, 1]]
    assert sim.potential_energy == 0.25
    e0 = total(sim)
    sim.run(until=10.0)
    assert abs(total(sim) - e0) < 1e-12
    assert sim.stats["step"] >= 2


def test_write_puts_the_potential_back_and_reads_back_identically(tmp_path):
    sim = edmd.gen.fluid(n=100, packing=0.3, well=1.5, seed=8)
    sim.run(until=3.0)
    out = tmp_path / "s.txt"
    sim.write(out)
    text = out.read_text()
    assert "# edmd potential 0 0 1.5 -1" in text
    back = edmd.Simulation.from_file(out)
    assert back.potential == sim.potential
    assert back.time == sim.time
    assert np.array_equal(back.positions, sim.positions)
    assert np.array_equal(back.velocities, sim.velocities)
    assert np.array_equal(back.shells, sim.shells)
    assert back.potential_energy == sim.potential_energy
    # Written again, the same bytes.
    again = tmp_path / "again.txt"
    back.write(again)
    assert again.read_bytes() == out.read_bytes()
    # From arrays too (the Princeton format, as arrays are written).
    arrays = pair(potential={(0, 0): {"core": 1.0, "steps": [(1.5, -1.0)]}})
    arrays.write(tmp_path / "a.txt")
    assert edmd.Simulation.from_file(tmp_path / "a.txt").potential == WELL


def test_the_course_format_refuses_a_stepped_system(tmp_path):
    path = tmp_path / "s.txt"
    path.write_text("keep me\n")
    with pytest.raises(ValueError, match="course format"):
        pair(potential=WELL).write(path, format="course")
    assert path.read_text() == "keep me\n"


def test_generator_and_runs_match_the_cli(tmp_path, edmd_cli):
    cli = tmp_path / "cli.txt"
    subprocess.run([edmd_cli, "gen", "fluid", "--n", "100", "--packing", "0.3", "--well", "1.5",
                    "--kt", "1.5", "--seed", "7", "-o", str(cli)], check=True, capture_output=True)
    sim = edmd.gen.fluid(n=100, packing=0.3, well=1.5, kt=1.5, seed=7)
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == cli.read_bytes()
    # And the run with a thermostat, as `edmd run --thermostat andersen` does it.
    out = tmp_path / "cli-out.txt"
    subprocess.run([edmd_cli, "run", str(cli), "--until", "5", "--thermostat", "andersen",
                    "--kT", "1.2", "--rate", "0.5", "--seed", "4", "--output", str(out)],
                   check=True, capture_output=True)
    sim.set_thermostat(kT=1.2, rate=0.5, seed=4)
    sim.run(until=5.0)
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()


# --- bad input -------------------------------------------------------------------------------

BAD_POTENTIALS = [
    [(1.5, -1.0)], "well", 1.5, {(0, 0): "1.5"}, {(0, 0): 1.5}, {(0, 0): None},
    {(0, 0): [1.5]}, {(0, 0): [(1.5,)]}, {(0, 0): [(1.5, -1.0, 2.0)]}, {(0, 0): [("1.5", -1)]},
    {(0, 0): [(1.5, 1 + 1j)]}, {(0, 0): [(True, -1)]}, {(0, 0): [(1.5, None)]},
    {0: [(1.5, -1.0)]}, {(0,): [(1.5, -1.0)]}, {(0, 0, 0): [(1.5, -1.0)]},
    {("a", 0): [(1.5, -1.0)]}, {(0, True): [(1.5, -1.0)]}, {(0, 1.0): [(1.5, -1.0)]},
    {(0, -1): [(1.5, -1.0)]}, {(0, 70000): [(1.5, -1.0)]}, {(0, 300): [(1.5, -1.0)]},
    {(0, 1): [(1.5, -1.0)]},                                   # no disc of species 1
    {(0, 0): [(0.5, -1.0)]}, {(0, 0): [(1.0, -1.0)]},          # inside the hard core
    {(0, 0): [(2.0, -1.0), (1.5, -1.0)]}, {(0, 0): [(1.5, -1.0), (1.5, 1.0)]},
    {(0, 0): [(NAN, -1.0)]}, {(0, 0): [(INF, -1.0)]}, {(0, 0): [(-1.5, -1.0)]},
    {(0, 0): [(1.5, NAN)]}, {(0, 0): [(1.5, -INF)]},
    {(0, 0): [(1.5 + 0.01 * k, -1.0) for k in range(300)]},
    {(0, 0): np.array([[1.5, -1.0]], dtype=complex)},
    {(0, 0): {"core": 1.1, "steps": [(1.5, -1.0)]}}, {(0, 0): {"core": -1, "steps": []}},
    {(0, 0): {"core": NAN, "steps": []}}, {(0, 0): {"core": "1", "steps": []}},
    {(0, 0): {"core": 1.0}}, {(0, 0): {"depth": 1.0, "steps": []}},
    {(0, 0): {"steps": "1.5"}},
]


def message_names(message, arg):
    return re.search(rf"(?<![A-Za-z_]){re.escape(arg)}(?![A-Za-z_])", message)


@pytest.mark.parametrize("k", range(len(BAD_POTENTIALS)))
def test_bad_potentials_raise_naming_potential(k):
    value = BAD_POTENTIALS[k]
    with pytest.raises((ValueError, TypeError)) as info:
        pair(potential=value)
    message = str(info.value)
    assert message.startswith("potential: "), message
    assert "\n" not in message and not re.search(r"[0-9]{30}", message), message


def test_a_core_that_is_not_every_pairs_contact_distance_is_refused():
    pos = [[2.0, 2.0], [5.0, 2.0], [8.0, 2.0]]
    vel = np.zeros((3, 2))
    with pytest.raises(ValueError, match=r"potential: \(0, 0\): core 1.0 is not the contact "
                                         r"distance of every pair .* discs 1 and 2"):
        edmd.Simulation.from_arrays(pos, vel, radii=[0.5, 0.5, 0.6], box=(10, 10),
                                    potential={(0, 0): {"core": 1.0, "steps": [(1.5, -1.0)]}})
    # Species 0 with 1: every 0-1 pair must have it.
    with pytest.raises(ValueError, match=r"core 1.1 .* discs 1 and 2 have 0.6 \+ 0.6 = 1.2"):
        edmd.Simulation.from_arrays(pos, vel, radii=[0.5, 0.6, 0.6], box=(10, 10),
                                    species=[0, 0, 1],
                                    potential={(0, 1): {"core": 1.1, "steps": [(1.5, -1.0)]}})
    # Up to rounding: 0.1 + 0.2 is not 0.3 in floating point, but is accepted as it.
    edmd.Simulation.from_arrays(pos, vel, radii=[0.1, 0.1, 0.2], box=(10, 10), species=[0, 0, 1],
                                potential={(0, 1): {"core": 0.3, "steps": [(0.5, -1.0)]}})


@pytest.mark.parametrize("kwargs,words", [(dict(rule="swap"), "elastic rule"),
                                          (dict(multi=True), "multi-disc")])
def test_a_stepped_potential_needs_elastic_binary_collisions(kwargs, words):
    with pytest.raises(ValueError) as info:
        pair(potential=WELL, **kwargs)
    assert "potential" in str(info.value) and words in str(info.value), str(info.value)
    pair(potential={}, **kwargs)  # no steps: hard cores, any rule


THERMOSTAT_CASES = [
    ("kT", [-1, 0, NAN, INF, "1", 1 + 1j, True, [1.0], object()],
     lambda v: dict(kT=v, rate=1.0)),
    ("rate", [-1, 0, NAN, INF, "1", 1 + 1j, True, [1.0], None],
     lambda v: dict(kT=1.0, rate=v)),
    ("seed", [-1, 2**70, 1.5, "1", True, 1 + 1j],
     lambda v: dict(kT=1.0, rate=1.0, seed=v)),
    # rate or seed without kT.
    ("kT", [1.0], lambda v: dict(kT=None, rate=v)),
    ("kT", [1], lambda v: dict(kT=None, seed=v)),
]


@pytest.mark.parametrize("case,k", [(c, k) for c, (_, vs, _) in enumerate(THERMOSTAT_CASES)
                                    for k in range(len(vs))])
def test_bad_thermostats_raise_naming_the_argument(case, k):
    arg, values, make = THERMOSTAT_CASES[case]
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    with pytest.raises((ValueError, TypeError)) as info:
        sim.set_thermostat(**make(values[k]))
    message = str(info.value)
    assert message_names(message, arg), message
    assert "\n" not in message
    assert sim.thermostat is None  # a refused call changes nothing


def test_a_refused_thermostat_keeps_the_one_set():
    sim = edmd.gen.fluid(n=20, packing=0.3, seed=1)
    sim.set_thermostat(kT=1.0, rate=2.0, seed=3)
    with pytest.raises(ValueError, match="rate"):
        sim.set_thermostat(kT=1.0, rate=-2.0)
    assert sim.thermostat == {"kT": 1.0, "rate": 2.0, "seed": 3}


REAL_HOSTILE = [NAN, INF, "1.5", 1 + 1j, True, [1.5], object()]

GEN_CASES = [
    ("well", [-1, 0, 1.0, 0.5, 101, 1e300] + REAL_HOSTILE,
     lambda v: edmd.gen.fluid(n=20, well=v)),
    ("shoulder", [-1, 0, 1.0, 101] + REAL_HOSTILE,
     lambda v: edmd.gen.fluid(n=20, shoulder=v)),
    ("depth", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.fluid(n=100, well=1.5, depth=v)),
    ("depth", [1.0], lambda v: edmd.gen.fluid(n=20, depth=v)),  # without a well
    ("shoulder", [1.5], lambda v: edmd.gen.fluid(n=100, well=1.5, shoulder=v)),  # both
    ("kt", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.fluid(n=20, kt=v)),
    ("rule", ["swap"], lambda v: edmd.gen.fluid(n=100, well=1.5, rule=v)),
    ("multi", [True], lambda v: edmd.gen.fluid(n=100, well=1.5, multi=v)),
]


@pytest.mark.parametrize("case,k", [(c, k) for c, (_, vs, _) in enumerate(GEN_CASES)
                                    for k in range(len(vs))])
def test_bad_generator_options_raise_naming_the_argument(case, k):
    arg, values, call = GEN_CASES[case]
    with pytest.raises((ValueError, TypeError)) as info:
        call(values[k])
    message = str(info.value)
    wanted = {"rule": "elastic rule", "multi": "multi-disc"}.get(arg, arg)
    assert message_names(message, wanted), message
    assert "\n" not in message and not re.search(r"[0-9]{30}", message), message


def test_pack_refuses_a_stepped_start():
    # Packing compresses hard particles: a start with a well would lose its potential.
    sim = edmd.gen.fluid(n=100, packing=0.3, well=1.5, seed=1)
    with pytest.raises(ValueError, match="stepped potential"):
        edmd.pack(start=sim)
