//! `celltissue._celltissue`: the compiled half of the Python package `celltissue` (PyO3,
//! abi3). It loads and validates scenarios with the library's own loader, runs them with the
//! library's run functions (in parallel on request, without the GIL) and hands the in-memory
//! run records to Python as `Run` objects with numpy arrays — no output files are
//! read or written. The pure-Python half (`pysrc/celltissue/`) adds the line and sheet
//! builders and the Dask ensemble helpers on top.

mod errors;
mod input;
mod record;
mod rim;

use celltissue::integrators::interrupt::Interrupt;
use celltissue::observe::RunRecord;
use celltissue::output::finite;
use celltissue::scenario::{execute, parallel};
use pyo3::prelude::*;
use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

/// Runs a scenario and returns its runs (in scenario order).
///
/// `scenario` is a bundled scenario's name (see `scenarios()`), a path to a TOML file, or a
/// dict with the file's structure. `set` overrides keys before validation: a `"key=value"`
/// string, a list of them, or a dict `{"model.K": 0.1}`, where `None` removes a key so that it
/// takes its default (`{"solver.jacobian_age": None, "solver.method": "radau"}`, as the
/// command line's `--unset`). `jobs` runs that many of the sweep's
/// runs at once (results do not depend on it). Invalid input raises `ScenarioError` (a
/// `ValueError` with `.key` and `.message`) before anything runs; a run whose solver fails is
/// returned with its partial data and `.error` set. A `KeyboardInterrupt` while it runs stops
/// every solve before its next step and is raised as soon as they have stopped.
#[pyfunction]
#[pyo3(signature = (scenario, set = None, jobs = 1))]
fn run(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
    jobs: usize,
) -> PyResult<Vec<record::Run>> {
    if jobs == 0 {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "jobs must be an integer >= 1 (got 0)",
        ));
    }
    let scenario = input::scenario(py, scenario, set)?;
    // a discrete run that repeats an earlier one (a sweep of the continuum's grid) is solved
    // once and its record given to the repeat, as `celltissue run` does
    let indices: Vec<usize> = (0..scenario.runs.len())
        .filter(|&i| scenario.runs[i].repeats.is_none())
        .collect();
    // every run's record is held until the list is returned
    let values = scenario.runs.iter().map(|r| r.profile_values()).sum();
    celltissue::scenario::limits::check_profiles(values, scenario.runs.len())
        .map_err(|e| errors::from_scenario(py, &e))?;
    let stop = Interrupt::new();
    let records = py.detach(|| {
        let (done, finished) = std::sync::mpsc::channel();
        std::thread::scope(|s| {
            let worker = s.spawn(|| {
                let records = parallel::run_parallel(
                    &scenario,
                    &indices,
                    jobs,
                    |spec| {
                        if stop.is_raised() {
                            return execute::not_run(spec, "interrupted before it started");
                        }
                        let mut rec = stop.scope(|| execute::run_spec(spec));
                        finite::sanitize(&mut rec);
                        rec
                    },
                    |_| {},
                );
                let _ = done.send(());
                records
            });
            // Python's signal handlers run here, between waits: a KeyboardInterrupt (Ctrl-C,
            // a notebook's "interrupt kernel") stops every solve before its next step
            let signal = loop {
                match finished.recv_timeout(SIGNAL_POLL) {
                    Err(RecvTimeoutError::Timeout) => {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            stop.raise();
                            break Some(e);
                        }
                    }
                    _ => break None,
                }
            };
            let records = worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            match signal {
                Some(e) => Err(e),
                None => records.map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string())),
            }
        })
    })?;
    let mut by_run: Vec<Option<RunRecord>> = vec![None; scenario.runs.len()];
    for (&i, rec) in indices.iter().zip(records) {
        by_run[i] = Some(rec);
    }
    for (i, spec) in scenario.runs.iter().enumerate() {
        if let Some(source) = spec.repeats.and_then(|s| by_run[s].clone()) {
            by_run[i] = Some(execute::repeated(&scenario, spec, source));
        }
    }
    Ok(by_run
        .into_iter()
        .flatten()
        .map(record::Run::from)
        .collect())
}

/// How often a running `run` lets Python handle its signals.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Validates a scenario (as for `run`) without running it; returns the labels of its runs.
#[pyfunction]
#[pyo3(signature = (scenario, set = None))]
fn validate(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<String>> {
    let scenario = input::scenario(py, scenario, set)?;
    Ok(scenario.runs.into_iter().map(|r| r.label).collect())
}

/// Names of the bundled scenarios (the thesis figures), e.g. `"fig2_5"`.
#[pyfunction]
fn scenarios() -> Vec<&'static str> {
    celltissue::scenario::bundled::BUNDLED
        .iter()
        .map(|(n, _)| *n)
        .collect()
}

/// The TOML text of a bundled scenario.
#[pyfunction]
fn scenario_text(name: &str) -> PyResult<&'static str> {
    input::bundled(name)
}

/// Rebuilds a run from `Run.to_json()` (used by pickling, e.g. to return runs from Dask
/// workers).
#[pyfunction]
fn run_from_json(text: &str) -> PyResult<record::Run> {
    record::Run::from_json(text)
}

#[pymodule]
fn _celltissue(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ScenarioError", m.py().get_type::<errors::ScenarioError>())?;
    m.add_class::<record::Run>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(scenario_text, m)?)?;
    m.add_function(wrap_pyfunction!(run_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(rim::travelling_rim, m)?)?;
    Ok(())
}
