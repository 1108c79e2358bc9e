"""An ensemble on ``dask.distributed``: stochastic division seeds and a parameter grid.

A line of 10 growing cells (σ₀ = 0.1, free right end) divides when a cell's area reaches a
threshold drawn from Uniform[2 − 0.2, 2 + 0.2] (``division.rule = "random_area"``); each seed
is one ensemble member, one Dask task. A second ensemble sweeps a (K, η) grid of Fig 2.5's line.

    python python/examples/dask_ensemble.py                        # a LocalCluster here
    python python/examples/dask_ensemble.py --scheduler tcp://host:8786   # an existing cluster

On a cluster the same code runs unchanged: start ``dask scheduler`` and ``dask worker``s (or
``dask_jobqueue.SLURMCluster``) with the ``celltissue`` wheel installed on every worker, and
pass the scheduler's address. Dask does the scheduling; celltissue only supplies the tasks.
"""

import argparse

import numpy as np

from celltissue import ensemble

GROWING = {
    "name": "random_division",
    "output": {"series": {"start": 0, "stop": 6, "count": 31}},
    "model": {
        "kind": "line",
        "models": ["discrete"],
        "cells": 10,
        "right_end": "free",
        "K": 1e-2,
        "growth": {"sigma0": 0.1},
        "division": {"rule": "random_area", "mean": 2.0, "spread": 0.2, "seed": 0},
    },
}


def seed_ensemble(client, seeds):
    """Cells N(t) of every seed: an array seeds × times, and the times."""
    members = ensemble.seeds("model.division.seed", seeds)
    results = ensemble.run_ensemble(client, GROWING, members)
    runs = [runs[0] for runs in results]
    return runs[0].series["t"], np.array([r.series["cells"] for r in runs])


def grid_ensemble(client, cells=20):
    """Fig 2.5's line on a (K, η) grid: {(K, η): max pressure at the end of the run}."""
    members = ensemble.grid({"model.K": [0.01, 1.0], "model.eta": [0.0, 1.0]})
    base = {"model.cells": cells, "model.nodes": cells + 1, "model.models": ["discrete"],
            "sweep.values": [1.0], "output.profiles": [1000]}
    results = ensemble.run_ensemble(
        client, "fig2_5", [{**base, **m, "sweep.parameter": "mu"} for m in members]
    )
    return {(m["model.K"], m["model.eta"]): float(runs[0].series["max_pressure"][-1])
            for m, runs in zip(members, results)}


def main(argv=None):
    from dask.distributed import Client, LocalCluster

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster workers")
    ap.add_argument("--seeds", type=int, default=8, help="ensemble size")
    args = ap.parse_args(argv)
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        client = Client(LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                     dashboard_address=None))
    with client:
        t, cells = seed_ensemble(client, range(args.seeds))
        print("t      " + " ".join(f"{x:5.1f}" for x in t[::5]))
        print("N mean " + " ".join(f"{x:5.1f}" for x in cells.mean(axis=0)[::5]))
        print("N std  " + " ".join(f"{x:5.2f}" for x in cells.std(axis=0)[::5]))
        for (k, eta), p in grid_ensemble(client).items():
            print(f"K = {k:<5g} eta = {eta:<4g} max p(t_end) = {p:.6g}")
    return t, cells


if __name__ == "__main__":
    main()
