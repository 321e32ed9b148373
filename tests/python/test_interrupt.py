"""Ctrl-C during a run: KeyboardInterrupt within a fraction of a second, a consistent state."""

import os
import signal
import threading
import time

import numpy as np

import edmd


def test_ctrl_c_interrupts_a_long_run_quickly(ctrl_c):
    sim = edmd.gen.fluid(n=2000, packing=0.5, seed=1)
    reference = edmd.Simulation.from_checkpoint(sim.checkpoint())
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    try:
        sim.run(until=1e6)
    except KeyboardInterrupt:
        pass
    else:
        raise AssertionError("the run was not interrupted")
    finally:
        timer.cancel()
    waited = time.monotonic() - started
    assert waited < 0.5 + 1.0, f"KeyboardInterrupt came after {waited:.2f} s"
    # The state is consistent: the uninterrupted run to the same time agrees bit for bit.
    t = sim.time
    assert 0.0 < t < 1e9
    reference.run(until=t)
    assert np.array_equal(reference.positions, sim.positions)
    assert np.array_equal(reference.velocities, sim.velocities)
    sim.run(until=t + 1.0)  # and it runs on
