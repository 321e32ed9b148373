"""edmd.pack: the compression of `edmd pack`, returning the packing as a Simulation and the
summary `edmd pack --json` prints."""

import json
import math
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import edmd

# Fast settings: 3D, N = 150, stopped at a reduced pressure of 1e6.
FAST = dict(n=150, dim=3, pressure=1e6)
# Keys whose values depend on the machine's speed.
TIMING = {"wall_seconds", "collisions_per_second"}


def volume_fraction(sim):
    r = sim.radii
    ball = math.pi * r**2 if sim.dim == 2 else 4.0 / 3.0 * math.pi * r**3
    return float(ball.sum() / np.prod(sim.box))


def same_summary(a, b):
    return {k: v for k, v in a.items() if k not in TIMING} == {
        k: v for k, v in b.items() if k not in TIMING
    }


def test_pack_returns_a_simulation_and_the_summary():
    sim, summary = edmd.pack(seed=1, **FAST)
    assert isinstance(sim, edmd.Simulation)
    assert sim.dim == 3 and sim.n == 150 and sim.time == 0.0
    assert sim.boundary == ("periodic",) * 3
    for key in ("packing_fraction", "reduced_pressure", "rattlers", "mean_contacts",
                "gap_tolerance", "min_gap", "collisions", "wall_collisions", "rescales",
                "wall_seconds", "collisions_per_second", "stop", "dim", "n", "growth_rate",
                "seed"):
        assert key in summary, key
    assert "output" not in summary
    assert summary["dim"] == 3 and summary["n"] == 150 and summary["seed"] == 1
    assert summary["growth_rate"] == 0.02
    assert summary["stop"] in ("pressure", "converged")
    assert summary["reduced_pressure"] >= 1e6
    # Near random close packing, at this small N and fast growth.
    phi = summary["packing_fraction"]
    assert 0.58 < phi < 0.68, phi
    assert abs(volume_fraction(sim) - phi) < 1e-12
    assert 0 <= summary["rattlers"] < 150
    assert 4.0 < summary["mean_contacts"] <= 6.5
    assert summary["collisions"] > 0 and summary["wall_seconds"] >= 0.0
    # Velocities of rms speed about 1 (mass 1).
    v2 = (sim.velocities**2).sum(axis=1).mean()
    assert 0.5 < v2 < 2.0


def test_the_same_seed_gives_the_same_packing_bit_for_bit():
    a, sa = edmd.pack(seed=4, **FAST)
    b, sb = edmd.pack(seed=4, **FAST)
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.radii, b.radii)
    assert a.box == b.box
    assert same_summary(sa, sb)
    c, _ = edmd.pack(seed=5, **FAST)
    assert not np.array_equal(a.positions, c.positions)


def test_slower_growth_packs_denser():
    _, slow = edmd.pack(seed=2, growth_rate=0.02, **FAST)
    _, fast = edmd.pack(seed=2, growth_rate=0.5, **FAST)
    assert slow["packing_fraction"] >= fast["packing_fraction"]


def test_the_packing_runs_and_conserves_energy():
    sim, _ = edmd.pack(seed=3, **FAST)
    e0 = sim.kinetic_energy
    sim.run(until=0.01)
    assert sim.time == 0.01
    assert sim.stats["disc_disc"] > 0
    assert abs(sim.kinetic_energy - e0) <= 1e-9 * e0


def test_a_target_packing_fraction_stops_there_exactly():
    sim, summary = edmd.pack(n=200, dim=3, packing=0.5, seed=1)
    assert summary["stop"] == "packing"
    assert abs(summary["packing_fraction"] - 0.5) < 1e-12
    assert abs(volume_fraction(sim) - 0.5) < 1e-12
    sim.run(until=1.0)


def test_discs_mixtures_and_walls():
    sim, summary = edmd.pack(n=120, dim=2, size_ratio=1.4, fraction_large=0.5,
                             boundary="walls", pressure=1e6, seed=1)
    assert sim.dim == 2 and sim.boundary == ("walls", "walls")
    assert len(np.unique(sim.radii)) == 2
    assert 0.7 < summary["packing_fraction"] < 0.9
    sim.run(until=0.01)
    poly, _ = edmd.pack(n=120, dim=2, polydispersity=0.1, pressure=1e6, seed=1)
    assert len(np.unique(poly.radii)) > 2


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(), ["n"]),
        (dict(n=1), ["n", "from 2"]),
        (dict(n=-5), ["n", "-5"]),
        (dict(n=100, dim=4), ["dim", "2 or 3"]),
        (dict(n=100, growth_rate=0.0), ["growth rate", "growth_rate"]),
        (dict(n=100, growth_rate=3.0), ["growth rate"]),
        (dict(n=100, growth_rate=float("nan")), ["growth rate"]),
        (dict(n=100, pressure=0.5), ["pressure"]),
        (dict(n=100, packing=1.2), ["packing"]),
        (dict(n=100, packing=0.001), ["packing fraction", "start"]),
        (dict(n=100, size_ratio=1.4, polydispersity=0.1), ["polydispersity", "size_ratio"]),
        (dict(n=100, fraction_large=0.3), ["fraction_large", "size_ratio"]),
        (dict(n=100, size_ratio=-1.0), ["ratio"]),
        (dict(n=100, polydispersity=0.9), ["polydispersity"]),
        (dict(n=100, boundary="box"), ["boundary", "box"]),
        (dict(n=100, seed=-1), ["seed"]),
    ],
)
def test_bad_arguments_raise_value_error(kwargs, words):
    with pytest.raises(ValueError) as info:
        edmd.pack(**kwargs)
    message = str(info.value)
    assert "\n" not in message
    assert "--" not in message, message
    for w in words:
        assert w in message, (w, message)


def test_a_start_refuses_the_options_of_a_random_start():
    start = edmd.gen.fluid(n=50, packing=0.3, seed=1)
    for kwargs in (dict(n=50), dict(dim=2), dict(boundary="walls"), dict(size_ratio=1.4)):
        with pytest.raises(ValueError, match="random start"):
            edmd.pack(start=start, **kwargs)
    with pytest.raises(TypeError):
        edmd.pack(start="fluid.txt")


def run_cli(edmd_cli, args):
    out = subprocess.run([edmd_cli, "pack", *args, "--json"], check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout)


def test_pack_agrees_with_the_cli(tmp_path, edmd_cli):
    cases = [
        (dict(seed=7, **FAST),
         ["--dim", "3", "--n", "150", "--pressure", "1e6", "--seed", "7"]),
        (dict(n=120, dim=2, size_ratio=1.4, boundary="walls", pressure=1e6, seed=2),
         ["--n", "120", "--size-ratio", "1.4", "--boundary", "walls", "--pressure", "1e6",
          "--seed", "2"]),
        (dict(n=200, dim=3, packing=0.5, growth_rate=0.05, polydispersity=0.1, seed=3),
         ["--dim", "3", "--n", "200", "--packing", "0.5", "--growth-rate", "0.05",
          "--polydispersity", "0.1", "--seed", "3"]),
    ]
    for k, (kwargs, flags) in enumerate(cases):
        f = tmp_path / f"cli-{k}.txt"
        cli = run_cli(edmd_cli, [*flags, "-o", str(f)])
        sim, summary = edmd.pack(**kwargs)
        assert cli.pop("output") == str(f)
        assert same_summary(summary, cli), (summary, cli)
        assert summary["packing_fraction"] == cli["packing_fraction"]
        back = edmd.Simulation.from_file(f)
        assert np.array_equal(back.positions, sim.positions)
        assert np.array_equal(back.velocities, sim.velocities)
        assert np.array_equal(back.radii, sim.radii)
        assert back.box == sim.box and back.boundary == sim.boundary
        mine = tmp_path / f"py-{k}.txt"
        sim.write(mine)
        assert mine.read_bytes() == f.read_bytes()


def test_pack_from_a_simulation_agrees_with_the_cli_from_its_file(tmp_path, edmd_cli):
    start = edmd.gen.fluid(n=100, packing=0.3, seed=1)
    start.run(until=1.0)
    f = tmp_path / "start.txt"
    start.write(f)
    out = tmp_path / "packed.txt"
    cli = run_cli(edmd_cli, [str(f), "--pressure", "1e6", "--seed", "9", "-o", str(out)])
    sim, summary = edmd.pack(start=edmd.Simulation.from_file(f), pressure=1e6, seed=9)
    assert summary["dim"] == 2 and summary["n"] == 100
    assert same_summary(summary, {k: v for k, v in cli.items() if k != "output"})
    mine = tmp_path / "mine.txt"
    sim.write(mine)
    assert mine.read_bytes() == out.read_bytes()
    # Packing on from the packing at a lower rate, from the returned simulation.
    glass, s1 = edmd.pack(n=150, dim=3, packing=0.55, seed=1)
    jammed, s2 = edmd.pack(start=glass, pressure=1e6)
    assert s2["packing_fraction"] > s1["packing_fraction"]
    assert jammed.n == 150


def test_the_gil_is_released_during_the_compression():
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.01)

    t = threading.Thread(target=tick)
    t.start()
    try:
        started = time.monotonic()
        edmd.pack(n=1000, dim=3, pressure=1e6, seed=1)
        took = time.monotonic() - started
    finally:
        done.set()
        t.join()
    if took > 0.3:
        # The other thread kept ticking while the compression ran.
        assert len(ticks) > 0.3 * took / 0.01


def test_ctrl_c_interrupts_a_long_compression(ctrl_c):
    # Ctrl-C was noticed only at a velocity rescaling (every 10 collisions per particle),
    # minutes apart for 10^6 particles; it is now looked for every few milliseconds.
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        edmd.pack(n=20000, dim=3, seed=1)
    except KeyboardInterrupt:
        pass
    else:
        raise AssertionError("the compression was not interrupted")
    finally:
        timer.cancel()
    waited = time.monotonic() - started
    assert waited < 1.0 + 2.0, f"KeyboardInterrupt came after {waited:.2f} s"
    # And the next compression runs as usual.
    _, summary = edmd.pack(n=100, dim=3, packing=0.3, seed=1)
    assert summary["stop"] == "packing"


def test_a_checkpointed_compression_resumes_bit_for_bit(tmp_path, edmd_cli):
    whole, s_whole = edmd.pack(seed=5, **FAST)
    ck = tmp_path / "pack.ck"
    # At every rescaling: the last checkpoint is the last rescaling before the stop.
    edmd.pack(seed=5, checkpoint=ck, checkpoint_every=0, **FAST)
    assert ck.read_bytes()[:8] == b"EDMDPACK"
    sim, summary = edmd.pack(resume=ck, checkpoint=ck)
    assert same_summary(summary, s_whole), (summary, s_whole)
    assert np.array_equal(sim.positions, whole.positions)
    assert np.array_equal(sim.velocities, whole.velocities)
    assert np.array_equal(sim.radii, whole.radii)
    # `edmd pack` continues Python's checkpoint to the very same file.
    out = tmp_path / "cli.txt"
    cli = run_cli(edmd_cli, [str(ck), "-o", str(out)])
    assert same_summary({k: v for k, v in cli.items() if k != "output"}, s_whole)
    mine = tmp_path / "py.txt"
    whole.write(mine)
    assert mine.read_bytes() == out.read_bytes()
    # What the checkpoint carries may be given again with its own value (the same call run
    # again after a crash), not with another; other files are not checkpoints.
    again, s_again = edmd.pack(resume=ck, seed=5, growth_rate=0.02, **FAST)
    assert same_summary(s_again, s_whole)
    for kwargs in (dict(pressure=1e7), dict(seed=2), dict(n=151), dict(growth_rate=0.01)):
        with pytest.raises(ValueError, match="carried by the checkpoint"):
            edmd.pack(resume=ck, **kwargs)
    with pytest.raises(ValueError, match="growth_rate 0.01 differs from the value carried by the checkpoint .*, 0.02"):
        edmd.pack(resume=ck, growth_rate=0.01)
    with pytest.raises(ValueError, match="not an edmd packing checkpoint"):
        edmd.pack(resume=mine)
    with pytest.raises(ValueError, match="start or a checkpoint"):
        edmd.pack(resume=ck, start=whole)
    with pytest.raises(ValueError, match="checkpoint_every"):
        edmd.pack(checkpoint_every=1.0, **FAST)


def test_ctrl_c_writes_a_checkpoint_and_leaves_no_temporary_file(tmp_path, ctrl_c):
    ck = tmp_path / "pack.ck"
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        edmd.pack(n=4000, dim=3, seed=1, checkpoint=ck, checkpoint_every=1e9)
    except KeyboardInterrupt:
        pass
    else:
        raise AssertionError("the compression was not interrupted")
    finally:
        timer.cancel()
    assert ck.read_bytes()[:8] == b"EDMDPACK"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pack.ck"]
