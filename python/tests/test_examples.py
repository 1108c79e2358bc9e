"""The Fig 2.5 example script end to end with matplotlib's Agg backend (N = 20 for speed),
and its data path at the thesis' N = 100."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

EXAMPLES = pathlib.Path(__file__).parent.parent / "examples"


def test_fig2_5_data_path():
    sys.path.insert(0, str(EXAMPLES))
    try:
        pytest.importorskip("matplotlib")
        import fig2_5
    finally:
        sys.path.pop(0)
    panels = fig2_5.data(cells=100)
    assert list(panels) == ["1e-5", "0.01", "1", "10"]
    for pair in panels.values():
        d, c = pair["discrete"], pair["continuum"]
        assert [p["t"] for p in d.profiles] == [0.0, 1.0, 10.0, 1000.0]
        # at t = 0 the line is unstretched: λ = 1; the cells' stretches always add up to the
        # prescribed length, so at t = 1000 their mean is 1 − k₁ = 0.9 whatever K
        np.testing.assert_allclose(d.profiles[0]["stretch"], 1.0, atol=1e-12)
        assert np.mean(d.profiles[-1]["stretch"]) == pytest.approx(0.9, rel=1e-9)
    # with weak drag the line has relaxed to the uniform stretch by t = 1000 (docs/model.md §2.6)
    for k in ["1e-5", "0.01"]:
        for run in panels[k].values():
            np.testing.assert_allclose(run.profiles[-1]["stretch"], 0.9, atol=1e-4)


def test_fig2_5_script_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "fig2_5.png"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    subprocess.run(
        [sys.executable, str(EXAMPLES / "fig2_5.py"), "--cells", "20", "--out", str(out)],
        check=True,
        env=env,
        timeout=300,
    )
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000
