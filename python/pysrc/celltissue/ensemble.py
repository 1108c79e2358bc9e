"""Ensembles (parameter grids, stochastic division seeds) on ``dask.distributed``.

Each member of an ensemble is one call of :func:`celltissue.run` with its own ``set``
overrides, submitted as one Dask task; the :class:`celltissue.Run` objects come back pickled
(through their exact JSON form). Scheduling, retries and data movement are Dask's: the same code
runs on a ``LocalCluster`` or on a multi-node cluster (``Client("tcp://scheduler:8786")``,
``dask-jobqueue``'s ``SLURMCluster``…).

>>> from dask.distributed import Client, LocalCluster        # doctest: +SKIP
>>> from celltissue import ensemble
>>> members = ensemble.grid({"model.K": [0.1, 1.0], "model.eta": [0.0, 1.0]})
>>> len(members), members[1]
(4, {'model.K': 0.1, 'model.eta': 1.0})
>>> with Client(LocalCluster(n_workers=2)) as client:        # doctest: +SKIP
...     runs = ensemble.run_ensemble(client, "fig2_5", members)
"""

from __future__ import annotations

import itertools
from typing import Any, Dict, List, Mapping, Optional, Sequence

from ._celltissue import Run, run

Overrides = Dict[str, Any]


def grid(axes: Mapping[str, Sequence[Any]]) -> List[Overrides]:
    """The product of parameter axes ``{"model.K": [...], "model.eta": [...]}`` as a list of
    ``set`` dicts, the last axis varying fastest."""
    keys = list(axes)
    return [dict(zip(keys, values)) for values in itertools.product(*(axes[k] for k in keys))]


def seeds(key: str, values: Sequence[int], base: Optional[Overrides] = None) -> List[Overrides]:
    """One ``set`` dict per seed, e.g. ``seeds("model.division.seed", range(8))`` for a
    ``random_area`` division rule (added to the overrides ``base``)."""
    return [{**(base or {}), key: int(s)} for s in values]


def run_member(scenario: Any, overrides: Optional[Overrides] = None, jobs: int = 1) -> List[Run]:
    """One ensemble member: :func:`celltissue.run` with ``set=overrides`` (a Dask task)."""
    return run(scenario, set=overrides, jobs=jobs)


def submit(client: Any, scenario: Any, members: Sequence[Overrides], jobs: int = 1) -> list:
    """Submits one task per member to a ``dask.distributed.Client``; returns the futures (in
    the order of ``members``)."""
    return [
        client.submit(run_member, scenario, dict(m), jobs, pure=False) for m in members
    ]


def run_ensemble(
    client: Any, scenario: Any, members: Sequence[Overrides], jobs: int = 1
) -> List[List[Run]]:
    """Runs every member on the client's cluster and gathers the results: one list of runs
    per member, in the order of ``members``. A member whose scenario is invalid raises its
    :class:`celltissue.ScenarioError` here."""
    return client.gather(submit(client, scenario, members, jobs))


__all__ = ["grid", "seeds", "run_member", "submit", "run_ensemble"]
