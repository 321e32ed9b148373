"""Inelastic collisions from Python: `from_arrays(restitution=...)`, `set_restitution`, the
generators' `restitution=`, the `restitution` and `dissipated` properties, in 2D and 3D; the
kinematics of one inelastic collision (a constant coefficient, Bridges' law, the walls'), the
accounting of the energy lost, the TC model against inelastic collapse, pickles and
checkpoints that continue bit for bit, files with `# edmd restitution` lines, runs that agree
with `edmd gen --restitution` and `edmd run` to the byte, and the refusal of every bad argument
by name."""

import copy
import math
import pickle
import re
import subprocess
import threading
import time

import numpy as np
import pytest

import edmd

NAN, INF = math.nan, math.inf


def pair(dim=2, speed=2.0, **kw):
    """Discs of masses 1 and 3 (reduced mass 3/4), species 0 and 1, diameter 1, 2 apart, the
    first closing on the second at `speed`, in a periodic box of 20: they meet at t = 1 /
    (2 speed) with normal relative speed `speed`."""
    pos = [[5.0, 5.0, 5.0], [7.0, 5.0, 5.0]]
    vel = [[speed, 0.0, 0.0], [0.0, 0.0, 0.0]]
    args = dict(positions=[p[:dim] for p in pos], velocities=[v[:dim] for v in vel], radii=0.5,
                masses=[1.0, 3.0], box=(20.0,) * dim, species=[0, 1])
    args.update(kw)
    return edmd.Simulation.from_arrays(**args)


def after(e, speed=2.0):
    """The pair's velocities along x after a collision with coefficient e: momentum `speed`
    kept, the relative velocity `speed` reversed and multiplied by e; and the energy lost,
    (1 - e^2) mu speed^2 / 2 with mu = 3/4."""
    v1 = speed * (1.0 + e) / 4.0
    return (speed - 3.0 * v1, v1), (1.0 - e * e) * 0.75 * speed**2 / 2.0


def fluid(dim=2, n=300, seed=1, **kw):
    return edmd.gen.fluid(n=n, packing=0.3 if dim == 2 else 0.2, dim=dim, seed=seed, **kw)


def energy(sim):
    return sim.kinetic_energy + sim.dissipated


# --- one collision, exactly ------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_a_head_on_collision_keeps_e_of_the_normal_velocity(dim):
    # e = 1/2: closing at 2, the pair leaves at 1 apart, momentum 2 kept: -1/4 and 3/4. The
    # energy lost is (1 - 1/4) (3/4) 2^2 / 2 = 9/8.
    sim = pair(dim, restitution=0.5)
    assert sim.dissipated == 0.0
    e0 = sim.kinetic_energy
    sim.run(until=5.0)
    assert sim.stats["disc_disc"] == 1
    (v0, v1), lost = after(0.5)
    assert (v0, v1, lost) == (-0.25, 0.75, 1.125)
    v = sim.velocities
    assert v[:, 0] == pytest.approx([v0, v1], abs=1e-14)
    assert np.all(v[:, 1:] == 0.0)
    assert sim.dissipated == pytest.approx(lost, abs=1e-14)
    assert sim.kinetic_energy == pytest.approx(e0 - lost, abs=1e-14)
    assert v[0, 0] + 3.0 * v[1, 0] == pytest.approx(2.0, abs=1e-14)


def test_e_zero_leaves_the_pair_moving_together_and_e_one_is_the_elastic_rule_to_the_bit():
    stuck = pair(restitution=0.0)
    stuck.run(until=5.0)
    assert stuck.velocities[:, 0] == pytest.approx([0.5, 0.5], abs=1e-14)
    assert stuck.dissipated == pytest.approx(1.5, abs=1e-14)  # all of the normal motion's
    # e = 1 for every pair is no restitution at all: the hard cores' run, bit for bit.
    plain, elastic = pair(), pair(restitution={"all": 1.0, "walls": 1.0})
    assert elastic.restitution is None
    for s in (plain, elastic):
        s.run(until=5.0)
    assert np.array_equal(plain.velocities, elastic.velocities)
    assert elastic.dissipated == 0.0


def test_a_wall_returns_e_of_the_normal_velocity():
    # One disc at speed 2 at 45 degrees into walls of coefficient 1/2: each bounce keeps the
    # tangential velocity and half the normal one, and loses 3/4 of m v_n^2 / 2.
    sim = edmd.Simulation.from_arrays([[5.0, 5.0]], [[2.0, 1.0]], radii=0.5, masses=2.0,
                                      box=(10.0, 10.0), boundary="walls",
                                      restitution={"walls": 0.5})
    assert sim.restitution == {"all": 1.0, "pairs": {}, "walls": 0.5, "tc": 0.0}
    sim.run(until=2.5)  # the right wall at t = 2.25
    assert sim.stats["wall"] == 1
    assert sim.velocities.tolist() == [[-1.0, 1.0]]
    assert sim.dissipated == 0.75 * 2.0 * 4.0 / 2.0
    assert sim.kinetic_energy + sim.dissipated == 5.0 * 2.0 / 2.0
    # Discs among themselves stay elastic: "all" is 1.
    two = pair(restitution={"walls": 0.5})
    two.run(until=5.0)
    assert two.dissipated == 0.0


def test_bridges_law_is_elastic_below_v_c_and_a_power_above():
    law = {"all": {"bridges": 0.5}}
    slow, plain = pair(speed=0.4, restitution=law), pair(speed=0.4)
    for s in (slow, plain):
        s.run(until=5.0)
    assert slow.dissipated == 0.0
    assert np.array_equal(slow.velocities, plain.velocities)
    # At 2 = 4 v_c: e = 4^-0.234.
    fast = pair(restitution=law)
    fast.run(until=5.0)
    e = 4.0 ** -0.234
    (v0, v1), lost = after(e)
    assert fast.velocities[:, 0] == pytest.approx([v0, v1], abs=1e-14)
    assert fast.dissipated == pytest.approx(lost, abs=1e-14)


def test_a_pairs_own_law_overrides_the_common_one_in_either_order():
    for pairs in ({(0, 1): 0.5}, {(1, 0): 0.5}, {(1, 0): 0.5, (0, 0): 0.1}):
        sim = pair(restitution={"all": 0.9, "pairs": pairs})
        sim.run(until=5.0)
        assert sim.velocities[:, 0] == pytest.approx(after(0.5)[0], abs=1e-14)
    other = pair(restitution={"all": 0.9, "pairs": {(0, 0): 0.5, (1, 1): 0.5}})
    other.run(until=5.0)
    assert other.dissipated == pytest.approx(after(0.9)[1], abs=1e-14)


# --- a fluid ---------------------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("restitution", [0.8, {"all": {"bridges": 0.5}, "walls": 0.7,
                                                "tc": 1e-3}])
def test_kinetic_energy_plus_the_energy_lost_is_conserved(dim, restitution):
    sim = fluid(dim, boundary="walls", restitution=restitution)
    e0 = sim.kinetic_energy
    sim.run(until=3.0)
    assert sim.stats["disc_disc"] > 300
    assert 0.1 * e0 < sim.dissipated < e0
    assert abs(energy(sim) - e0) < 1e-9 * e0
    if restitution == 0.8:
        # Momentum is kept in every collision: in a periodic box it stays put.
        periodic = fluid(dim, restitution=restitution)
        p0 = periodic.masses @ periodic.velocities
        periodic.run(until=3.0)
        assert np.allclose(periodic.masses @ periodic.velocities, p0, atol=1e-9)


def test_without_the_tc_model_a_dense_gas_collapses_and_the_run_says_so():
    # e = 0.3 at packing 0.5: discs in clusters lose their relative motion in infinitely many
    # collisions in a finite time (inelastic collapse), and the clock stops. The TC model
    # (collisions within tc of a disc's previous one elastic) lets the gas go on cooling.
    collapse = edmd.gen.fluid(n=300, packing=0.5, seed=3, restitution=0.3)
    with pytest.raises(ValueError, match="clock stopped advancing"):
        collapse.run(until=100.0)
    assert collapse.time < 10.0
    cooled = edmd.gen.fluid(n=300, packing=0.5, seed=3, restitution={"all": 0.3, "tc": 1e-3})
    e0 = cooled.kinetic_energy
    cooled.run(until=20.0)
    assert cooled.time == 20.0 and cooled.kinetic_energy < 0.05 * e0
    assert abs(energy(cooled) - e0) < 1e-9 * e0


def test_set_restitution_sets_replaces_and_removes_it_and_starts_the_loss_again():
    sim = fluid(n=200)
    assert sim.restitution is None and sim.dissipated == 0.0
    sim.set_restitution(0.9)
    sim.run(until=1.0)
    lost = sim.dissipated
    assert lost > 0.0
    # Set again from its own dict: the same restitution, the loss counted from 0 again.
    sim.set_restitution(sim.restitution)
    assert sim.restitution == {"all": 0.9, "pairs": {}, "walls": 1.0, "tc": 0.0}
    assert sim.dissipated == 0.0
    full = {"all": {"bridges": 0.25}, "pairs": {(0, 1): 0.5, (2, 2): {"bridges": 1.5}},
            "walls": 0.75, "tc": 1e-4}
    sim.set_restitution(full)
    assert sim.restitution == full
    again = pair(restitution=sim.restitution)
    assert again.restitution == full
    # Keys left out take their defaults; numpy numbers are numbers.
    sim.set_restitution({"pairs": {(np.int64(0), np.uint8(1)): np.float32(0.5)}})
    assert sim.restitution == {"all": 1.0, "pairs": {(0, 1): 0.5}, "walls": 1.0, "tc": 0.0}
    sim.set_restitution(None)
    assert sim.restitution is None and sim.dissipated == 0.0
    e0 = sim.kinetic_energy
    sim.run(until=2.0)
    assert sim.kinetic_energy == pytest.approx(e0, rel=1e-12)


# --- pickles, checkpoints and files ----------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_pickles_carry_the_restitution_and_continue_bit_for_bit(dim):
    sim = fluid(dim, boundary="walls", seed=5,
                restitution={"all": 0.9, "pairs": {(0, 0): {"bridges": 0.8}}, "walls": 0.6,
                             "tc": 0.05})
    sim.run(until=2.0)
    restored = pickle.loads(pickle.dumps(sim))
    copied = copy.deepcopy(sim)
    for s in (restored, copied):
        assert s.restitution == sim.restitution
        assert s.dissipated.hex() == sim.dissipated.hex()
    for s in (sim, restored, copied):
        s.run(until=4.0)
    for s in (restored, copied):
        assert np.array_equal(s.positions, sim.positions)
        assert np.array_equal(s.velocities, sim.velocities)
        assert s.dissipated.hex() == sim.dissipated.hex()
        assert s.stats == sim.stats
        assert s.checkpoint() == sim.checkpoint()


def test_a_checkpoint_file_carries_the_restitution_and_the_loss(tmp_path):
    sim = fluid(n=200, seed=6, restitution={"all": 0.8, "tc": 0.01})
    sim.run(until=1.0)
    sim.write(tmp_path / "s.ck")
    back = edmd.Simulation.from_file(tmp_path / "s.ck")
    assert back.restitution == sim.restitution and back.dissipated == sim.dissipated
    for s in (sim, back):
        s.run(until=2.0)
    assert np.array_equal(back.velocities, sim.velocities)
    assert back.dissipated == sim.dissipated


# The pair of the head-on test, and two discs at rest far from its path.
PRINCETON = """\
4
# edmd box 20 20
# edmd boundary periodic periodic
# edmd restitution 0.9
# edmd restitution 1 0 0.5
# edmd restitution 1 1 bridges 0.25
# edmd restitution walls 0.75
# edmd restitution tc 0.001
5.0 5.0 2.0 0.0 0.5 1.0 0 0 255 0
7.0 5.0 0.0 0.0 0.5 3.0 255 0 0 1
5.0 15.0 0.0 0.0 0.5 1.0 0 0 255 0
7.0 15.0 0.0 0.0 0.5 1.0 255 0 0 1
"""

FROM_FILE = {"all": 0.9, "pairs": {(1, 0): 0.5, (1, 1): {"bridges": 0.25}}, "walls": 0.75,
             "tc": 0.001}


def test_from_file_reads_the_restitution_and_write_puts_it_back(tmp_path):
    path = tmp_path / "pair.txt"
    path.write_text(PRINCETON)
    sim = edmd.Simulation.from_file(path)
    assert sim.restitution == FROM_FILE
    sim.run(until=5.0)
    assert sim.velocities[:2, 0] == pytest.approx(after(0.5)[0], abs=1e-14)
    assert sim.dissipated == pytest.approx(after(0.5)[1], abs=1e-14)
    out = tmp_path / "out.txt"
    sim.write(out)
    text = out.read_text()
    for line in PRINCETON.splitlines():
        if line.startswith("# edmd restitution"):
            assert line + "\n" in text
    back = edmd.Simulation.from_file(out)
    assert back.restitution == sim.restitution
    assert np.array_equal(back.velocities, sim.velocities)
    again = tmp_path / "again.txt"
    back.write(again)
    assert again.read_bytes() == out.read_bytes()
    # What from_arrays makes with the same restitution writes the same file.
    arrays = edmd.Simulation.from_arrays(sim.positions, sim.velocities, sim.radii,
                                         masses=sim.masses, box=sim.box, species=sim.species,
                                         restitution=sim.restitution)
    mine = tmp_path / "mine.txt"
    arrays.write(mine)
    assert [l for l in mine.read_text().splitlines() if "restitution" in l] == \
        [l for l in text.splitlines() if "restitution" in l]


def test_a_file_whose_restitution_cannot_be_is_refused_naming_the_line(tmp_path):
    path = tmp_path / "bad.txt"
    for old, new, words in [
        ("restitution 0.9", "restitution 1.5", r"bad\.txt:4: .*coefficient must be in \[0, 1\]"),
        ("restitution 1 1 bridges 0.25", "restitution 0 1 0.1", r"bad\.txt:6: .*second"),
        ("restitution walls 0.75", "restitution walls", r"bad\.txt:7: "),
    ]:
        path.write_text(PRINCETON.replace(old, new))
        with pytest.raises(ValueError, match=words):
            edmd.Simulation.from_file(path)
    # Beside what it does not go with: the swap rule, multi-disc collisions.
    path.write_text(PRINCETON)
    with pytest.raises(ValueError, match=r"bad\.txt: restitution: .*multi-disc"):
        edmd.Simulation.from_file(path, multi=True)
    path.write_text(PRINCETON.replace("0.5 3.0", "0.5 1.0"))  # the swap rule's equal masses
    with pytest.raises(ValueError, match=r"bad\.txt: restitution: .*elastic one"):
        edmd.Simulation.from_file(path, rule="swap")


def test_states_without_a_place_for_the_restitution_are_refused(tmp_path):
    # GSD, XYZ and course states hold no restitution: writing one would lose it without a
    # word, so it is refused, and nothing is written.
    sim = edmd.Simulation.from_arrays([[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]],
                                      radii=1.0, box=(10.0, 10.0), boundary="walls",
                                      restitution=0.5)
    for kind in ("gsd", "xyz", "course"):
        out = tmp_path / f"state.{kind}"
        with pytest.raises(ValueError, match="no place for the restitution"):
            sim.write(str(out), format=kind)
        assert not out.exists()
    kept = tmp_path / "s.txt"
    kept.write_text("keep me\n")
    with pytest.raises(ValueError, match="course format.*restitution"):
        sim.write(kept, format="course")
    assert kept.read_text() == "keep me\n"
    sim.set_restitution(None)
    sim.write(tmp_path / "state.xyz")  # elastic again: any format


# --- the generators and the command line -----------------------------------------------------

CLI_RESTITUTION = ["0.9", "0 0 bridges 0.25", "walls 0.8", "tc 0.0001"]
PY_RESTITUTION = {"all": 0.9, "pairs": {(0, 0): {"bridges": 0.25}}, "walls": 0.8, "tc": 1e-4}


@pytest.mark.parametrize("kind,kw,cli", [
    ("fluid", dict(n=200, packing=0.3, boundary="walls"),
     ["--n", "200", "--packing", "0.3", "--boundary", "walls"]),
    ("fluid", dict(n=200, dim=3), ["--n", "200", "--dim", "3"]),
    ("mixture", dict(n=200, size_ratio=1.4), ["--n", "200", "--size-ratio", "1.4"]),
    ("head_on", dict(speed=1.0), ["--speed", "1"]),
    ("lattice", dict(n=100), ["--n", "100"]),
])
def test_generated_systems_and_their_runs_match_the_cli(tmp_path, edmd_cli, kind, kw, cli):
    flags = [a for text in CLI_RESTITUTION for a in ("--restitution", text)]
    gen_file = tmp_path / "cli.txt"
    subprocess.run([edmd_cli, "gen", kind.replace("_", "-"), *cli, *flags, "--seed", "7",
                    "-o", str(gen_file)], check=True, capture_output=True)
    sim = getattr(edmd.gen, kind)(seed=7, restitution=PY_RESTITUTION, **kw)
    assert sim.restitution == PY_RESTITUTION
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
    if kind != "lattice":  # the lattice's discs may not have met by t = 3
        assert sim.dissipated > 0.0


def test_generators_refuse_restitution_with_what_the_command_refuses_it_with():
    with pytest.raises(ValueError, match="gen fluid: restitution does not go with well"):
        edmd.gen.fluid(n=20, well=1.5, restitution=0.9)
    # Even elastic: `edmd gen --restitution 1 --well 1.5` is refused too.
    with pytest.raises(ValueError, match="restitution does not go with well"):
        edmd.gen.fluid(n=20, shoulder=1.5, restitution=1.0)
    with pytest.raises(ValueError, match="restitution does not go with reactions"):
        edmd.gen.fluid(n=20, species=(0.5, 0.5), reactions=["0 + 1 -> 1 + 0"], restitution=0.9)
    with pytest.raises(ValueError, match=r"^restitution: .*multi-disc"):
        edmd.gen.fluid(n=20, multi=True, restitution=0.9)
    with pytest.raises(ValueError, match=r"^restitution: .*elastic one"):
        edmd.gen.lattice(n=20, rule="swap", restitution=0.9)
    assert edmd.gen.fluid(n=20, restitution=1.0).restitution is None
    assert edmd.gen.fluid(n=20, restitution=None).restitution is None


# --- what restitution does not go with -------------------------------------------------------


@pytest.mark.parametrize("kwargs,words", [
    (dict(potential={(0, 1): [(1.5, -1.0)]}), "a stepped potential"),
    (dict(reactions=["0 + 1 -> 1 + 0"]), "reaction rules"),
    (dict(rule="swap", masses=None), "elastic one"),  # the swap rule needs equal masses
    (dict(multi=True), "multi-disc collisions"),
])
def test_restitution_needs_hard_cores_elastic_binary_collisions_and_no_rules(kwargs, words):
    with pytest.raises(ValueError) as info:
        pair(restitution=0.5, **kwargs)
    message = str(info.value)
    assert message.startswith("restitution: inelastic collisions do not go with "), message
    assert words in message, message
    sim = pair(**kwargs)  # without restitution, each is fine
    with pytest.raises(ValueError) as info:
        sim.set_restitution(0.5)
    assert str(info.value).startswith("restitution: ") and words in str(info.value)
    assert sim.restitution is None
    # An elastic restitution is none, and goes with anything.
    sim.set_restitution(1.0)
    assert sim.restitution is None


def test_reaction_rules_are_refused_beside_restitution():
    sim = pair(restitution=0.5)
    with pytest.raises(ValueError, match=r"^rules: .*inelastic collisions"):
        sim.set_reactions(["0 + 1 -> 1 + 0"])
    assert sim.reactions is None and sim.restitution["all"] == 0.5


# --- bad input -------------------------------------------------------------------------------

BAD = [
    # (value, the key the message names after "restitution")
    (1.5, ""), (-0.1, ""), (NAN, ""), (INF, ""), (1e300, ""), ("0.5", ""), (b"0.5", ""),
    (True, ""), (1 + 1j, ""), ([0.5], ""), ((0.5,), ""), ({0.5}, ""), (object(), ""),
    (np.array([0.5, 0.5]), ""),
    ({"every": 0.5}, ""), ({5: 0.5}, ""), ({"all": 0.5, "wall": 0.5}, ""),
    ({"all": 1.5}, "['all']"), ({"all": None}, "['all']"), ({"all": "0.5"}, "['all']"),
    ({"all": True}, "['all']"), ({"all": [0.5]}, "['all']"), ({"all": {}}, "['all']"),
    ({"all": {"bridges": 0.0}}, "['all']['bridges']"),
    ({"all": {"bridges": -1.0}}, "['all']['bridges']"),
    ({"all": {"bridges": INF}}, "['all']['bridges']"),
    ({"all": {"bridges": NAN}}, "['all']['bridges']"),
    ({"all": {"bridges": "1"}}, "['all']['bridges']"),
    ({"all": {"bridges": None}}, "['all']['bridges']"),
    ({"all": {"bridge": 1.0}}, "['all']"), ({"all": {"bridges": 1.0, "e": 0.5}}, "['all']"),
    ({"walls": 1.5}, "['walls']"), ({"walls": -1e-300}, "['walls']"),
    ({"walls": NAN}, "['walls']"), ({"walls": {"bridges": 1.0}}, "['walls']"),
    ({"walls": None}, "['walls']"),
    ({"tc": -1.0}, "['tc']"), ({"tc": INF}, "['tc']"), ({"tc": NAN}, "['tc']"),
    ({"tc": "0"}, "['tc']"), ({"tc": 1 + 1j}, "['tc']"),
    ({"pairs": [(0, 1, 0.5)]}, "['pairs']"), ({"pairs": 0.5}, "['pairs']"),
    ({"pairs": None}, "['pairs']"),
    ({"pairs": {(0, 1): 1.5}}, "['pairs'][(0, 1)]"),
    ({"pairs": {(0, 1): {"bridges": 0}}}, "['pairs'][(0, 1)]['bridges']"),
    ({"pairs": {(0, 1): None}}, "['pairs'][(0, 1)]"),
    ({"pairs": {0: 0.5}}, "['pairs'][0]"), ({"pairs": {(0,): 0.5}}, "['pairs'][(0,)]"),
    ({"pairs": {(0, 1, 2): 0.5}}, "['pairs'][(0, 1, 2)]"),
    ({"pairs": {"0 1": 0.5}}, "['pairs']['0 1']"),
    ({"pairs": {(0, -1): 0.5}}, "['pairs'][(0, -1)]"),
    ({"pairs": {(0, 256): 0.5}}, "['pairs'][(0, 256)]"),
    ({"pairs": {(0, 2**70): 0.5}}, "['pairs'][(0, 1.1805916207174113e21)]"),  # shortened
    ({"pairs": {(0, 1.0): 0.5}}, "['pairs'][(0, 1.0)]"),
    ({"pairs": {(0, True): 0.5}}, "['pairs'][(0, True)]"),
    ({"pairs": {(0, 1): 0.5, (1, 0): 0.6}}, "['pairs'][(1, 0)]"),
]


def one_line(message):
    assert "\n" not in message, message
    assert not re.search(r"[0-9]{30}", message), message
    assert "Can't extract" not in message and "panic" not in message.lower(), message


@pytest.mark.parametrize("k", range(len(BAD)))
def test_bad_restitution_raises_naming_the_argument_and_the_key(k):
    value, key = BAD[k]
    named = "restitution" + key + ": "
    calls = [
        lambda: pair(restitution=value),
        lambda: edmd.gen.fluid(n=20, restitution=value),
        lambda: edmd.gen.single(restitution=value),
    ]
    for call in calls:
        with pytest.raises((ValueError, TypeError)) as info:
            call()
        message = str(info.value)
        assert message.startswith(named), (named, message)
        one_line(message)
    # set_restitution: the same message, and the simulation unchanged.
    sim = pair(restitution={"all": 0.5, "walls": 0.9})
    sim.run(until=5.0)
    before, lost = sim.restitution, sim.dissipated
    with pytest.raises((ValueError, TypeError)) as info:
        sim.set_restitution(value)
    assert str(info.value).startswith(named), str(info.value)
    assert sim.restitution == before and sim.dissipated == lost


def test_the_kinds_of_error():
    with pytest.raises(ValueError, match=r"^restitution: the coefficient must be in \[0, 1\], "
                                         r"got 1\.5$"):
        pair(restitution=1.5)
    with pytest.raises(TypeError, match=r"^restitution: expected None, a coefficient"):
        pair(restitution="0.5")
    with pytest.raises(TypeError, match=r"^restitution\['pairs'\]: expected a dict"):
        pair(restitution={"pairs": [(0, 1, 0.5)]})
    with pytest.raises(ValueError, match=r"^restitution\['pairs'\]\[\(1, 0\)\]: species 1 and 0 "
                                         r"are given twice"):
        pair(restitution={"pairs": {(0, 1): 0.5, (1, 0): 0.6}})
    with pytest.raises(ValueError, match=r"^restitution: unknown key 'wall' "):
        pair(restitution={"wall": 0.5})
    with pytest.raises(TypeError, match="missing 1 required positional argument"):
        pair().set_restitution()


# --- threads and empty systems ---------------------------------------------------------------


def test_a_simulation_running_in_another_thread_is_refused_clearly():
    sim = fluid(n=100, restitution={"all": 0.95, "tc": 1e-3})
    inside, stop = threading.Event(), threading.Event()
    errors = []

    def callback(s):
        inside.set()
        if stop.is_set():
            raise StopIteration("stopped by the test")
        time.sleep(0.001)

    def work():
        try:
            sim.run(until=1e3, callback=callback, callback_every=0.01)
        except BaseException as e:  # noqa: BLE001 - the test inspects it
            errors.append(e)

    thread = threading.Thread(target=work)
    thread.start()
    try:
        assert inside.wait(60)
        for use in (lambda: sim.set_restitution(0.5), lambda: sim.restitution,
                    lambda: sim.dissipated):
            for _ in range(10):
                with pytest.raises(RuntimeError, match="another thread"):
                    use()
    finally:
        stop.set()
        thread.join(60)
    assert isinstance(errors[0], StopIteration)
    assert sim.restitution["all"] == 0.95 and sim.dissipated > 0.0


def test_zero_particles_with_restitution():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      boundary="walls", restitution={"all": 0.5, "tc": 0.1})
    sim.run(until=1.0)
    assert sim.dissipated == 0.0
    assert pickle.loads(pickle.dumps(sim)).restitution == sim.restitution
