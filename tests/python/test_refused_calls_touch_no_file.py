"""Regression (issue 24): a refused call emptied a file before refusing.

`sim.run(until=1, trajectory="notes.txt", every=0.1)` raised ValueError (not a trajectory
extension) but had already created "notes.txt" empty: the trajectory was opened with a plain
create before its checks. Every output of the Python package now goes through the CLI's
temporary-name-then-rename path (`AtomicFile`), and every check comes before any file is made.
"""

import os

import numpy as np
import pytest

import edmd


def small():
    return edmd.gen.fluid(n=20, packing=0.3, seed=1)


def listing(folder):
    return sorted(os.listdir(folder))


REFUSED_RUNS = [
    ("notes.txt", dict(until=1.0, every=0.1), "xyz or .gsd"),
    ("t.xyz", dict(until=1.0, every=-0.1), "every"),
    ("t.xyz", dict(until=1.0, every=1e-9), "too many"),
    ("t.gsd", dict(until=1e3, every=1e-9), "too many"),
    ("t.xyz", dict(until=1.0, every=0.1, callback=3, callback_every=0.5), "callback"),
    ("t.xyz", dict(until=1.0, every=0.1, callback_every=0.5), "callback"),
    ("t.xyz", dict(events=10, every=0.1), "need until"),
    ("t.xyz", dict(until=float("nan"), every=0.1), "until"),
]


@pytest.mark.parametrize("name,kwargs,message", REFUSED_RUNS)
def test_a_refused_run_leaves_the_trajectory_file_as_it_was(tmp_path, name, kwargs, message):
    path = tmp_path / name
    path.write_text("keep me\n")
    sim = small()
    with pytest.raises((ValueError, TypeError), match=message):
        sim.run(trajectory=path, **kwargs)
    assert path.read_text() == "keep me\n"
    assert listing(tmp_path) == [name]
    assert sim.time == 0.0


def test_a_refused_measurement_schedule_leaves_the_trajectory_as_it_was(tmp_path):
    path = tmp_path / "t.xyz"
    path.write_text("keep me\n")
    sim = small()
    sim.measure("temperature", every=1e-9)
    with pytest.raises(ValueError, match="samples"):
        sim.run(until=1.0, trajectory=path, every=0.1)
    assert path.read_text() == "keep me\n"
    assert listing(tmp_path) == ["t.xyz"]


def test_a_trajectory_into_a_folder_that_does_not_exist_is_refused_first(tmp_path):
    sim = small()
    with pytest.raises(ValueError, match="does not exist"):
        sim.run(until=1.0, trajectory=tmp_path / "nowhere" / "t.xyz", every=0.1)
    (tmp_path / "d.xyz").mkdir()
    with pytest.raises(ValueError, match="names a folder"):
        sim.run(until=1.0, trajectory=tmp_path / "d.xyz", every=0.1)
    assert sim.time == 0.0
    assert listing(tmp_path) == ["d.xyz"] and listing(tmp_path / "d.xyz") == []


@pytest.mark.parametrize("name", ["t.xyz", "t.gsd"])
def test_a_trajectory_is_written_whole_under_its_name(tmp_path, name):
    path = tmp_path / name
    path.write_text("old\n")
    sim = small()
    sim.run(until=1.0, trajectory=path, every=0.25)
    assert path.read_bytes() != b"old\n"
    assert listing(tmp_path) == [name]  # no temporary file left beside it
    if name.endswith(".xyz"):
        assert path.read_text().count("Time=") == 5


def test_a_run_stopped_by_its_callback_keeps_the_frames_written(tmp_path):
    path = tmp_path / "t.xyz"

    def stop(sim):
        if sim.time >= 0.5:
            raise KeyboardInterrupt

    sim = small()
    with pytest.raises(KeyboardInterrupt):
        sim.run(until=10.0, trajectory=path, every=0.25, callback=stop, callback_every=0.5)
    assert sim.time == 0.5
    assert path.read_text().count("Time=") == 3  # frames at 0, 0.25 and 0.5
    assert listing(tmp_path) == ["t.xyz"]


REFUSED_WRITES = [
    (dict(format="weather"), "format"),
    (dict(format="course"), "course"),  # a 3D system
]


@pytest.mark.parametrize("kwargs,message", REFUSED_WRITES)
def test_a_refused_write_leaves_the_file_as_it_was(tmp_path, kwargs, message):
    path = tmp_path / "state.txt"
    path.write_text("keep me\n")
    sim = edmd.gen.fluid(n=20, packing=0.2, dim=3, seed=1)
    with pytest.raises(ValueError, match=message):
        sim.write(path, **kwargs)
    assert path.read_text() == "keep me\n"
    assert listing(tmp_path) == ["state.txt"]


def test_write_to_a_folder_is_refused(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(ValueError, match="folder"):
        small().write(tmp_path / "d")
    assert listing(tmp_path) == ["d"] and listing(tmp_path / "d") == []


@pytest.mark.parametrize("name", ["s.txt", "s.xyz", "s.gsd", "s.ck"])
def test_write_replaces_the_file_and_leaves_nothing_beside_it(tmp_path, name):
    path = tmp_path / name
    path.write_text("old\n")
    sim = small()
    sim.write(path)
    assert path.read_bytes() != b"old\n"
    assert listing(tmp_path) == [name]
    if name.endswith(".ck"):
        back = edmd.Simulation.from_file(path)
        assert np.array_equal(back.positions, sim.positions)
