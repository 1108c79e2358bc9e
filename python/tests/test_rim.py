"""celltissue.travelling_rim against a proliferating run's long-time elongation speed."""

import numpy as np
import pytest

import celltissue


def test_rim_speed_matches_a_strong_drag_run():
    # K = 0.1: the rim is about one cell wide (epsilon ~ 0.64), so the discrete run is cheap;
    # the prediction's error there is 2.7 % (docs/model.md §8.4)
    (run,) = celltissue.run(
        "fig3_3d",
        set={
            "model.K": 0.1,
            "output.series": {"start": 600, "stop": 1000, "count": 3},
            "output.profiles": [1000],
        },
    )
    assert run.error is None
    t, length = run.series["t"], run.series["length"]
    measured = (length[-1] - length[-2]) / (t[-1] - t[-2])
    rim = celltissue.travelling_rim(0.1)
    assert rim["epsilon"] > 0.5
    assert abs(rim["speed"] / measured - 1) < 0.04, (rim, measured)
    assert rim["speed"] > measured  # the continuum overestimates, at O(epsilon²)
    cells = run.series["cells"]
    added = (cells[-1] - cells[-2]) / (t[-1] - t[-2])
    assert abs(rim["cell_rate"] / added - 1) < 0.04, (rim, added)
    # where the rim divides after t = 800: depth from the tip of each division's parent
    d = run.divisions
    late = d["t"] > 800
    depths, counts = np.unique((d["cells_after"] - d["parent"])[late], return_counts=True)
    assert [int(x) for x in depths] == [depth for depth, _ in rim["division_depths"]]
    np.testing.assert_allclose(
        counts / counts.sum(), [share for _, share in rim["division_depths"]], atol=0.02
    )


@pytest.mark.parametrize(
    "kwargs, key",
    [({"K": 0.0}, "K"), ({"K": 1e-2, "width": -1.0}, "width"), ({"K": 1e-2, "mu": 0.0}, "mu")],
)
def test_bad_parameters_name_the_key(kwargs, key):
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.travelling_rim(**kwargs)
    assert info.value.key == key


def test_speed_scales_as_inverse_root_drag_when_weak():
    # weak drag, stiff cells: V -> sqrt(sigma0 ln 2 / K)
    v = [celltissue.travelling_rim(k, mu=100.0)["speed"] * np.sqrt(k) for k in (1e-6, 1e-7)]
    assert abs(v[1] / np.sqrt(0.1 * np.log(2)) - 1) < 2e-3
    assert abs(v[1] - np.sqrt(0.1 * np.log(2))) < abs(v[0] - np.sqrt(0.1 * np.log(2)))
