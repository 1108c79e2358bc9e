"""celltissue: discrete-to-continuum mechanics of cells in tissues, from Python.

The solver is the Rust crate ``celltissue``; this package runs its scenarios and hands back the
in-memory run records with numpy arrays.

>>> import celltissue
>>> runs = celltissue.run("fig2_5", set={"model.cells": 10, "model.nodes": 11})
>>> [r.label for r in runs][:2]
['discrete K=1e-5', 'continuum K=1e-5']
>>> runs[0].series["t"][0]
0.0

* :func:`run` — a bundled scenario (:func:`scenarios`), a TOML file or a dict → list of
  :class:`Run` (``.label``, ``.model``, ``.parameters``, ``.series``, ``.profiles``,
  ``.profile(name)``, ``.divisions``, ``.stats``, ``.error``).
* :func:`line`, :func:`sheet`, :func:`shear` — build a model from keyword parameters and ``.solve(times)``.
* :mod:`celltissue.ensemble` — run parameter grids and seeds on a ``dask.distributed`` client.
* :func:`travelling_rim` — the long-time speed of a proliferating rim under strong drag
  (docs/model.md §8.4), to compare with a run's late ``dl/dt``.

Bad input raises :class:`ScenarioError` (a ``ValueError``) with ``.key`` and ``.message``
before anything runs.
"""

from ._celltissue import (
    Run,
    ScenarioError,
    __version__,
    run,
    run_from_json,
    scenario_text,
    scenarios,
    travelling_rim,
    validate,
)
from .builders import Line, Shear, Sheet, line, shear, sheet

__all__ = [
    "Run",
    "ScenarioError",
    "Line",
    "Shear",
    "Sheet",
    "__version__",
    "line",
    "run",
    "run_from_json",
    "scenario_text",
    "scenarios",
    "shear",
    "sheet",
    "travelling_rim",
    "validate",
]
