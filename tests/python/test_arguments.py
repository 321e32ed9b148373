"""Regression (issue 24): bad arguments raised the wrong exception or a message that did not
name them.

Before: OverflowError for negative counts (`n=-1`, `seed=-1`, `events=-1`), "Can't extract
`str` to `Vec`" for `box="10 10"`, complex positions made real, a missing `resume` file called
"not a checkpoint", a folder accepted as a packing checkpoint (`edmd.pack(checkpoint="/tmp")`,
to fail only at the first checkpoint), and numbers like 1e300 printed with 301 digits. This
walks every public function and argument of the package (`edmd.Simulation`'s methods and
properties, `edmd.gen.*`, `edmd.pack`) with hostile values, each of which must raise
ValueError or TypeError whose message names the argument, in one line, with numbers short.
"""

import math
import pathlib
import re

import numpy as np
import pytest

import edmd

NAN, INF = math.nan, math.inf
RAGGED = [[1.0, 2.0], [3.0]]


def small():
    return edmd.gen.fluid(n=20, packing=0.3, seed=1)


def pair(**kw):
    args = dict(positions=[[2.0, 5.0], [8.0, 5.0]], velocities=[[1.0, 0.0], [-1.0, 0.0]],
                radii=1.0, box=(10.0, 10.0))
    args.update(kw)
    return edmd.Simulation.from_arrays(**args)


def cb(sim):
    pass


# (argument, hostile values, call with the value, text the message must hold)
def run_cases(tmp):
    traj = str(tmp / "t.xyz")
    return [
        ("until", [-1, NAN, INF, -INF, "1", 1 + 1j, True, None, [1.0], object()],
         lambda v: small().run(until=v)),
        ("events", [-1, 2**70, 1.5, NAN, "10", 1 + 1j, True, [10], object()],
         lambda v: small().run(events=v)),
        ("every", [-1, 0, NAN, INF, 1e-300, "0.1", 1 + 1j, True, None, [0.1]],
         lambda v: small().run(until=1.0, trajectory=traj, every=v)),
        ("callback_every", [-1, 0, NAN, INF, 1e-300, "0.1", 1 + 1j, True, None, [0.1]],
         lambda v: small().run(until=1.0, callback=cb, callback_every=v)),
        ("callback", [3, "f", None, True],
         lambda v: small().run(until=1.0, callback=v, callback_every=0.5)),
        ("trajectory", [5, str(tmp / "t.txt"), str(tmp), None, True],
         lambda v: small().run(until=1.0, trajectory=v, every=0.1)),
    ]


def measure_cases(tmp):
    return [
        ("every", [-1, 0, NAN, INF, "1", 1 + 1j, True, None, [1.0]],
         lambda v: small().measure("pressure", every=v)),
        ("measure", [5, None, "weather", b"pressure"],
         lambda v: small().measure(v, every=1.0)),
    ]


def write_cases(tmp):
    return [
        ("path", [5, None, str(tmp)], lambda v: small().write(v)),
        ("format", [5, "weather", True], lambda v: small().write(str(tmp / "s.txt"), format=v)),
    ]


def setter_cases(tmp):
    return [
        ("velocities", ["fast", np.zeros((20, 2), dtype=complex), None, RAGGED, np.array([]),
                        np.zeros((20, 3)), np.full((20, 2), 1e200), np.full((20, 2), NAN),
                        np.full((20, 2), INF), np.zeros((20, 2), dtype=bool), True, 1.0],
         lambda v: setattr(small(), "velocities", v)),
    ]


def from_arrays_cases(tmp):
    return [
        ("positions", ["10 10", [[2 + 1j, 5.0], [8.0, 5.0]], None, RAGGED, np.array([]),
                       [[True, False], [False, True]], [[NAN, 5.0], [8.0, 5.0]],
                       [[INF, 5.0], [8.0, 5.0]], [[1.0, 2.0, 3.0, 4.0]] * 2, 5.0],
         lambda v: pair(positions=v)),
        ("velocities", ["10 10", [[1 + 1j, 0.0], [0.0, 0.0]], None, RAGGED, np.array([]),
                        [[1e200, 0.0], [0.0, 0.0]], [[NAN, 0.0], [0.0, 0.0]], [[0.0, 0.0]]],
         lambda v: pair(velocities=v)),
        ("radii", [-1, 0, NAN, INF, "1", 1 + 1j, True, None, [1.0], [], [[1.0, 1.0]]],
         lambda v: pair(radii=v)),
        ("masses", [-1, 0, NAN, INF, "1", 1 + 1j, True, [1.0], []],
         lambda v: pair(masses=v)),
        ("box", ["10 10", -1, (0, 10), (-10, 10), (NAN, 10), (INF, 10), (10,), (10, 10, 10),
                 None, (1 + 1j, 10), (True, True), [], [[10, 10]]],
         lambda v: pair(box=v)),
        ("boundary", ["sticky", 5, ["walls"], True, ["walls", 5], [None, None]],
         lambda v: pair(boundary=v)),
        ("species", [-1, 1.5, 70000, NAN, "a", 1 + 1j, [0], []],
         lambda v: pair(species=v)),
        # None is each one's default here.
        ("rule", ["sticky", 5, True], lambda v: pair(rule=v)),
        ("multi", ["yes", 1, 0.0], lambda v: pair(multi=v)),
        ("allow_overlaps", ["yes", 1, 0.0], lambda v: pair(allow_overlaps=v)),
        ("potential", [[(3.0, -1.0)], "well", 5, {0: [(3.0, -1.0)]}, {(0, 0): "3"},
                       {(0, 0): [(NAN, -1.0)]}, {(0, 0): [(1.0, -1.0)]}, {(0, 9): [(3.0, -1.0)]},
                       {(0, 0): [(4.0, -1.0), (3.0, 1.0)]}, {(0, 0): [("3", -1.0)]},
                       {(0, 0): {"core": 2.5, "steps": [(3.0, -1.0)]}}],
         lambda v: pair(potential=v)),
        ("reactions", ["0 + 1 -> 1 + 1", 5, [5], ["0 + 1 -> 1"], ["0 + 0 -> 1 + 1 heat nan"],
                       ["0 + 0 -> 1 + 1 probability 2"], ["0 + 9 -> 1 + 1"],
                       [{"reactants": (0, 0)}], [{"reactants": (0, -1), "products": (1, 1)}],
                       [{"reactants": (0, 0), "products": (1, 1), "activation": -1}],
                       ["0 + 0 -> 1 + 1", "0 + 0 -> 2 + 2"], {"seed": 1},
                       {"rules": ["0 + 0 -> 1 + 1"], "seed": -1}],
         lambda v: pair(reactions=v)),
        ("restitution", RESTITUTION_HOSTILE, lambda v: pair(restitution=v)),
        # -1.0 is refused for the box's periodic axes.
        ("gravity", [-1.0, 0, NAN, INF, "1", True, 1 + 1j, [1.0], {"g": 0}, {"g": "1"},
                     {"axis": 5, "g": 1.0}, {"axis": "w", "g": 1.0}, {"axis": 1}, {"x": 1}],
         lambda v: pair(gravity=v)),
        # The box is 10 wide: an offset of 10 is outside [0, L_x).
        ("shear", [NAN, INF, "0.1", True, 1 + 1j, {"rate": 1.0}, (1.0,), (1.0, 2.0, 3.0),
                   (NAN, 0.0), ("1", 0.0), (1.0, -1.0), (1.0, 10.0), (1.0, NAN), object()],
         lambda v: pair(shear=v)),
    ]


def thermostat_cases(tmp):
    return [
        ("kT", [-1, 0, NAN, INF, "1", 1 + 1j, True, [1.0]],
         lambda v: small().set_thermostat(kT=v, rate=1.0)),
        ("rate", [-1, 0, NAN, INF, "1", 1 + 1j, True, [1.0], None],
         lambda v: small().set_thermostat(kT=1.0, rate=v)),
        ("seed", [-1, 2**70, 1.5, "1", True],
         lambda v: small().set_thermostat(kT=1.0, rate=1.0, seed=v)),
    ]


def reactions_cases(tmp):
    rule = ["0 + 0 -> 1 + 1"]
    return [
        ("rules", ["0 + 0 -> 1 + 1", 5, [5], ["0 + 0 -> 1"], ["0 + 0 -> 1 + 1 activation -1"],
                   ["0 + 0 -> 1 + 1 probability 1.5"], ["0 + 0 -> 1 + 1 heat inf"],
                   ["0 + 9 -> 1 + 1"], [{"reactants": (0, 0)}],
                   [{"reactants": (0, 0), "products": (1, 1), "probability": "1"}],
                   ["0 + 0 -> 1 + 1", "0 + 0 -> 2 + 2"]],
         lambda v: small().set_reactions(v)),
        ("seed", [-1, 2**70, 1.5, "1", True], lambda v: small().set_reactions(rule, seed=v)),
        ("colours", [[1, 2, 3], {1: "red"}, {1: (1, 2)}, {1: (1, 2, 256)}, {-1: (1, 2, 3)}],
         lambda v: small().set_reactions(rule, colours=v)),
    ]


RESTITUTION_HOSTILE = [1.5, -0.1, NAN, INF, "0.5", True, 1 + 1j, [0.5], {"all": 2},
                       {"all": {"bridges": 0}}, {"walls": NAN}, {"tc": -1},
                       {"pairs": {(0, 1): 2}}, {"pairs": {(0, 300): 0.5}}, {"wall": 0.5}]


def restitution_cases(tmp):
    return [
        ("restitution", RESTITUTION_HOSTILE, lambda v: small().set_restitution(v)),
    ]


def walled():
    return edmd.gen.fluid(n=20, packing=0.3, seed=1, boundary="walls")


def gravity_cases(tmp):
    sideways = dict(boundary=("periodic", "walls"))
    return [
        ("g", [0, -0.0, NAN, INF, "1", True, 1 + 1j, [1.0], {"g": 0}, {"axis": 1}, {"x": 1},
               object()],
         lambda v: walled().set_gravity(v)),
        # 0 and "x" name the periodic axis.
        ("axis", [0, "x", 2, "z", 3, -1, 2**70, 1.5, "w", True, [1], object()],
         lambda v: pair(**sideways).set_gravity(-1.0, axis=v)),
    ]


def shear_cases(tmp):
    return [
        ("rate", [NAN, INF, -INF, "1", True, 1 + 1j, [1.0], (1.0, 2.0, 3.0), (NAN, 0.0),
                  ("1", 0.0), object()],
         lambda v: small().set_shear(v)),
        # small() is about 8 wide.
        ("offset", [-1.0, 1e9, NAN, INF, "0", True, 1 + 1j, [0.0], object()],
         lambda v: small().set_shear(0.1, offset=v)),
    ]


def from_file_cases(tmp):
    state = tmp / "state.txt"  # written by the test before the call
    return [
        ("path", [5, None, str(tmp), str(tmp / "missing.txt")],
         lambda v: edmd.Simulation.from_file(v)),
        ("format", ["weather", 5], lambda v: edmd.Simulation.from_file(state, format=v)),
        ("columns", ["weather", 5], lambda v: edmd.Simulation.from_file(state, columns=v)),
        ("rule", ["weather", 5], lambda v: edmd.Simulation.from_file(state, rule=v)),
        ("seed", [-1, 2**70, 1.5, "1", True], lambda v: edmd.Simulation.from_file(state, seed=v)),
        ("data", ["abc", 5, None, b"", b"EDMDCK garbage"],
         lambda v: edmd.Simulation.from_checkpoint(v)),
    ]


INT_HOSTILE = [2**70, 1.5, NAN, "10", 1 + 1j, True, [10], object()]
REAL_HOSTILE = [NAN, INF, "0.3", 1 + 1j, True, [0.3], object()]


def gen_cases(tmp):
    cases = [
        ("n", [-1, 0] + INT_HOSTILE, lambda v: edmd.gen.fluid(n=v)),
        ("packing", [-1, 0, 1e300] + REAL_HOSTILE, lambda v: edmd.gen.fluid(n=20, packing=v)),
        ("dim", [4, -1, 2**70, 2.0, "2", True], lambda v: edmd.gen.fluid(n=20, dim=v)),
        ("seed", [-1, 2**70, 1.5, "1", True, None], lambda v: edmd.gen.fluid(n=20, seed=v)),
        ("boundary", ["sticky", 5, True], lambda v: edmd.gen.fluid(n=20, boundary=v)),
        ("rule", ["sticky", 5, None], lambda v: edmd.gen.fluid(n=20, rule=v)),
        ("multi", ["yes", 1, None], lambda v: edmd.gen.fluid(n=20, multi=v)),
        ("radius", [-1, 0, 1e300] + REAL_HOSTILE, lambda v: edmd.gen.single(radius=v)),
        ("speed", REAL_HOSTILE, lambda v: edmd.gen.head_on(speed=v)),
        ("mass", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.head_on(mass=v)),
        ("angle", REAL_HOSTILE, lambda v: edmd.gen.angled(angle=v)),
        ("impact", REAL_HOSTILE, lambda v: edmd.gen.angled(impact=v)),
        ("kt", [-1] + REAL_HOSTILE, lambda v: edmd.gen.lattice(kt=v)),
        ("region", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.diffusion1(region=v)),
        ("big_radius", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.brownian(big_radius=v)),
        ("big_mass", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.brownian(big_mass=v)),
        ("size_ratio", [-1, 0] + REAL_HOSTILE,
         lambda v: edmd.gen.mixture(n=20, size_ratio=v)),
        ("fraction_large", [-1, 2] + REAL_HOSTILE,
         lambda v: edmd.gen.mixture(n=20, size_ratio=1.4, fraction_large=v)),
        ("spread", [-1] + REAL_HOSTILE, lambda v: edmd.gen.mixture(n=20, spread=v)),
        ("well", [-1, 0, 1.0, 101] + REAL_HOSTILE, lambda v: edmd.gen.fluid(n=20, well=v)),
        ("shoulder", [-1, 0, 1.0, 101] + REAL_HOSTILE,
         lambda v: edmd.gen.fluid(n=20, shoulder=v)),
        ("depth", [-1, 0] + REAL_HOSTILE, lambda v: edmd.gen.fluid(n=20, well=1.5, depth=v)),
        ("species", [(0.5, 0.6), (-0.5, 1.5), (NAN, 1.0), (INF,), 0.5, "0.5,0.5", [0.5, "a"],
                     [1 + 1j], True, [[0.5, 0.5]], [0.5] * 300],
         lambda v: edmd.gen.fluid(n=20, species=v)),
        ("reactions", [["0 + 1 -> 2 + 2"], "0 + 0 -> 1 + 1", [5], ["0 + 0 -> 1"],
                       [{"reactants": (0, 0), "products": (1, 1), "probability": 2}],
                       ["0 + 0 -> 1 + 1", "0 + 0 -> 2 + 2"]],
         lambda v: edmd.gen.fluid(n=20, reactions=v)),
        ("restitution", [1.5, NAN, "0.9", True, {"all": 2}, {"tc": -1}],
         lambda v: edmd.gen.fluid(n=20, restitution=v)),
        ("gravity", [0, NAN, INF, "-1", True, 1 + 1j, [1.0]],
         lambda v: edmd.gen.fluid(n=20, gravity=v)),
        ("shear", [NAN, INF, "0.1", True, 1 + 1j, [0.1]],
         lambda v: edmd.gen.fluid(n=20, shear=v)),
    ]
    return cases


def pack_cases(tmp):
    def pack(**kw):
        args = dict(n=20, dim=2, pressure=100.0, seed=1)
        args.update(kw)
        return edmd.pack(**args)

    ck = str(tmp / "p.ck")
    return [
        ("n", [-1, 0, 2**70, 1.5, "10", 1 + 1j, True, [10]], lambda v: pack(n=v)),
        ("dim", [4, 0, True, "3", 2.0], lambda v: pack(dim=v)),
        ("growth_rate", [-1, 0, NAN, "x", True, 1 + 1j], lambda v: pack(growth_rate=v)),
        ("pressure", [-1, NAN, "x", True], lambda v: pack(pressure=v)),
        ("packing", [-1, 2, NAN, "x", True], lambda v: pack(pressure=None, packing=v)),
        ("size_ratio", [-1, NAN, "x", True], lambda v: pack(size_ratio=v)),
        ("fraction_large", [2, NAN, "x", True],
         lambda v: pack(size_ratio=1.4, fraction_large=v)),
        ("polydispersity", [-1, NAN, "x", True], lambda v: pack(polydispersity=v)),
        ("boundary", ["sticky", 5, True], lambda v: pack(boundary=v)),
        ("seed", [-1, 2**70, 1.5, "1", True], lambda v: pack(seed=v)),
        ("start", [5, "sim"], lambda v: pack(n=None, dim=None, start=v)),
        ("checkpoint", [str(tmp), str(tmp) + "/", str(tmp / "no" / "p.ck"), 5, True],
         lambda v: pack(checkpoint=v)),
        ("checkpoint_every", [-1, NAN, "x", True, 1 + 1j],
         lambda v: pack(checkpoint=ck, checkpoint_every=v)),
        ("resume", [str(tmp / "missing.ck"), str(tmp), 5, True],
         lambda v: edmd.pack(resume=v)),
    ]


GROUPS = [run_cases, measure_cases, write_cases, setter_cases, from_arrays_cases,
          thermostat_cases, reactions_cases, restitution_cases, gravity_cases, shear_cases,
          from_file_cases, gen_cases, pack_cases]


def ids():
    """(group, argument, index) for every hostile value (the calls are not made here)."""
    out = []
    for g in GROUPS:
        for arg, values, _ in g(pathlib.Path("/nonexistent")):
            out += [(g.__name__, arg, k) for k in range(len(values))]
    return out


@pytest.mark.parametrize("group,arg,k", ids())
def test_hostile_values_raise_value_or_type_error_naming_the_argument(tmp_path, group, arg, k):
    cases = {g.__name__: g for g in GROUPS}[group](tmp_path)
    (values, call), = [(vs, c) for a, vs, c in cases if a == arg]
    value = values[k]
    small().write(tmp_path / "state.txt")
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises((ValueError, TypeError)) as info:
        call(value)
    message = str(info.value)
    # The argument named as a word ("n must be", "argument 'rule'", "box: ..."), or for a
    # file, the file itself.
    named = re.search(rf"(?<![A-Za-z_]){re.escape(arg)}(?![A-Za-z_])", message)
    assert named or (isinstance(value, str) and value in message), message
    assert "\n" not in message, message
    assert not re.search(r"[0-9]{30}", message), message  # no 301-digit numbers
    assert "Can't extract" not in message, message
    # A refused call makes no file.
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_a_missing_resume_file_is_called_missing(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        edmd.pack(resume=tmp_path / "missing.ck")


def test_a_folder_is_refused_as_a_packing_checkpoint_before_the_compression(tmp_path):
    with pytest.raises(ValueError, match="folder"):
        edmd.pack(n=20, dim=2, pressure=100.0, checkpoint=tmp_path)


def test_large_numbers_are_short_in_messages():
    with pytest.raises(ValueError) as info:
        small().run(until=-1e300)
    assert "-1e300" in str(info.value)
