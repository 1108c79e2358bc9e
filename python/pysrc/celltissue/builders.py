"""Building and solving a line, a sheet or a shear column from Python parameters.

``celltissue.line(cells=100, K=1.0, k1=0.1)`` collects the ``[model]`` keys of a line
(documented in ``models/README.md``: ``cells``, ``K``, ``eta``, ``mu``, ``k1``, ``ramp``,
``growth``, ``division``, ``law``, …) and ``.solve(times)`` runs it through the same validation
and run code as a scenario file, so a bad parameter raises :class:`celltissue.ScenarioError`
naming ``model.<key>`` and its valid range.
"""

from __future__ import annotations

from typing import Any, Iterable, Optional, Sequence

from ._celltissue import Run, ScenarioError, run


def _times(values: Any, key: str) -> list:
    """Output times as a list of floats: one number, or a flat sequence (list, tuple, 1-D
    numpy array) of numbers; anything else raises :class:`ScenarioError` naming ``key``."""
    shape = getattr(values, "shape", None)
    if shape is not None and len(shape) > 1:
        raise _error(
            key,
            f"`{key}`: times must be one number or a flat list, "
            f"not an array of shape {tuple(shape)}",
        )
    if isinstance(values, (int, float)) or (shape is not None and len(shape) == 0):
        values = [values]
    try:
        return [float(t) for t in values]
    except (TypeError, ValueError) as e:
        raise _error(key, f"`{key}`: times must be numbers ({e})") from None


def _error(key: str, message: str) -> ScenarioError:
    err = ScenarioError(message)
    err.key = key
    err.message = message
    return err


class _Model:
    kind = ""

    def __init__(self, **params: Any):
        self.params = dict(params)

    def scenario(
        self,
        times: Iterable[float],
        model: str = "discrete",
        profiles: Optional[Iterable[float]] = None,
        nodes: Any = None,
        method: str = "bdf",
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        **solver: Any,
    ) -> dict:
        """The scenario (as a dict, the structure of a scenario file) that :meth:`solve` runs."""
        m = {"kind": self.kind, "models": [model], **self.params}
        if nodes is not None:
            m["nodes"] = nodes
        out = {"series": _times(times, "output.series")}
        if profiles is not None:
            out["profiles"] = _times(profiles, "output.profiles")
        sol = {"method": method, **solver}
        if rtol is not None:
            sol["rtol"] = rtol
        if atol is not None:
            sol["atol"] = atol
        return {"name": self.kind, "solver": sol, "output": out, "model": m}

    def solve(self, times: Iterable[float], model: str = "discrete", **options: Any) -> Run:
        """Solves the model and returns its :class:`celltissue.Run`.

        ``times``: output times of the series, a flat sequence or one number (every model
        starts at t = 0; include 0 to record the initial state). ``model``: ``"discrete"`` or
        ``"continuum"``. Options: ``profiles`` (times of the per-cell profiles), ``nodes``
        (continuum grid), ``method`` (``"bdf"``, ``"esdirk"``, ``"radau"``, ``"dopri"``),
        ``rtol``, ``atol`` and further ``[solver]`` keys.
        """
        (r,) = run(self.scenario(times, model=model, **options))
        return r

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({args})"


class Line(_Model):
    """A line (or ring) of cells, Chapters 2–3: ``[model] kind = "line"``."""

    kind = "line"


class Sheet(_Model):
    """A sheet of cells, Chapter 4.2: ``[model] kind = "sheet"`` (``cells_x``, ``cells_y``…)."""

    kind = "sheet"


class Shear(_Model):
    """A column of cells in simple shear, Chapter 4.3: ``[model] kind = "shear"`` (``cells``,
    ``force``, ``k_th`` or ``drag``…)."""

    kind = "shear"


def line(**params: Any) -> Line:
    """A line of cells from its ``[model]`` parameters, e.g. ``line(cells=100, K=1.0)``."""
    return Line(**params)


def sheet(**params: Any) -> Sheet:
    """A sheet of cells from its ``[model]`` parameters, e.g. ``sheet(cells_x=10, cells_y=10)``."""
    return Sheet(**params)


def shear(**params: Any) -> Shear:
    """A shear column from its ``[model]`` parameters, e.g. ``shear(cells=10, force=1.0)``."""
    return Shear(**params)


__all__: Sequence[str] = ["Line", "Sheet", "Shear", "line", "sheet", "shear"]
