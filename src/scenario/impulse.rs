//! A force against a vanishing drag, checked before a run.
//!
//! The shear column's applied force `F_A` and a sheet's external pressure `p_e` start the
//! boundaries they push at about force/drag at `t = 0`, before any cell has deformed. The
//! solver measures that first rate in units of `atol` to pick its first step: once
//! force/(drag·atol) passes the largest double (about 1.8e308) the measure overflows, the first
//! step would have to be below the smallest normal double, and the run could only stop at
//! `t = 0` ("non-finite Newton update"). That happens near a drag of 1e-298 at `F_A = 1`,
//! `atol = 1e-10`. [`check_section`] rejects such a scenario at `validate`, keeping the rate
//! within [`RATE_LIMIT`] tolerances (eight decades inside the overflow), and names the smallest
//! drag that would run. Kelvin–Voigt cells bound the shear column's rate by their viscosity as
//! well (the column then runs at any drag); a sheet with Kelvin–Voigt cells is left to the
//! solver's own message.
//!
//! ```
//! use celltissue::scenario::impulse::check_section;
//! use celltissue::scenario::model::parse_model;
//! use celltissue::scenario::schema::SolverSection;
//! let solver: SolverSection = toml::from_str("atol = 1e-10")?;
//! let solver = solver.validate()?;
//! let column = |k_th: &str| parse_model(&toml::from_str(&format!(
//!     "kind = \"shear\"\ncells = 10\nforce = 1.0\nk_th = {k_th}"
//! )).unwrap()).unwrap();
//! assert!(check_section(&column("1e-280"), &solver).is_ok());
//! let e = check_section(&column("1e-300"), &solver).unwrap_err();
//! assert_eq!(e.key_name(), Some("model.k_th"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::error::ScenarioError;
use super::model::{ModelConfig, ModelSection};
use crate::cell::ViscosityModel;
use crate::scenario::format_number;
use crate::settings::SolveSettings;
use crate::sheet::{ShearConfig, SheetConfig};

/// The largest starting rate, in units of `atol` per unit time, that a scenario may ask of
/// the solver: 1e300, eight decades below the overflow at 1.8e308.
pub const RATE_LIMIT: f64 = 1e300;

/// Rejects a shear column or a sheet whose applied force or external pressure, against its
/// drag, would start its boundaries faster than [`RATE_LIMIT`] tolerances per unit time.
/// Other models (whose boundaries move at a prescribed or growth-driven rate) pass.
pub fn check_section(section: &ModelSection, solver: &SolveSettings) -> Result<(), ScenarioError> {
    match &section.config {
        ModelConfig::Shear(c, _) => check_shear(c, solver.atol),
        ModelConfig::Sheet(c, _) => check_sheet(c, solver.atol),
        _ => Ok(()),
    }
}

/// The column's top edge starts at `v = F_A·[(K + c·L)⁻¹]_MM` (`L` the column's Laplacian,
/// `c = β₀η/(2γ₀)` its Kelvin–Voigt coupling), at most `F_A·min(1/K, 2Mγ₀/(β₀η))` since both
/// `K` and `c·L` (whose inverse has `M` in that corner) are below the sum.
fn check_shear(c: &ShearConfig, atol: f64) -> Result<(), ScenarioError> {
    let eta = match c.viscosity {
        Some(ViscosityModel::KelvinVoigt { eta }) => eta,
        _ => 0.0,
    };
    let viscous = if eta > 0.0 {
        2.0 * c.cells as f64 * c.gamma0 / (c.beta0 * eta)
    } else {
        f64::INFINITY
    };
    let drag = c.drag();
    let rate = c.force.abs() * (1.0 / drag).min(viscous) / atol;
    if rate <= RATE_LIMIT {
        return Ok(());
    }
    // the smallest drag at which the force alone stays within the limit
    let needed = c.force.abs() / (atol * RATE_LIMIT);
    Err(drag_error(
        c.k_th.is_some(),
        drag,
        needed,
        &format!("the applied force F_A = {}", format_number(c.force)),
        atol,
        "or Kelvin–Voigt cells",
    ))
}

/// A free face under `p_e` starts at about `p_e·H·L/K` (docs/model.md, the sheet's face
/// rows); in tolerance units the first rate scales as `1/γ₀` (at `p_e = 1`, `atol = 1e-10`
/// the run stopped from `k_th = 1e-298` at `γ₀ = 1`, from 1e-297 at `γ₀ = 0.1` and from
/// 1e-299 at `γ₀ = 10`), bounded here by `|p_e|·max(1, 1/γ₀)/K` over the discrete cells'
/// centres.
fn check_sheet(c: &SheetConfig, atol: f64) -> Result<(), ScenarioError> {
    if matches!(c.viscosity, Some(ViscosityModel::KelvinVoigt { eta }) if eta > 0.0) {
        return Ok(());
    }
    let centres: Vec<f64> = (0..c.cells_x).map(|j| j as f64 + 0.5).collect();
    let p = c
        .external_pressure
        .sample(&centres, c.cells_x as f64)
        .into_iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    if p == 0.0 {
        return Ok(());
    }
    let geometry = (1.0 / c.gamma0).max(1.0);
    let drag = c.drag();
    if p * geometry / (drag * atol) <= RATE_LIMIT {
        return Ok(());
    }
    let needed = p * geometry / (atol * RATE_LIMIT);
    Err(drag_error(
        c.k_th.is_some(),
        drag,
        needed,
        &format!("the external pressure (up to {})", format_number(p)),
        atol,
        "or a smaller pressure",
    ))
}

/// The error on `model.k_th` (thesis drag, `K = k_th/2`) or `model.drag`, with the smallest
/// value that runs.
fn drag_error(
    thesis: bool,
    drag: f64,
    needed: f64,
    what: &str,
    atol: f64,
    other_remedy: &str,
) -> ScenarioError {
    let (key, given, least) = if thesis {
        ("model.k_th", 2.0 * drag, 2.0 * needed)
    } else {
        ("model.drag", drag, needed)
    };
    let remedy = if least.is_finite() {
        format!(
            "give {key} ≥ {} (or a larger solver.atol, {other_remedy})",
            round_up(least)
        )
    } else {
        format!("no finite {key} carries it: give a larger solver.atol, {other_remedy}")
    };
    ScenarioError::key(
        key,
        format!(
            "= {} is too small for {what}: the boundaries it pushes would start at about \
             force/drag, more than 1e300 times atol = {} per unit time, beyond what double \
             precision can step through (the first step would be below the smallest double); \
             {remedy}",
            format_number(given),
            format_number(atol),
        ),
    )
}

/// `x > 0` (finite) rounded up to two significant digits, as text (`1.9999999999999999e-290` reads
/// `2e-290`, `2.01e-290` reads `2.1e-290`).
fn round_up(x: f64) -> String {
    let mut e = x.log10().floor() as i32;
    let mut m = (x / 10f64.powi(e) * 10.0 - 1e-9).ceil() / 10.0;
    if m >= 10.0 {
        m /= 10.0;
        e += 1;
    }
    format!("{}e{e}", format_number(m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_drag_is_rounded_up_to_two_digits() {
        assert_eq!(round_up(1.9999999999999999e-290), "2e-290");
        assert_eq!(round_up(2.01e-290), "2.1e-290");
        assert_eq!(round_up(9.99e-5), "1e-4");
        assert_eq!(round_up(1e-10), "1e-10");
    }
}
