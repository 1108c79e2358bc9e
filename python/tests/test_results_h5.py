"""`results.h5` (the CLI's `hdf5` feature) read with h5py, whose HDF5 library is its own build:
every array equals the same run's `.npz` member, and the attributes carry the parameters,
stats and provenance. CI writes the directory with the feature on and names it in
CELLTISSUE_H5_DIR (see .ci/run); without it there is no file to read and the test is skipped."""

import json
import os
from pathlib import Path

import numpy as np
import pytest

H5_DIR = os.environ.get("CELLTISSUE_H5_DIR")


@pytest.mark.skipif(not H5_DIR, reason="CELLTISSUE_H5_DIR names no run directory with results.h5")
def test_results_h5_equals_the_npz_archives():
    h5py = pytest.importorskip("h5py")
    out = Path(H5_DIR)
    summary = json.loads((out / "summary.json").read_text())
    with h5py.File(out / "results.h5", "r") as f:
        assert f.attrs["scenario"] == summary["scenario"]
        provenance = json.loads(f.attrs["provenance"])
        assert provenance["version"] == summary["provenance"]["version"]
        assert len(f.keys()) == len(summary["runs"])
        compared = 0
        for index, run in enumerate(summary["runs"]):
            g = f[run["label"]]
            assert g.attrs["index"] == index
            assert json.loads(g.attrs["stats"])["steps"] == run["stats"]["steps"]
            with np.load(out / run["arrays"]) as z:
                for name in z.files:
                    a = g[name.removesuffix(".npy")][()]
                    assert a.shape == z[name].shape, name
                    assert np.array_equal(a, z[name]), name
                    compared += 1
        assert compared > 10
