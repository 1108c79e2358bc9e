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
