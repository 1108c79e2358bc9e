"""Bad input raises celltissue.ScenarioError (a ValueError) naming the key and the valid range,
before anything runs."""

import pytest

import celltissue


@pytest.mark.parametrize(
    "params, key, needle",
    [
        ({"cells": 0}, "model.cells", ">= 1"),
        ({"K": -1.0}, "model.K", ">= 0"),
        ({"kay": 1.0}, "model.kay", "unknown field"),
        ({"K": "x"}, "model.K", "invalid type"),
    ],
)
def test_bad_model_parameters_name_the_key(params, key, needle):
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.line(**params).solve([0.0, 1.0])
    e = info.value
    assert isinstance(e, ValueError)
    assert e.key == key
    assert needle in e.message and key in str(e)


def test_bad_override_names_the_key():
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.run("fig2_5", set={"solver.rtol": 2.0})
    assert info.value.key == "solver.rtol"
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.validate("fig2_5", set="model.cells")
    assert "model.cells" in info.value.message


def test_unknown_scenario_lists_the_bundled_ones():
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.run("fig9_9")
    assert info.value.key is None
    assert "fig2_5" in info.value.message


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(celltissue.ScenarioError, match="cannot read"):
        celltissue.run(tmp_path / "absent.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    with pytest.raises(celltissue.ScenarioError, match="not valid TOML"):
        celltissue.run(bad)


def test_unusable_python_values():
    with pytest.raises(celltissue.ScenarioError, match="None"):
        celltissue.run({"name": "x", "model": {"kind": "line", "K": None}})
    with pytest.raises(celltissue.ScenarioError, match="expected a bundled name"):
        celltissue.run(42)
    with pytest.raises(celltissue.ScenarioError, match="set"):
        celltissue.run("fig2_5", set=3)


def test_zero_jobs_is_refused():
    with pytest.raises(ValueError, match="jobs must be an integer"):
        celltissue.run("fig2_5", set={"model.cells": 4, "model.nodes": 5}, jobs=0)


@pytest.mark.parametrize(
    "params, times, key, needle",
    [
        ({"K": float("nan")}, [0.0, 1.0], "model.K", "finite"),
        ({"K": float("inf")}, [0.0, 1.0], "model.K", "finite"),
        ({"K": 1.0}, [0.0, float("nan")], "output.series", "finite"),
        ({"K": 1.0}, [0.0, float("inf")], "output.series", "finite"),
    ],
)
def test_non_finite_numbers_name_their_key(params, times, key, needle):
    # they used to fail in the JSON step as "scenario: expected value at line 1 column 74"
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.line(cells=5, **params).solve(times)
    assert info.value.key == key, str(info.value)
    assert needle in info.value.message


def test_numpy_values_and_nesting():
    np = pytest.importorskip("numpy")
    # NumPy arrays and scalars are taken as their Python values
    r = celltissue.run(
        {
            "name": "np",
            "output": {"series": np.linspace(0.0, 1.0, 3)},
            "model": {"kind": "line", "cells": np.int64(5), "K": np.float64(0.1),
                      "models": ["discrete"]},
        },
        set={"output.profiles": np.array([1.0])},
    )
    assert list(r[0].series["t"]) == [0.0, 0.5, 1.0]
    assert len(r[0].profiles) == 1
    loop = {"name": "x"}
    loop["model"] = loop
    with pytest.raises(celltissue.ScenarioError, match="nested more than"):
        celltissue.run(loop)
    with pytest.raises(celltissue.ScenarioError, match="64 bits"):
        celltissue.line(cells=2**70).solve([0.0, 1.0])


def test_profiles_beyond_memory_name_output_profiles():
    # 10⁶ cells at 10⁵ profile times: 1e11 values, 17.5 TB; refused before anything runs
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.line(cells=1_000_000, K=1.0).solve(
            [0.0, 1.0], profiles=[i * 1e-5 for i in range(100_000)]
        )
    assert info.value.key == "output.profiles"
    assert "17.5 TB" in info.value.message


def test_none_in_set_removes_a_key():
    # fig3_3 sets the BDF-only solver.jacobian_age: removed, another method runs
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.validate("fig3_3", set={"solver.method": "radau"})
    assert info.value.key == "solver.jacobian_age"
    s = celltissue.validate("fig3_3", set={"solver.jacobian_age": None, "solver.method": "radau"})
    assert s == celltissue.validate("fig3_3")  # the same runs
    with pytest.raises(celltissue.ScenarioError) as info:
        celltissue.validate("fig3_3", set={"solver.jacobian_ag": None})
    assert info.value.key == "solver.jacobian_ag" and "does not have" in info.value.message


def test_output_times_of_the_wrong_shape_name_their_key():
    import numpy as np

    line = celltissue.line(cells=5, K=1.0, k1=0.1)
    with pytest.raises(celltissue.ScenarioError) as info:
        line.solve(np.zeros((2, 2)))
    assert info.value.key == "output.series" and "(2, 2)" in info.value.message
    with pytest.raises(celltissue.ScenarioError) as info:
        line.solve([0.0, 1.0], profiles=["late"])
    assert info.value.key == "output.profiles" and "numbers" in info.value.message
    # one number is one output time (a 0-d array too)
    for t in (1.0, 2, np.float64(1.5), np.array(0.5)):
        run = line.solve(t)
        assert run.error is None and run.series["t"].tolist() == [float(t)]
