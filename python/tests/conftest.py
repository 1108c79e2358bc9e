"""Shared fixtures: small versions of the bundled scenarios (seconds, not minutes)."""

import json

import pytest

SMALL_FIG2_5 = {"model.cells": 20, "model.nodes": 21}


def record_without_timing(run):
    """A run's record as a dict with its one timing field removed."""
    d = json.loads(run.to_json())
    d["stats"].pop("wall_seconds")
    return d


@pytest.fixture
def small_line_toml(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(
        """
name = "small"
[output]
series = { start = 0, stop = 2, count = 21 }
profiles = [0, 2]
[model]
kind = "line"
models = ["discrete", "continuum"]
nodes = 11
cells = 10
[sweep]
parameter = "K"
values = [0.1, 1]
"""
    )
    return path
