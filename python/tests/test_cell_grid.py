"""The proliferating continuum on the cell-number grid (`division.cell_grid`) from Python: the
bundled rim scenario's continuum run against its discrete run."""

import numpy as np

import celltissue


def test_cell_grid_follows_the_discrete_rim():
    # K = 0.1 keeps the discrete run cheap; the grid merges segments that have stopped growing
    discrete, grid = celltissue.run(
        "fig3_3d_cell_grid",
        set={
            "model.K": 0.1,
            "output.series": [0, 100, 200, 300],
            "output.profiles": [300],
        },
    )
    assert discrete.model == "discrete" and grid.model == "continuum"
    assert discrete.error is None and grid.error is None
    # N counts cells (not segments) and l follows the discrete line (measured: N equal,
    # 233 at t = 300; l within 1.4e-6)
    n_d, n_g = discrete.series["cells"], grid.series["cells"]
    assert n_d[-1] > 200
    np.testing.assert_allclose(n_g, n_d, rtol=0.02)
    np.testing.assert_allclose(grid.series["length"], discrete.series["length"], rtol=1e-4)
    # fewer segments than cells: the compressed cells behind the rim were merged
    (last_g,), (last_d,) = grid.profiles[-1:], discrete.profiles[-1:]
    assert len(last_g["x"]) < len(last_d["x"]) / 2, (len(last_g["x"]), len(last_d["x"]))


def test_cell_grid_takes_a_random_threshold_rule():
    # the bundled ensemble: thresholds U[1.8, 2.2], four cells per segment dividing one by one
    runs = celltissue.run(
        "fig3_3_ensemble",
        set={"sweep.ensemble.realisations": 2, "output.series": [0, 1.5, 3]},
    )
    assert sorted(r.model for r in runs) == ["continuum"] * 2 + ["discrete"] * 2
    assert all(r.error is None for r in runs)
    n3 = {
        m: np.mean([r.series["cells"][-1] for r in runs if r.model == m])
        for m in ("discrete", "continuum")
    }
    # every cell has divided once by t = 3 in either model (measured: about 190 of 200)
    assert all(150 < n <= 200 for n in n3.values()), n3
    # cells divide one at a time: a segment of four dividing as one would keep N a multiple
    # of four (measured: 189 in both realisations), and each division adds one cell
    cont = [r for r in runs if r.model == "continuum"]
    assert any(int(r.series["cells"][-1]) % 4 != 0 for r in cont)
    for r in cont:
        after = np.asarray(r.divisions["cells_after"])
        assert np.all(np.diff(after) == 1) and after[-1] == r.series["cells"][-1]


def test_division_ages_are_cycle_times():
    # without drag nothing is stressed: every cell grows from g = 1 to 2 at the unstressed
    # rate 1/2, so every cycle lasts 2, on the discrete line and on the cell-number grid;
    # the density continuum has no individual cells and records no age
    scenario = {
        "name": "ages",
        "output": {"series": [0, 3, 5]},
        "model": {"kind": "line", "models": ["discrete", "continuum"], "cells": 8, "nodes": 4,
                  "right_end": "free", "K": 0.0, "growth": {"sigma0": 0.1},
                  "division": {"rule": "area", "cell_grid": {}}},
    }
    scenario["output"]["profiles"] = [5]
    for r in celltissue.run(scenario):
        age = r.divisions["age"]
        assert age.shape == r.divisions["t"].shape and len(age) > 0
        np.testing.assert_allclose(age, 2.0, rtol=1e-6)
        if r.model == "discrete":
            # lineage: 8 clones of 4 cells each by t = 5 (two synchronous generations), every
            # division's daughters numbered from 8 on
            (ancestor,) = r.profile("ancestor")
            assert np.array_equal(ancestor, np.repeat(np.arange(8.0), 4))
            d = r.divisions
            born = np.concatenate([d["daughter_1"], d["daughter_2"]])
            assert sorted(born) == list(range(8, 8 + 2 * len(d["cell"])))
        else:
            # the cell-number grid's segments are not cells: no identities
            assert "cell" not in r.divisions
    del scenario["model"]["division"]["cell_grid"]
    scenario["model"]["K"] = 1e-3
    _, density = celltissue.run(scenario)
    assert len(density.divisions["t"]) > 0 and "age" not in density.divisions
