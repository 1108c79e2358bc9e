//! `celltissue.travelling_rim`: the long-time rates of a proliferating rim
//! ([`celltissue::proliferation::travelling_rim`]) for neo-Hookean cells with the tanh growth law.

use crate::errors::scenario_error;
use celltissue::cell::{GrowthLaw, TanhGrowth};
use celltissue::proliferation::{travelling_rim as rim, RimError};
use celltissue::NeoHookean;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The travelling rim of a free end under drag `K` (m = 0), for neo-Hookean cells of modulus
/// `mu` and width `width` (γ₀g₂) growing by ½(1 + tanh(σ/sigma0)).
///
/// Returns a dict:
/// * ``speed``: dl/dt at long times;
/// * ``cell_rate``: the cells the rim adds per unit time (dN/dt at long times while the
///   compressed cells behind it no longer divide);
/// * ``division_depths``: ``(depth from the tip, fraction of divisions)`` pairs;
/// * ``tip_stress``;
/// * ``width``: cells from the tip to where growth falls to 1 %;
/// * ``epsilon``: the per-cell stress drop at the tip over sigma0; the error of ``speed`` is
///   O(epsilon²).
///
/// It assumes m = 0, the area rule with ratio 2 on unit cells, η = 0, no active stress and no
/// end force (docs/model.md §8.4). A parameter out of range raises `ScenarioError` naming it.
#[pyfunction]
#[pyo3(signature = (K, sigma0 = 0.1, mu = 1.0, width = 1.0))]
#[allow(non_snake_case)]
pub fn travelling_rim<'py>(
    py: Python<'py>,
    K: f64,
    sigma0: f64,
    mu: f64,
    width: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let energy = NeoHookean::new(mu).map_err(|e| scenario_error(py, Some("mu"), e.to_string()))?;
    let growth = TanhGrowth {
        sigma0,
        ..TanhGrowth::default()
    };
    growth
        .check()
        .map_err(|e| scenario_error(py, Some("sigma0"), e.to_string()))?;
    let r = py
        .detach(|| rim(&energy, &growth, K, width))
        .map_err(|e| match e {
            RimError::Parameter { key, .. } => scenario_error(py, Some(key), e.to_string()),
            e => PyRuntimeError::new_err(e.to_string()),
        })?;
    let d = PyDict::new(py);
    d.set_item("speed", r.speed)?;
    d.set_item("tip_stress", r.tip_stress)?;
    d.set_item("width", r.width)?;
    d.set_item("epsilon", r.epsilon)?;
    d.set_item("cell_rate", r.cell_rate)?;
    d.set_item("division_depths", r.division_depths)?;
    Ok(d)
}
