"""Thesis Fig 2.5 from Python: a line of N = 100 neo-Hookean cells (η = 0) shortened by 10 % by
the exponential ramp, for four substrate drags K; pressure p and stretch λ against the
reference position X at t = 0, 1, 10, 1000 — discrete cells as symbols, the continuum as lines.

    python python/examples/fig2_5.py --out fig2_5.png        # (pip install ./python matplotlib)

Runs the bundled scenario ``fig2_5`` (the same one as ``celltissue run fig2_5``) through
``celltissue.run`` and plots the in-memory records; no files are read.
"""

import argparse

import matplotlib

import celltissue


def data(cells=100, jobs=2):
    """The runs of Fig 2.5 grouped by K: {K label: {"discrete": Run, "continuum": Run}}."""
    overrides = {"model.cells": cells, "model.nodes": cells + 1}
    runs = celltissue.run("fig2_5", set=overrides, jobs=jobs)
    panels = {}
    for r in runs:
        if r.error is not None:
            raise RuntimeError(f"{r.label}: {r.error}")
        panels.setdefault(r.parameters["sweep"]["label"], {})[r.model] = r
    return panels


def plot(panels, out):
    """Two rows (p, λ) × one column per K, one colour per profile time."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(panels), figsize=(4 * len(panels), 6.5), squeeze=False)
    for col, (k, pair) in enumerate(panels.items()):
        for row, (field, name) in enumerate([("pressure", "p"), ("stretch", "λ")]):
            ax = axes[row][col]
            for i, (pd, pc) in enumerate(zip(pair["discrete"].profiles, pair["continuum"].profiles)):
                colour = f"C{i}"
                ax.plot(pc["X"], pc[field], "-", color=colour, lw=1.2, label=f"t = {pc['t']:g}")
                ax.plot(pd["X"], pd[field], "o", color=colour, ms=2.5, mfc="none")
            ax.set_xlabel("X")
            ax.set_ylabel(name)
            if row == 0:
                ax.set_title(f"K = {k}")
    axes[0][0].legend(fontsize=8)
    fig.suptitle("Fig 2.5: η = 0, exponential ramp (symbols: discrete N cells; lines: continuum)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="fig2_5.png", help="PNG file to write")
    ap.add_argument("--cells", type=int, default=100, help="N (the thesis: 100)")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once")
    args = ap.parse_args(argv)
    if "MPLBACKEND" not in __import__("os").environ:
        matplotlib.use("Agg")
    plot(data(args.cells, args.jobs), args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
