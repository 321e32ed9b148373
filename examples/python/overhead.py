"""The Python layer's overhead, for BENCHMARKS.md: the event loop's speed from Python against
`edmd bench` on the same kind of system, and the time to read the arrays of 10^6 discs.

    python examples/python/overhead.py [--edmd target/release/edmd] [--n 100000]

Prints one JSON object.
"""

import argparse
import json
import subprocess
import time

import numpy as np

import edmd


def python_rate(n, packing, melt, collisions, dim):
    """Collisions per second of `run(until=...)` from Python on a melted fluid, timed over
    about `collisions` collisions per disc (as `edmd bench --collisions`)."""
    sim = edmd.gen.fluid(n=n, packing=packing, dim=dim, seed=1)
    while sim.stats["disc_disc"] < melt * n:
        sim.run(events=1 << 16)
    # Learn the collision rate per unit time, then time a run(until=...) of the right length.
    c0, t0 = sim.stats["disc_disc"], sim.time
    sim.run(until=t0 + 1.0)
    rate = (sim.stats["disc_disc"] - c0) / 1.0
    c0, t0 = sim.stats["disc_disc"], sim.time
    started = time.perf_counter()
    sim.run(until=t0 + collisions * n / rate)
    seconds = time.perf_counter() - started
    return (sim.stats["disc_disc"] - c0) / seconds


def bench_rate(exe, n, packing, melt, collisions, dim):
    out = subprocess.run(
        [exe, "bench", "--n", str(n), "--packing", str(packing), "--melt", str(melt),
         "--collisions", str(collisions), "--dim", str(dim)],
        check=True, capture_output=True, text=True,
    ).stdout
    return json.loads(out)["collisions_per_second"]


def same_file_rates(exe, n, packing, until, directory="."):
    """Collisions per second of Python's `run(until=...)` and of `edmd run --until` on the same
    file (a fluid melted for 20 time units), interleaved."""
    import os

    path = os.path.join(directory, f"overhead-fluid-{n}.txt")
    sim = edmd.gen.fluid(n=n, packing=packing, seed=1)
    sim.run(until=20.0)
    sim.write(path)
    s = edmd.Simulation.from_file(path)
    started = time.perf_counter()
    s.run(until=until)
    py = s.stats["disc_disc"] / (time.perf_counter() - started)
    out = subprocess.run([exe, "run", path, "--until", str(until), "--json"], check=True,
                         capture_output=True, text=True).stdout
    os.remove(path)
    return py, json.loads(out)["collisions_per_second"]


def array_read_ms(n=1_000_000, repeats=5):
    """Milliseconds to read positions and velocities of n discs (a square lattice)."""
    side = int(np.ceil(np.sqrt(n)))
    g = (np.arange(side) + 0.5) * 1.0
    pos = np.array(np.meshgrid(g, g)).reshape(2, -1).T[:n]
    vel = np.random.default_rng(1).normal(size=(n, 2))
    sim = edmd.Simulation.from_arrays(pos, vel, 0.25, box=(side, side))
    sim.run(until=0.1)
    out = {}
    for name in ("positions", "velocities", "unwrapped_positions"):
        best = float("inf")
        for _ in range(repeats):
            started = time.perf_counter()
            getattr(sim, name)
            best = min(best, time.perf_counter() - started)
        out[name] = best * 1e3
    return out


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--edmd", default="target/release/edmd")
    p.add_argument("--n", type=int, default=100_000)
    p.add_argument("--packing", type=float, default=0.5)
    p.add_argument("--melt", type=int, default=5)
    p.add_argument("--collisions", type=int, default=20)
    p.add_argument("--dim", type=int, default=2)
    p.add_argument("--repeats", type=int, default=3)
    a = p.parse_args()
    py = [python_rate(a.n, a.packing, a.melt, a.collisions, a.dim) for _ in range(a.repeats)]
    cli = [bench_rate(a.edmd, a.n, a.packing, a.melt, a.collisions, a.dim)
           for _ in range(a.repeats)]
    same = [same_file_rates(a.edmd, a.n, a.packing, 40.0) for _ in range(a.repeats)]
    print(json.dumps({
        "n": a.n, "packing": a.packing, "dim": a.dim,
        "same_file_python_run_until": [p for p, _ in same],
        "same_file_edmd_run": [c for _, c in same],
        "python_collisions_per_second": py, "edmd_bench_collisions_per_second": cli,
        "python_over_bench_best": max(py) / max(cli),
        "read_ms_n_1e6": array_read_ms(),
    }))


if __name__ == "__main__":
    main()
