//! External pressure `p_e(X)` on the upper faces of the sheet's cells (docs/external_pressure.md,
//! "The sheet"): `σ₃₃ = −p_e`, so `p = λ₃W₃ + p_e` and both in-plane stresses drop by `p_e`.
//!
//! * free top, uniform `p_e`: the steady state is uniform with `λ₁ = 1 − k₁` and `σ₂₂ = 0`,
//!   i.e. `μ(λ₂² − λ₃²) = p_e` for the neo-Hookean cell — the cells spread under the load;
//! * periodic side: nothing moves that would not move without the load, and `p` shifts by `p_e`;
//! * a Gaussian `p_e(X)` with a free top drives the sheet to the exact discrete steady state
//!   (each column solves `σ₂₂ = 0` and every row carries one `σ₁₁`; found by bisection here);
//! * a non-finite pressure is refused naming the key.

use crate::common::sheet_solver;
use celltissue::cell::Field;
use celltissue::observe::{ModelKind, Profile, RunRecord};
use celltissue::runner::OutputTimes;
use celltissue::sheet::{run_sheet, SheetConfig, TopBoundary};
use celltissue::NeoHookean;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

/// Discrete run with profiles at `times`.
fn run(cfg: &SheetConfig, times: &[f64]) -> RunRecord {
    let out = OutputTimes {
        series: times.to_vec(),
        profiles: times.to_vec(),
    };
    let rec = run_sheet(
        cfg,
        &nh(),
        ModelKind::Discrete,
        None,
        &sheet_solver(1e-10, 1e-12),
        &out,
    )
    .unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

fn column<'a>(p: &'a Profile, key: &str) -> &'a [f64] {
    &p.extra[key]
}

/// `λ₂` with `σ₂₂ = μ(λ₂² − λ₁⁻²λ₂⁻²) − p_e = 0` (μ = 1).
fn lateral(l1: f64, pe: f64) -> f64 {
    ((pe + (pe * pe + 4.0 / (l1 * l1)).sqrt()) / 2.0).sqrt()
}

fn sheet(cells_x: usize, cells_y: usize, top: TopBoundary, pe: Field) -> SheetConfig {
    SheetConfig {
        cells_x,
        cells_y,
        top,
        external_pressure: pe,
        ..Default::default()
    }
}

#[test]
fn free_top_under_uniform_pressure_relaxes_to_the_exact_spread_state() {
    let pe = 0.5;
    let rec = run(
        &sheet(6, 4, TopBoundary::Free, Field::Constant(pe)),
        &[400.0],
    );
    let p = &rec.profiles[0];
    let (l1, l2) = (0.9, lateral(0.9, pe));
    let l3 = 1.0 / (l1 * l2);
    let mut worst = 0.0f64;
    for i in 0..p.stretch.len() {
        worst = worst
            .max((p.stretch[i] - l1).abs())
            .max((column(p, "stretch_y")[i] - l2).abs())
            .max((p.pressure[i] - (l3 * l3 + pe)).abs())
            .max(column(p, "sigma22")[i].abs());
    }
    println!("p_e = {pe}: λ₂ = {l2:.7} (exact), worst deviation {worst:.2e}");
    // the load spreads the cells beyond the unloaded λ₂ = (1 − k₁)^(−½) = 1.0541
    assert!(l2 > (1.0 / 0.9f64).sqrt() + 0.1, "{l2}");
    assert!(worst < 1e-7, "{worst}");
}

#[test]
fn periodic_sheet_keeps_its_motion_and_shifts_the_pressure() {
    let pe = 0.7;
    let times = [0.5, 2.0, 10.0];
    let plain = run(
        &sheet(5, 4, TopBoundary::Periodic, Field::Constant(0.0)),
        &times,
    );
    let loaded = run(
        &sheet(5, 4, TopBoundary::Periodic, Field::Constant(pe)),
        &times,
    );
    let (mut dx, mut dp) = (0.0f64, 0.0f64);
    for (a, b) in plain.profiles.iter().zip(&loaded.profiles) {
        for i in 0..a.stretch.len() {
            dx = dx
                .max((a.x[i] - b.x[i]).abs())
                .max((column(a, "y")[i] - column(b, "y")[i]).abs());
            dp = dp.max((b.pressure[i] - a.pressure[i] - pe).abs());
        }
    }
    println!("periodic, p_e = {pe}: positions differ by {dx:.2e}, pressure shift off by {dp:.2e}");
    assert!(dx < 1e-8, "{dx}");
    assert!(dp < 1e-8, "{dp}");
}

/// Exact discrete steady state under `p_e(X_j)` with a free top: per column, `λ₂ = lateral(λ₁,
/// p_j)` and `σ₁₁ = λ₁² − λ₃² − p_j = c`; `c` makes the columns fill the held length.
fn field_steady(pes: &[f64], length: f64) -> Vec<f64> {
    let s11 = |l1: f64, p: f64| {
        let l2 = lateral(l1, p);
        l1 * l1 - 1.0 / (l1 * l1 * l2 * l2) - p
    };
    // σ₁₁ increases with λ₁ along σ₂₂ = 0: invert by bisection
    let stretch = |c: f64, p: f64| {
        let (mut lo, mut hi) = (0.2, 5.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if s11(mid, p) < c {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let total = |c: f64| pes.iter().map(|&p| stretch(c, p)).sum::<f64>();
    let (mut lo, mut hi) = (-5.0, 5.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if total(mid) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let c = 0.5 * (lo + hi);
    pes.iter().map(|&p| stretch(c, p)).collect()
}

#[test]
fn pressure_field_drives_the_sheet_to_its_exact_discrete_steady_state() {
    let field = Field::gaussian_bump(0.0, 0.8, 0.5, 0.15);
    let (nx, ny) = (8, 3);
    let pes: Vec<f64> = (0..nx)
        .map(|j| field.eval(j as f64 + 0.5, nx as f64))
        .collect();
    let exact = field_steady(&pes, nx as f64 * 0.9);
    let rec = run(&sheet(nx, ny, TopBoundary::Free, field), &[1.0, 600.0]);
    let (early, last) = (&rec.profiles[0], &rec.profiles[1]);
    let mut worst = 0.0f64;
    for i in 0..last.stretch.len() {
        let j = column(last, "column")[i] as usize - 1;
        worst = worst
            .max((last.stretch[i] - exact[j]).abs())
            .max((column(last, "stretch_y")[i] - lateral(exact[j], pes[j])).abs());
    }
    // the load is not uniform: the columns differ (the loaded middle spreads in y)
    let spread =
        exact.iter().cloned().fold(0.0, f64::max) - exact.iter().cloned().fold(9.0, f64::min);
    let early_y = column(early, "stretch_y");
    println!(
        "Gaussian p_e: exact λ₁ from {:.5} to {:.5}, worst deviation at t = 600 {worst:.2e}; \
         λ₂ at t = 1 from {:.4} to {:.4}",
        exact.iter().cloned().fold(9.0, f64::min),
        exact.iter().cloned().fold(0.0, f64::max),
        early_y.iter().cloned().fold(9.0, f64::min),
        early_y.iter().cloned().fold(0.0, f64::max),
    );
    assert!(spread > 1e-2, "{spread}");
    assert!(worst < 1e-7, "{worst}");
}

#[test]
fn a_non_finite_pressure_is_refused_naming_the_key() {
    let cfg = sheet(4, 4, TopBoundary::Free, Field::Constant(f64::INFINITY));
    let e = cfg.validate().unwrap_err();
    assert_eq!(e.key, "external_pressure");
    assert!(e.to_string().contains("finite"), "{e}");
    let cfg: SheetConfig = toml::from_str(
        "external_pressure = { type = \"gaussian\", base = 0.1, amplitude = 0.5, centre = 0.5, width = 0.1 }",
    )
    .unwrap();
    assert!(cfg.validate().is_ok());
}
