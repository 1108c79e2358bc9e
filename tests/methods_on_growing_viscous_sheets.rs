//! Every method on a growing Kelvin–Voigt sheet, where the residual is nonlinear in ẏ (the
//! growth law reads the viscous stress): a 2 × 6 sheet with a free side and a free top, found
//! by the accuracy-contract sweep (`accuracy_contract_fuzz`, sheets, case 320 of 600).
//!
//! Radau IIA used to crawl there: its first step and every retry started the stages from
//! Z = 0, i.e. every stage rate at 0, an O(1) distance from ẏₙ however short the step, which
//! its simplified Newton iteration (∂F/∂ẏ frozen at ẏₙ) crossed by only 0.3–0.7 per
//! iteration. At rtol 1e-6 it took 2·10⁵ steps to reach t = 0.015 of 0.21, two Newton
//! failures per step. It now starts from `Zᵢ = cᵢ h ẏₙ` (stage rates ẏₙ exactly).
//!
//! What is asserted: BDF, Radau IIA and ESDIRK finish at rtol 1e-6 and 1e-8 with either norm;
//! BDF and Radau IIA hold every stretch (both directions) within the contract's 10·rtol of BDF
//! at rtol 1e-11; Radau IIA's cost is pinned (5 steps, no rejection, no Newton failure).

use crate::common::{profile_gap, run_with};
use celltissue::observe::{Profile, RunRecord};

const SHEET: &str = r#"
name = "growing_viscous_sheet"
[output]
series = { start = 0, stop = 0.20548033324969942, count = 5 }
profiles = [0.051370083312424854, 0.10274016662484971, 0.20548033324969942]
[model]
kind = "sheet"
models = ["discrete"]
cells_x = 2
cells_y = 6
law = { law = "neo_hookean", mu = 0.5905773113308265 }
k_th = 8.882052969355646
drag_exponent = 1
top = "free"
viscosity = { model = "kelvin_voigt", eta = 5.522268617853501 }
right = "free"
growth = { sigma0 = 0.1992060809108235 }
growth_directions = "both"
"#;

/// The sheet run with `method` and `norm` at `rtol` (atol = rtol/100); the old crawl passed
/// 2 000 steps in the first 1 % of the span.
fn run(method: &str, norm: &str, rtol: f64) -> RunRecord {
    run_with(SHEET, method, norm, rtol, 2000)
}

/// Largest relative stretch difference, both in-plane directions, every cell and profile.
fn stretch_gap(a: &RunRecord, b: &RunRecord) -> f64 {
    fn x(p: &Profile) -> &[f64] {
        &p.stretch
    }
    fn y(p: &Profile) -> &[f64] {
        &p.extra["stretch_y"]
    }
    profile_gap(a, b, x).max(profile_gap(a, b, y))
}

#[test]
fn every_method_finishes_and_bdf_and_radau_hold_the_contract() {
    let reference = run("bdf", "max", 1e-11);
    for norm in ["max", "rms"] {
        for rtol in [1e-6, 1e-8] {
            for method in ["bdf", "radau", "esdirk"] {
                let rec = run(method, norm, rtol);
                let gap = stretch_gap(&rec, &reference);
                println!(
                    "{method} {norm} rtol {rtol:e}: {} steps, {} rejected, stretch {:.2}·rtol",
                    rec.stats.steps,
                    rec.stats.extra["rejected_steps"],
                    gap / rtol
                );
                if method != "esdirk" {
                    assert!(gap <= 10.0 * rtol, "{method} {norm} {rtol}: {gap:e}");
                }
            }
        }
    }
}

#[test]
fn radau_takes_a_few_steps_without_a_newton_failure() {
    for norm in ["max", "rms"] {
        for (rtol, newton) in [(1e-6, 6), (1e-8, 8)] {
            let s = run("radau", norm, rtol).stats;
            let c = |k: &str| s.extra[k];
            assert_eq!(
                (
                    s.steps as u64,
                    c("rejected_steps"),
                    c("newton_failures"),
                    c("newton_iterations")
                ),
                (5, 0, 0, newton),
                "{norm} {rtol}"
            );
        }
    }
}
