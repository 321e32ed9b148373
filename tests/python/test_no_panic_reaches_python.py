"""Regression (issue 24): PanicException reached Python.

A system of zero particles panicked in `measure("speeds")` and `measure("collisions")` (an
empty histogram range in the engine's observers), and a second thread calling `run()` or
`pickle.dumps(sim)` while another thread ran the simulation panicked on PyO3's borrow flag.
`PanicException` is not an `Exception`, so `except Exception` did not catch it. Now every
method maps a panic to RuntimeError, and a simulation running in one thread is refused to the
others at once with a RuntimeError that says so. Also here: a callback that called `run`
made `run(until=5)` end at t = 501; that call is now refused.
"""

import pickle
import threading
import time

import numpy as np
import pytest

import edmd

MEASUREMENTS = ["temperature", "pressure", "collisions", "speeds", "msd", "species", "energy",
                "rdf", "kinetics", "viscosity"]


def empty():
    return edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10))


@pytest.mark.parametrize("name", MEASUREMENTS)
def test_measurements_of_zero_particles_raise_no_panic(name):
    sim = empty()
    try:
        sim.measure(name, every=0.1)
        sim.run(until=1.0)
        sim.results()
        pickle.loads(pickle.dumps(sim))
    except Exception:
        pass  # a clear refusal is fine; a PanicException (a BaseException) fails the test


def test_zero_particles_with_a_potential_and_a_thermostat():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      potential={(0, 0): [(3.0, -1.0)]})
    sim.set_thermostat(kT=1.0, rate=1.0)
    sim.measure("energy", "rdf", every=0.1)
    sim.run(until=1.0)
    sim.results()
    assert sim.shells.shape == (0, 3) and sim.potential_energy == 0.0
    assert pickle.loads(pickle.dumps(sim)).thermostat == sim.thermostat


def test_zero_particles_with_reaction_rules():
    # No disc is of species 0 or 1, but each rule makes a reactant of the other.
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      reactions=["0 + 1 -> 1 + 0"])
    sim.measure("kinetics", "species", every=0.1)
    sim.run(until=1.0)
    sim.results()
    assert sim.species_counts.tolist() == [0, 0]
    assert sim.reaction_counts.tolist() == [0] and sim.reaction_heat == 0.0
    assert pickle.loads(pickle.dumps(sim)).reactions == sim.reactions
    sim.set_reactions(None)
    assert sim.species_counts.shape == (0,)


def test_zero_particles_with_restitution_and_a_field():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      boundary="walls", gravity=-1.0,
                                      restitution={"all": 0.5, "tc": 0.1})
    sim.measure("energy", "temperature", every=0.1)
    sim.run(until=1.0)
    sim.results()
    assert sim.dissipated == 0.0 and sim.field_energy == 0.0 and sim.potential_energy == 0.0
    back = pickle.loads(pickle.dumps(sim))
    assert back.gravity == sim.gravity and back.restitution == sim.restitution
    sim.set_gravity(None)
    sim.set_restitution(None)


def test_zero_particles_under_shear():
    sim = edmd.Simulation.from_arrays(np.zeros((0, 2)), np.zeros((0, 2)), 1.0, box=(10, 10),
                                      shear=(0.5, 3.0), restitution=0.8)
    sim.set_thermostat(kT=1.0, rate=1.0)
    sim.measure("energy", "temperature", every=0.1)
    sim.run(until=1.0)
    sim.results()
    assert sim.shear[0] == 0.5 and abs(sim.shear[1] - 8.0) < 1e-12
    assert sim.peculiar_velocities.shape == (0, 2) and sim.peculiar_kinetic_energy == 0.0
    back = pickle.loads(pickle.dumps(sim))
    assert back.shear == sim.shear
    sim.set_shear(None)
    assert sim.shear is None


def test_zero_particles_run_and_read():
    sim = empty()
    sim.run(until=1.0)
    sim.run(events=10)
    assert sim.positions.shape == (0, 2)
    assert sim.time == 1.0
    assert pickle.loads(pickle.dumps(sim)).n == 0


class Background:
    """`sim.run` in another thread, held inside its callback until told to stop."""

    def __init__(self, sim):
        self.sim = sim
        self.inside = threading.Event()
        self.stop = threading.Event()
        self.error = None
        self.thread = threading.Thread(target=self.work)

    def callback(self, sim):
        self.inside.set()
        if self.stop.is_set():
            raise StopIteration("stopped by the test")
        time.sleep(0.001)  # 10^5 callbacks: the run outlasts the test

    def work(self):
        try:
            self.sim.run(until=1e3, callback=self.callback, callback_every=0.01)
        except BaseException as e:  # noqa: BLE001 - the test inspects it
            self.error = e

    def __enter__(self):
        self.thread.start()
        assert self.inside.wait(60), "the background run did not start"
        return self

    def __exit__(self, *exc):
        self.stop.set()
        self.thread.join(60)
        assert not self.thread.is_alive()


USES = {
    "run": lambda sim: sim.run(until=sim.time + 1.0),
    "run_events": lambda sim: sim.run(events=10),
    "pickle": lambda sim: pickle.dumps(sim),
    "positions": lambda sim: sim.positions,
    "time": lambda sim: sim.time,
    "velocities_set": lambda sim: setattr(sim, "velocities", np.zeros((sim_n(), 2))),
    "measure": lambda sim: sim.measure("pressure", every=1.0),
    "write": lambda sim: sim.write("/dev/null", format="xyz"),
    "checkpoint": lambda sim: sim.checkpoint(),
    "repr": lambda sim: repr(sim),
    "pack_start": lambda sim: edmd.pack(start=sim, packing=0.3),
    "set_thermostat": lambda sim: sim.set_thermostat(kT=1.0, rate=1.0),
    "thermostat": lambda sim: sim.thermostat,
    "shells": lambda sim: sim.shells,
    "potential_energy": lambda sim: sim.potential_energy,
    "set_reactions": lambda sim: sim.set_reactions(["0 + 0 -> 1 + 1"]),
    "reactions": lambda sim: sim.reactions,
    "species_counts": lambda sim: sim.species_counts,
    "reaction_counts": lambda sim: sim.reaction_counts,
    "reaction_heat": lambda sim: sim.reaction_heat,
    "set_restitution": lambda sim: sim.set_restitution(0.9),
    "restitution": lambda sim: sim.restitution,
    "dissipated": lambda sim: sim.dissipated,
    "set_gravity": lambda sim: sim.set_gravity(-1.0),
    "gravity": lambda sim: sim.gravity,
    "field_energy": lambda sim: sim.field_energy,
    "set_shear": lambda sim: sim.set_shear(0.1),
    "shear": lambda sim: sim.shear,
    "peculiar_velocities": lambda sim: sim.peculiar_velocities,
    "peculiar_kinetic_energy": lambda sim: sim.peculiar_kinetic_energy,
}


def sim_n():
    return 200


@pytest.mark.parametrize("use", sorted(USES))
def test_a_simulation_running_in_another_thread_is_refused_clearly(use):
    sim = edmd.gen.fluid(n=sim_n(), packing=0.3, seed=1)
    with Background(sim):
        # Many tries: whether the run is inside a chunk (GIL released) or inside its
        # callback (GIL held, switched away from), the answer is the same.
        for _ in range(20):
            with pytest.raises(RuntimeError, match="another thread"):
                USES[use](sim)


def test_the_background_run_ends_cleanly_and_the_simulation_is_free_again():
    sim = edmd.gen.fluid(n=sim_n(), packing=0.3, seed=1)
    with Background(sim) as bg:
        pass
    assert isinstance(bg.error, StopIteration), bg.error
    t = sim.time
    sim.run(until=t + 1.0)  # usable again from this thread
    assert sim.time == t + 1.0
    pickle.loads(pickle.dumps(sim))


def test_run_from_its_own_callback_is_refused():
    sim = edmd.gen.fluid(n=50, packing=0.3, seed=1)
    seen = []

    def again(s):
        seen.append(s.time)
        s.run(until=s.time + 500.0)

    with pytest.raises(RuntimeError, match="callback"):
        sim.run(until=5.0, callback=again, callback_every=1.0)
    assert seen == [1.0]
    assert sim.time == 1.0
    sim.run(until=5.0)  # the mark is cleared: it runs again
    assert sim.time == 5.0


def test_a_callback_may_still_read_and_change_the_simulation():
    sim = edmd.gen.fluid(n=50, packing=0.3, seed=1)
    energies = []

    def thermostat(s):
        energies.append(s.kinetic_energy)
        s.velocities = s.velocities * 0.5
        pickle.dumps(s)

    sim.run(until=3.0, callback=thermostat, callback_every=1.0)
    assert len(energies) == 3
    assert sim.kinetic_energy == pytest.approx(energies[0] / 64, rel=1e-9)
