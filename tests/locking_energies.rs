//! Locking strain energies (docs/model.md §1, §8): the Gent law
//! `W = −(μJ_m/2) ln(1 − (I₁ − 3)/J_m)` is finite only for `I₁ − 3 < J_m`; on the line the cell
//! locks at `|λ − 1/λ| = √J_m` (λ ≈ 1.4142 and 0.7071 for `J_m = 0.5`).
//!
//! * a state past the lock is a named, recoverable residual error (never NaN), in the line and
//!   the sheet;
//! * the static solver inverts the locking law (the bracket never leaves the domain) and its
//!   equilibrium satisfies the equal-stress and length conditions;
//! * a dynamic run approaching the lock converges to that static state; a ramp past the lock
//!   fails with an error naming the law;
//! * the law is selectable in a scenario with checked parameters;
//! * an exponential law stretched until its derivatives overflow fails naming the non-finite
//!   iteration-matrix entry and the stretches reached, not a "zero pivot".

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::Field;
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::integrate;
use celltissue::line::static_solve::{invert_stretch, static_equilibrium};
use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::ModelKind;
use celltissue::{AnyEnergy, ArrayProblem, CellArray, Gent, StrainEnergy};
use integrators::ResidualError;

fn gent() -> Gent {
    Gent::new(1.0, 0.5).unwrap()
}

/// The line's upper lock: `λ − 1/λ = √J_m`.
fn lock(jm: f64) -> f64 {
    0.5 * (jm.sqrt() + (jm + 4.0).sqrt())
}

#[test]
fn a_cell_past_the_lock_is_a_named_recoverable_error() {
    // a free right end, so moving boundaries 2..5 together stretches cell 2 alone
    let mut p = LineParams::unit_cells(5);
    p.k = 1.0.into();
    p.right = RightEnd::Free(None);
    let line = discrete(gent(), &p).unwrap();
    let mut y = line.initial_state();
    // cell 2 = [x1, x2] stretched to 1.5 > 1.4142
    let k2 = line.layout().xi[2];
    for v in &mut y[k2..] {
        *v += 0.5;
    }
    let yp = vec![0.0; y.len()];
    let mut r = vec![0.0; y.len()];
    match line.residual(0.0, &y, &yp, &mut r) {
        Err(ResidualError::Recoverable { reason, component }) => {
            assert!(
                reason.contains("cell 2") && reason.contains("gent"),
                "{reason}"
            );
            assert!(component.is_some());
        }
        other => panic!("expected a recoverable error, got {other:?}"),
    }
    // just inside the lock: finite
    let mut y = line.initial_state();
    let d = lock(0.5) - 1.0 - 1e-6;
    for v in &mut y[k2..] {
        *v += d;
    }
    line.residual(0.0, &y, &yp, &mut r).unwrap();
    assert!(r.iter().all(|v| v.is_finite()));
    assert!(
        r.iter().any(|v| v.abs() > 1e3),
        "near the lock the stress is large"
    );
}

#[test]
fn the_static_solver_handles_the_locking_law() {
    for l in [130.0, 75.0] {
        let mut p = LineParams::unit_cells(100);
        p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.1);
        let line = discrete(gent(), &p).unwrap();
        let s = static_equilibrium(&line, l).unwrap();
        let total: f64 = s.lambda.iter().sum();
        assert!((total - l).abs() < 1e-9 * l, "l = {l}: Σλ = {total}");
        for (j, lam) in s.lambda.iter().enumerate() {
            assert!(*lam < lock(0.5) && *lam > 1.0 / lock(0.5), "λ = {lam}");
            let sig = line.cells().mu[j] * gent().line(*lam).sigma;
            assert!(
                (sig - s.stress).abs() < 1e-9 * s.stress.abs(),
                "{sig} vs {}",
                s.stress
            );
        }
        println!(
            "Gent J_m = 0.5, l = {l}: S = {:.6}, λ ∈ [{:.6}, {:.6}]",
            s.stress,
            s.min_stretch(),
            s.lambda.iter().copied().fold(0.0, f64::max)
        );
    }
    // stresses far beyond neo-Hookean's reach at these stretches stay inside the domain
    // (near the lock the stress is ill-conditioned in λ: 1e-8 relative is ≈ 10⁴ ulp of σ at 1e6)
    for target in [1e3, -1e3, 1e6, -1e6] {
        let l = invert_stretch(&gent(), 1.0, target).unwrap();
        assert!(l < lock(0.5) && l > 1.0 / lock(0.5));
        assert!((gent().line(l).sigma - target).abs() < 1e-8 * target.abs());
    }
}

#[test]
fn a_dynamic_run_near_the_lock_reaches_the_static_state() {
    let mut p = LineParams::unit_cells(20);
    p.k = 0.5.into();
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.15);
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: 20.0,
        k1: -0.35,
        t_ramp: 1.0,
    });
    let line = discrete(gent(), &p).unwrap();
    let exact = static_equilibrium(&line, 27.0).unwrap();
    let settings = SolveSettings {
        rtol: 1e-9,
        atol: 1e-11,
        ..Default::default()
    };
    let traj = integrate(&mut ArrayProblem::new(line), &settings, &[0.0, 200.0]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let last = traj.snapshots.last().unwrap();
    let err = last
        .lambda
        .iter()
        .zip(&exact.lambda)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("Gent ramp to λ̄ = 1.35: max |λ − λ_static| at t = 200: {err:.2e}");
    assert!(err < 1e-6, "{err}");
}

#[test]
fn a_ramp_past_the_lock_fails_naming_the_law() {
    let cfg: LineConfig = toml::from_str(
        r#"
        cells = 10
        K = 0.1
        k1 = -0.5
        law = { law = "gent", mu = 1.0, jm = 0.5 }
        "#,
    )
    .unwrap();
    let times = OutputTimes {
        series: vec![0.0, 5.0],
        profiles: vec![],
    };
    let rec = run_line(
        &cfg,
        ModelKind::Discrete,
        None,
        &SolveSettings::default(),
        &times,
    );
    let e = rec.error.expect("the ramp is past the lock");
    println!("{e}");
    assert!(e.contains("gent"), "{e}");
    // the series written before the failure hold no NaN
    assert!(rec.series.max_stretch.iter().all(|v| v.is_finite()));
}

#[test]
fn the_law_is_a_checked_scenario_choice() {
    let law: AnyEnergy = serde_json::from_str(r#"{"law": "gent", "mu": 2.0, "jm": 0.5}"#).unwrap();
    assert_eq!(law.name(), "gent");
    assert!((law.line(1.0).dsigma - 8.0).abs() < 1e-12);
    assert!(law.admissible([1.5, 1.0 / 1.5, 1.0]).is_err());
    let bad = serde_json::from_str::<AnyEnergy>(r#"{"law": "gent", "mu": 1.0, "jm": -1}"#);
    assert!(bad.unwrap_err().to_string().contains("jm = -1"));
}

#[test]
fn an_overflowing_exponential_law_fails_naming_the_non_finite_matrix_entry() {
    use celltissue::scenario::{execute::run_spec, load_str};
    // HGO with k₂ = 500, the end pulled out to twice the length: exp(k₂(I₄ − 1)²) leaves the
    // doubles near λ = 1.65, its derivatives first
    let text = r#"
name = "hgo"
[output]
series = [0, 0.5, 1, 5]
[model]
kind = "line"
models = ["discrete"]
cells = 20
K = 1
k1 = -1
law = { law = "hgo", c = 0.5, k1 = 1.0, k2 = 500.0, theta = 0.5 }
"#;
    let s = load_str(text, std::path::Path::new("hgo.toml"), &[]).unwrap();
    let rec = run_spec(&s.runs[0]);
    let err = rec.error.as_deref().expect("the run must fail");
    assert!(
        err.contains("non-finite iteration matrix entry inf")
            && err.contains("derivatives overflowed")
            && !err.contains("zero pivot"),
        "{err}"
    );
    assert!(err.contains("most stretched cell"), "{err}");
    // the outputs before the failure are kept, finite, the line stretched beyond 1.5
    assert_eq!(rec.series.t, [0.0, 0.5, 1.0]);
    let max = rec.series.max_stretch[2];
    assert!(max.is_finite() && max > 1.5, "{max}");
}
