"""Equation of state of hard discs (or spheres): Z = PA/NkT over packings and seeds, on Dask.

Each run (one packing, one seed) is a task: make a melted fluid with ``edmd.gen.fluid``, run it
to let it forget the lattice, then measure the pressure (the collision virial, in blocks, with
its error). The runs are mapped over a Dask ``distributed`` cluster and gathered into a pandas
table (one row per run, then one per packing with the mean over seeds and its standard error),
written as CSV, and plotted against the reference equation of state.

On this machine (a ``LocalCluster`` with one worker process per core)::

    python examples/python/eos_sweep.py --packings 0.1,0.2,0.3,0.4,0.5,0.6 --seeds 4

On a running scheduler (``dask scheduler`` and ``dask worker ADDRESS`` anywhere)::

    python examples/python/eos_sweep.py --scheduler tcp://10.0.0.1:8786

On a Slurm cluster, through dask-jobqueue (``pip install dask-jobqueue``): ``--slurm 4``
submits four jobs of workers (``--slurm-cores`` each) and scales the cluster to them::

    python examples/python/eos_sweep.py --slurm 4 --slurm-cores 16 --n 10000 --seeds 16

Needs ``edmd``, ``dask[distributed]``, ``pandas`` and, for the plot, ``matplotlib``.
"""

import argparse
import math
import sys


def henderson_z(eta):
    """Henderson's equation of state for hard discs (2D)."""
    return (1 + eta**2 / 8) / (1 - eta) ** 2


def carnahan_starling_z(eta):
    """The Carnahan-Starling equation of state for hard spheres (3D)."""
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


def one_run(packing, seed, n=1000, dim=2, melt=10.0, measure=40.0, blocks=10):
    """One task: a fluid at `packing` from `seed`, melted for `melt` time units, then its
    pressure measured over `measure` in `blocks` blocks. Returns a plain dict (one table row)."""
    import time

    import edmd

    started = time.perf_counter()
    sim = edmd.gen.fluid(n=n, packing=packing, dim=dim, seed=seed)
    sim.run(until=melt)
    sim.measure("pressure", "collisions", every=measure / blocks)
    sim.run(until=melt + measure)
    r = sim.results()
    z = r["pressure"]["Z"]
    return {
        "packing": packing,
        "seed": seed,
        "n": n,
        "dim": dim,
        "Z": z["value"],
        "Z_block_error": z["error"],
        "collision_frequency": r["collisions"]["frequency"]["value"],
        "collisions": sim.stats["disc_disc"],
        "seconds": time.perf_counter() - started,
    }


def sweep(client, packings, seeds, **run_options):
    """Maps `one_run` over every (packing, seed) on the cluster behind `client`; returns the
    runs and the per-packing table (mean Z over seeds, standard error, reference Z)."""
    import pandas as pd

    pairs = [(p, s) for p in packings for s in range(1, seeds + 1)]
    futures = client.map(
        one_run, [p for p, _ in pairs], [s for _, s in pairs], pure=False, **run_options
    )
    runs = pd.DataFrame(client.gather(futures)).sort_values(["packing", "seed"])
    grouped = runs.groupby("packing")
    table = pd.DataFrame({
        "Z": grouped["Z"].mean(),
        "runs": grouped["Z"].count(),
        # Error bar: the spread over seeds when there are several, else the block error.
        "Z_error": grouped["Z"].std(ddof=1) / grouped["Z"].count() ** 0.5,
    })
    single = table["runs"] < 2
    table.loc[single, "Z_error"] = grouped["Z_block_error"].mean()[single]
    dim = run_options.get("dim", 2)
    reference = henderson_z if dim == 2 else carnahan_starling_z
    table["Z_reference"] = [reference(eta) for eta in table.index]
    return runs, table.reset_index()


def plot(table, path, dim):
    """Z against packing with error bars and the reference curve."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(6, 4))
    eta = np.linspace(0.0, max(table["packing"]) * 1.05, 200)
    if dim == 2:
        ax.plot(eta, henderson_z(eta), label="Henderson (1975)")
    else:
        ax.plot(eta, carnahan_starling_z(eta), label="Carnahan-Starling (1969)")
    ax.errorbar(table["packing"], table["Z"], yerr=table["Z_error"], fmt="o", capsize=3,
                label="edmd")
    ax.set_xlabel("packing fraction")
    ax.set_ylabel("Z = PA / NkT" if dim == 2 else "Z = PV / NkT")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def connect(args):
    """A Dask client: to --scheduler, to a Slurm cluster (--slurm), or to a LocalCluster."""
    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        return Client(args.scheduler), None
    if args.slurm:
        from dask_jobqueue import SLURMCluster

        cluster = SLURMCluster(cores=args.slurm_cores, processes=args.slurm_cores,
                               memory=args.slurm_memory, walltime=args.slurm_walltime)
        cluster.scale(jobs=args.slurm)
        return Client(cluster), cluster
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True)
    return Client(cluster), cluster


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--packings", default="0.1,0.2,0.3,0.4,0.5,0.6",
                   help="comma-separated packing fractions")
    p.add_argument("--seeds", type=int, default=3, help="runs per packing")
    p.add_argument("--n", type=int, default=1000, help="discs per run")
    p.add_argument("--dim", type=int, default=2, choices=(2, 3))
    p.add_argument("--melt", type=float, default=10.0, help="time before measuring")
    p.add_argument("--measure", type=float, default=40.0, help="time measured")
    p.add_argument("--blocks", type=int, default=10, help="blocks for the error of one run")
    p.add_argument("--scheduler", help="address of a running Dask scheduler")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of the LocalCluster (default: one per core)")
    p.add_argument("--slurm", type=int, default=0, help="Slurm jobs of workers (dask-jobqueue)")
    p.add_argument("--slurm-cores", type=int, default=8)
    p.add_argument("--slurm-memory", default="8GB")
    p.add_argument("--slurm-walltime", default="01:00:00")
    p.add_argument("--out", default="eos.csv", help="per-packing table (CSV)")
    p.add_argument("--runs-out", default=None, help="per-run table (CSV)")
    p.add_argument("--plot", default="eos.png", help="figure ('' for none)")
    args = p.parse_args(argv)
    packings = [float(x) for x in args.packings.split(",") if x.strip()]
    if not packings or any(not (0 < x < 1) or math.isnan(x) for x in packings):
        p.error("--packings: give packing fractions between 0 and 1")

    client, cluster = connect(args)
    try:
        runs, table = sweep(client, packings, args.seeds, n=args.n, dim=args.dim,
                            melt=args.melt, measure=args.measure, blocks=args.blocks)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    table.to_csv(args.out, index=False)
    if args.runs_out:
        runs.to_csv(args.runs_out, index=False)
    if args.plot:
        plot(table, args.plot, args.dim)
    print(table.to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
