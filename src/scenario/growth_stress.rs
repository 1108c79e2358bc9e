//! Cells too stiff for their growth law at the run's tolerance, checked before a run.
//!
//! A growing cell's rate `G(σ)` reads its stress, and the stress of a stiff cell is a small
//! difference of large numbers: the error test holds each stretch to `rtol + atol`
//! (docs/model.md §8.1), which leaves the stress free by up to `E·(rtol + atol)`, `E` the
//! cell's small-strain modulus `dσ/dα = 4μ` (μ the law's shear modulus times the largest
//! `mu`). The growth law varies on the stress scale `σ_s = G(0)/G′(0)` (σ₀ for the tanh law).
//! Once `E·(rtol + atol)` passes about ten `σ_s`, the Newton and error tests no longer pin
//! the growth rate, and the stretches and length drift past the contract. Measured on the
//! `fig3_1` line to t = 10 against an rtol 1e-11 run, rtol 1e-6 (K from 1e-3 to 1): at
//! `E·tol/σ_s` ≈ 10 the length errs by at most 3.3·rtol, at 20 by up to 23·rtol (K = 0.1),
//! at 40 by up to 20·rtol and at 400 by up to 48·rtol (K = 1e-2, 1), and at 4·10³ (μ = 1e8,
//! σ₀ = 0.1) by 22 % at K = 1e-2 while taking 8.6·10⁵ steps to t = 1; at rtol 1e-8 that
//! line runs in 101 steps within 5e-7. At K = 1e-5 the stresses stay near zero and the
//! contract held up to 4·10³: the check is conservative there.
//! [`check_section`] rejects such a scenario at `validate`, naming `solver.rtol` and the
//! tolerance that would run.
//!
//! ```
//! use celltissue::scenario::growth_stress::check_section;
//! use celltissue::scenario::model::parse_model;
//! use celltissue::scenario::schema::SolverSection;
//! let line = |mu: &str| parse_model(&toml::from_str(&format!(
//!     "kind = \"line\"\ncells = 10\nright_end = \"free\"\nmu = {mu}\ngrowth = {{ sigma0 = 0.1 }}"
//! )).unwrap()).unwrap();
//! let solver: SolverSection = toml::from_str("rtol = 1e-6")?;
//! let solver = solver.validate()?;
//! assert!(check_section(&line("1.0"), &solver).is_ok());
//! let e = check_section(&line("1e8"), &solver).unwrap_err();
//! assert_eq!(e.key_name(), Some("solver.rtol"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::error::ScenarioError;
use super::model::{ModelConfig, ModelSection};
use crate::cell::GrowthSpec;
use crate::energy::StrainEnergy;
use crate::scenario::format_number;
use crate::settings::SolveSettings;

/// The largest `E·(rtol + atol)/σ_s` a growing model may run at: the stress error the stretch
/// tolerance allows, in units of the growth law's stress scale.
pub const STRESS_RESOLUTION_LIMIT: f64 = 10.0;

/// Rejects a growing line (or a growing sheet) whose cells' stress, at the stretch tolerance
/// `rtol + atol`, is resolved to more than [`STRESS_RESOLUTION_LIMIT`] stress scales of the
/// growth law. Models without growth, a growth law flat at zero stress (no scale), and a
/// `mu` field given by a program's function pass.
pub fn check_section(section: &ModelSection, solver: &SolveSettings) -> Result<(), ScenarioError> {
    let line = match &section.config {
        ModelConfig::Line(c) => &**c,
        ModelConfig::Proliferating(p) => &p.line,
        ModelConfig::Sheet(c, law) => {
            return match &c.growth {
                Some(g) => check(g, 4.0 * law.shear_modulus(), "model.law", solver),
                None => Ok(()),
            };
        }
        _ => return Ok(()),
    };
    let (Some(growth), Some(mu)) = (&line.growth, line.mu.upper_bound()) else {
        return Ok(());
    };
    check(
        growth,
        4.0 * line.law.shear_modulus() * mu,
        "model.mu",
        solver,
    )
}

/// The check for a cell modulus `modulus` (`dσ/dα` at rest); `stiffness_key` names where the
/// modulus comes from in the message.
fn check(
    growth: &GrowthSpec,
    modulus: f64,
    stiffness_key: &str,
    solver: &SolveSettings,
) -> Result<(), ScenarioError> {
    let (g0, slope) = growth.law().rate(0.0);
    let scale = g0 / slope;
    if !(scale > 0.0 && scale.is_finite() && modulus.is_finite()) {
        return Ok(());
    }
    let tol = solver.rtol + solver.atol;
    let ratio = modulus * tol / scale;
    if ratio <= STRESS_RESOLUTION_LIMIT {
        return Ok(());
    }
    let needed = STRESS_RESOLUTION_LIMIT * scale / modulus;
    Err(ScenarioError::key(
        "solver.rtol",
        format!(
            "= {} (with atol = {}) is too loose for cells this stiff: it leaves their \
             stress, which sets the growth rate, free by E·(rtol + atol) = {:.2e} (E = 4μ = \
             {:.2e}, {stiffness_key}) against the growth law's stress scale G(0)/G'(0) = \
             {:.2e}, so growth, stretches and length would err far beyond it; \
             rtol + atol ≤ {:.2e} runs",
            format_number(solver.rtol),
            format_number(solver.atol),
            modulus * tol,
            modulus,
            scale,
            needed,
        ),
    ))
}
