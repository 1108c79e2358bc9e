//! `celltissue.Run`: one run's in-memory record ([`RunRecord`]) seen from Python — series and
//! profiles as numpy arrays, stats and parameters as dicts. Picklable (through its JSON form,
//! which round-trips every number exactly), so runs can come back from Dask workers.

use celltissue::observe::{ModelKind, Profile, RunRecord};
use celltissue::output::files::{profile_field_name, series_columns};
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// One run: one discretisation of one parameter set.
#[pyclass(module = "celltissue", frozen)]
pub struct Run {
    rec: RunRecord,
}

impl From<RunRecord> for Run {
    fn from(rec: RunRecord) -> Run {
        Run { rec }
    }
}

impl Run {
    /// From `to_json()`.
    pub fn from_json(text: &str) -> PyResult<Run> {
        serde_json::from_str(text)
            .map(|rec| Run { rec })
            .map_err(|e| PyValueError::new_err(format!("not a celltissue run record: {e}")))
    }
}

/// A profile's fields under their output names ([`profile_field_name`]: a shear column's `Y`
/// and `tan_theta`), the model's further fields after them.
fn profile_fields<'a>(rec: &RunRecord, p: &'a Profile) -> Vec<(&'a str, &'a Vec<f64>)> {
    [
        ("X", &p.x_ref),
        ("x", &p.x),
        ("stretch", &p.stretch),
        ("pressure", &p.pressure),
    ]
    .into_iter()
    .map(|(k, v)| (profile_field_name(rec, k), v))
    .chain(p.extra.iter().map(|(k, v)| (k.as_str(), v)))
    .collect()
}

/// Python's value of a JSON value (through the `json` module).
fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (v.to_string(),))
}

#[pymethods]
impl Run {
    /// Label used in legends and file names, e.g. `"discrete K=0.01"`.
    #[getter]
    fn label(&self) -> &str {
        &self.rec.label
    }

    /// `"discrete"` or `"continuum"`.
    #[getter]
    fn model(&self) -> &'static str {
        match self.rec.model {
            ModelKind::Discrete => "discrete",
            ModelKind::Continuum => "continuum",
        }
    }

    /// The resolved parameters (model configuration, `"kind"`, `"solver"`, `"sweep"`).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.rec.parameters)
    }

    /// Scalar series by name, each a numpy array over the output times `"t"`, named as in
    /// the run's `series_<label>.csv` and `.npz` (a shear column's `max_tan_theta`,
    /// `min_tan_theta` and `top_displacement`, not a line's `max_stretch` and `length`).
    #[getter]
    fn series<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in series_columns(&self.rec) {
            d.set_item(k, v.clone().into_pyarray(py))?;
        }
        Ok(d)
    }

    /// Snapshots at the profile times: a list of dicts with `"t"` (float) and per-cell
    /// (per-node) numpy arrays `"X"` (reference position), `"x"`, `"stretch"`, `"pressure"`
    /// and the model's further fields, named as in the run's profile CSV (a shear column's
    /// `"Y"` and `"tan_theta"`).
    #[getter]
    fn profiles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for p in &self.rec.profiles {
            let d = PyDict::new(py);
            d.set_item("t", p.t)?;
            for (k, v) in profile_fields(&self.rec, p) {
                d.set_item(k, v.clone().into_pyarray(py))?;
            }
            list.append(d)?;
        }
        Ok(list)
    }

    /// One profile field stacked over the profile times: a `times × cells` numpy array.
    /// Raises `ValueError` if the run recorded no profiles, the field is unknown or its length
    /// changes between times (cells divided).
    fn profile<'py>(&self, py: Python<'py>, field: &str) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if self.rec.profiles.is_empty() {
            // an empty array would hide a forgotten `profiles=` and accept any field name
            return Err(PyValueError::new_err(format!(
                "this run recorded no profiles, so no `{field}`: give profile times \
                 (`solve(…, profiles=[…])`, or `output.profiles` in a scenario)"
            )));
        }
        let rows: Vec<&Vec<f64>> = self
            .rec
            .profiles
            .iter()
            .map(|p| {
                profile_fields(&self.rec, p)
                    .into_iter()
                    .find(|(k, _)| *k == field)
                    .map(|(_, v)| v)
            })
            .collect::<Option<_>>()
            .ok_or_else(|| {
                PyValueError::new_err(format!("`{field}` is not a profile field of this run"))
            })?;
        let width = rows.first().map_or(0, |r| r.len());
        if rows.iter().any(|r| r.len() != width) {
            return Err(PyValueError::new_err(format!(
                "`{field}` changes length between profile times (cells divided); use .profiles"
            )));
        }
        let rows: Vec<Vec<f64>> = rows.into_iter().cloned().collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Division events as numpy arrays `"t"`, `"parent"` (1-based), `"x"`, `"x_over_length"`,
    /// `"cells_after"` (all empty without division), `"age"`, the dividing cells' cycle
    /// times, unless the model has no individual cells (the density continuum), and
    /// `"cell"`, `"daughter_1"`, `"daughter_2"`, their identities, where the model traces
    /// lineage (the discrete line and ring).
    #[getter]
    fn divisions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        use celltissue::events::log::{division_columns, DivisionColumn};
        let d = PyDict::new(py);
        for (name, column) in division_columns(&self.rec.divisions) {
            match column {
                DivisionColumn::F64(v) => d.set_item(name, v.into_pyarray(py))?,
                DivisionColumn::I64(v) => d.set_item(name, v.into_pyarray(py))?,
            }
        }
        Ok(d)
    }

    /// Integrator work: `steps`, `residual_calls`, `jacobians` (ints), `wall_seconds` and
    /// further counters by name.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.rec.stats;
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("residual_calls", s.residual_calls)?;
        d.set_item("jacobians", s.jacobians)?;
        d.set_item("wall_seconds", s.wall_seconds)?;
        for (k, v) in &s.extra {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The analytic solution of the run's configuration where one applies (lines with a
    /// prescribed end), else None: a dict with `"label"`, `"series"` (`"t"`, `"max_pressure"`,
    /// `"min_stretch"`), `"profiles"` and `"equilibrium"` (each a list of dicts of numpy
    /// arrays: `"t"`, `"X"`, `"stretch"`, `"pressure"`; `"t"`, `"X"`, `"x"`).
    #[getter]
    fn reference<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(r) = &self.rec.reference else {
            return Ok(None);
        };
        let arr = |v: &[f64]| v.to_vec().into_pyarray(py);
        let d = PyDict::new(py);
        d.set_item("label", &r.label)?;
        let series = PyDict::new(py);
        series.set_item("t", arr(&r.series.t))?;
        series.set_item("max_pressure", arr(&r.series.max_pressure))?;
        series.set_item("min_stretch", arr(&r.series.min_stretch))?;
        d.set_item("series", series)?;
        let profiles = PyList::empty(py);
        for p in &r.profiles {
            let q = PyDict::new(py);
            q.set_item("t", p.t)?;
            q.set_item("X", arr(&p.x_ref))?;
            q.set_item("stretch", arr(&p.stretch))?;
            q.set_item("pressure", arr(&p.pressure))?;
            profiles.append(q)?;
        }
        d.set_item("profiles", profiles)?;
        let equilibrium = PyList::empty(py);
        for e in &r.equilibrium {
            let q = PyDict::new(py);
            q.set_item("t", e.t)?;
            q.set_item("X", arr(&e.x_ref))?;
            q.set_item("x", arr(&e.x))?;
            equilibrium.append(q)?;
        }
        d.set_item("equilibrium", equilibrium)?;
        Ok(Some(d))
    }

    /// The run against itself at a tenfold tighter tolerance, where `solver.accuracy_check`
    /// asked for it, else None: a dict with `"rtol"`, `"atol"` and `"steps"` of the tighter run,
    /// `"profiles_compared"`, `"profiles_skipped"`, the largest `"stretch_difference"` (over
    /// the contract's weight |λ| + atol/rtol), `"stretch_over_rtol"` (the contract holds it to
    /// 10), its `"t"` and `"cell"`, the largest `"pressure_difference"`, the same for the
    /// series' smallest and largest stretch (`"series_times_compared"`,
    /// `"series_stretch_over_rtol"`, `"series_t"`), and `"failed"` (the tighter run's error,
    /// or None).
    #[getter]
    fn accuracy_check<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = &self.rec.accuracy_check else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("rtol", c.rtol)?;
        d.set_item("atol", c.atol)?;
        d.set_item("steps", c.steps)?;
        d.set_item("profiles_compared", c.profiles_compared)?;
        d.set_item("profiles_skipped", c.profiles_skipped)?;
        d.set_item("stretch_difference", c.stretch_difference)?;
        d.set_item("stretch_over_rtol", c.stretch_over_rtol)?;
        d.set_item("t", c.t)?;
        d.set_item("cell", c.cell)?;
        d.set_item("pressure_difference", c.pressure_difference)?;
        d.set_item("series_times_compared", c.series_times_compared)?;
        d.set_item("series_stretch_over_rtol", c.series_stretch_over_rtol)?;
        d.set_item("series_t", c.series_t)?;
        d.set_item("failed", c.failed.as_deref())?;
        Ok(Some(d))
    }

    /// The solver's message if the run failed (the record holds what was computed before),
    /// else None.
    #[getter]
    fn error(&self) -> Option<&str> {
        self.rec.error.as_deref()
    }

    /// What to know about a finished run's numbers, one sentence each (a dividing line that
    /// reached its `max_cells` cap, for one); empty for most runs.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.rec.notes.clone()
    }

    /// The record as JSON (the `summary.json` schema of one run).
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.rec).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let f = py
            .import("celltissue._celltissue")?
            .getattr("run_from_json")?;
        Ok((f, (self.to_json()?,)))
    }

    fn __repr__(&self) -> String {
        format!(
            "Run(label={:?}, model={:?}, outputs={}, profiles={}, steps={}{})",
            self.rec.label,
            self.model(),
            self.rec.series.t.len(),
            self.rec.profiles.len(),
            self.rec.stats.steps,
            self.rec
                .error
                .as_ref()
                .map(|e| format!(", error={e:?}"))
                .unwrap_or_default()
        )
    }
}
