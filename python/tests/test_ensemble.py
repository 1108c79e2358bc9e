"""Ensembles on a dask.distributed LocalCluster (two worker processes): the gathered runs are
exactly those of running each member here, seeds reproduce, and different seeds differ."""

import numpy as np
import pytest

import celltissue
from celltissue import ensemble
from conftest import record_without_timing

distributed = pytest.importorskip("dask.distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_grid_helper():
    g = ensemble.grid({"model.K": [0.1, 1.0], "model.eta": [0.0, 1.0, 2.0]})
    assert len(g) == 6 and g[0] == {"model.K": 0.1, "model.eta": 0.0}
    assert g[-1] == {"model.K": 1.0, "model.eta": 2.0}
    assert ensemble.seeds("model.division.seed", range(2), {"model.K": 1}) == [
        {"model.K": 1, "model.division.seed": 0},
        {"model.K": 1, "model.division.seed": 1},
    ]


def test_grid_on_dask_equals_local_runs(client):
    members = ensemble.grid({"model.cells": [6, 8], "model.eta": [0.0, 1.0]})
    base = {"sweep.values": [1.0]}
    members = [{**base, **m, "model.nodes": m["model.cells"] + 1} for m in members]
    remote = ensemble.run_ensemble(client, "fig2_5", members)
    assert len(remote) == 4
    for m, runs in zip(members, remote):
        local = celltissue.run("fig2_5", set=m)
        assert [record_without_timing(r) for r in runs] == [
            record_without_timing(r) for r in local
        ]
        assert runs[0].profile("x").shape[1] == m["model.cells"]


def test_division_seeds_on_dask(client):
    import importlib.util
    import pathlib

    path = pathlib.Path(__file__).parent.parent / "examples" / "dask_ensemble.py"
    spec = importlib.util.spec_from_file_location("dask_ensemble", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    t, cells = example.seed_ensemble(client, [0, 1, 2, 0])
    assert cells.shape == (4, t.shape[0])
    assert np.array_equal(cells[0], cells[3])  # same seed, same history
    assert not (np.array_equal(cells[0], cells[1]) and np.array_equal(cells[1], cells[2]))
    assert np.all(cells[:, 0] == 10) and np.all(np.diff(cells, axis=1) >= 0)
    assert np.all(cells[:, -1] > 10)  # growth at sigma0 = 0.1 divides cells by t = 6
    grid = example.grid_ensemble(client, cells=8)
    assert len(grid) == 4 and all(np.isfinite(list(grid.values())))


def test_invalid_member_raises_scenario_error(client):
    with pytest.raises(celltissue.ScenarioError, match="model.cells"):
        ensemble.run_ensemble(client, "fig2_5", [{"model.cells": 0}])


def test_scenario_error_from_a_worker_keeps_key_and_message(client):
    # a swept key overridden by --set, and a value out of range: both raised on a worker
    for member, key in [({"model.K": 0.5}, "model.K"), ({"model.mu": -1.0}, "model.mu")]:
        with pytest.raises(celltissue.ScenarioError) as info:
            ensemble.run_ensemble(client, "fig2_5", [member])
        assert info.value.key == key
        assert key in info.value.message
