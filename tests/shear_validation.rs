//! Validation of the simple-shear column (docs/model.md §4.4–4.6, §5.6): Ref top displacements and
//! spreads, the exact discrete solution, the steady state `tan θ = F_A/(β₀μ)`, the cell-centre
//! form, the continuum series solution against the continuum solver, and discrete → continuum
//! convergence.

use celltissue::array::ArrayProblem;
use celltissue::cell::ViscosityModel;
use celltissue::observe::{ModelKind, Profile, RunRecord};
use celltissue::runner::OutputTimes;
use celltissue::sheet::exact::{shear_series_viscous, ShearDiscreteExact};
use celltissue::sheet::shear::{ShearColumn, ShearParams};
use celltissue::sheet::{run_shear, ShearConfig, ShearForm};
use celltissue::{NeoHookean, Ogden, SolveSettings, StrainEnergy};
use integrators::{MethodKind, Options, Solver};

fn nh(mu: f64) -> NeoHookean {
    NeoHookean::new(mu).unwrap()
}

fn solver(rtol: f64) -> SolveSettings {
    SolveSettings {
        rtol,
        atol: rtol * 1e-2,
        ..Default::default()
    }
}

fn run(
    cfg: &ShearConfig,
    law: &impl StrainEnergy,
    model: ModelKind,
    grid: Option<usize>,
    times: &[f64],
    rtol: f64,
) -> RunRecord {
    let rec = run_shear(
        cfg,
        law,
        model,
        grid,
        &solver(rtol),
        &OutputTimes::at(times),
    )
    .unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

/// A run that records only the profiles, at `times`, with `rtol = 10⁻¹¹` (BDF), without error.
fn profiles(cfg: &ShearConfig, model: ModelKind, grid: Option<usize>, times: &[f64]) -> RunRecord {
    let outputs = OutputTimes {
        series: vec![],
        profiles: times.to_vec(),
    };
    let rec = run_shear(cfg, &nh(1.0), model, grid, &solver(1e-11), &outputs).unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

fn series<'a>(rec: &'a RunRecord, key: &str) -> &'a [f64] {
    &rec.series.extra[key]
}

/// `max_k |x_e,k − x(y_k)|` over a profile's edges at `y_k = (k + 1)·h`, against the series
/// solution `shear_series(1, d, w, y, t)` of the continuum column of width `w`.
fn series_gap(p: &Profile, h: f64, d: f64, w: f64) -> f64 {
    viscous_series_gap(p, h, d, 0.0, w)
}

/// [`series_gap`] against the Kelvin–Voigt column's series, viscous coefficient `e`.
fn viscous_series_gap(p: &Profile, h: f64, d: f64, e: f64, w: f64) -> f64 {
    p.extra["x_edge"]
        .iter()
        .enumerate()
        .map(|(k, xe)| {
            let y = (k + 1) as f64 * h;
            (xe - shear_series_viscous(1.0, d, e, w, y, p.t, 4000).0).abs()
        })
        .fold(0.0, f64::max)
}

/// Errors against the series at `w₀` fall at first order under halving of `h` (the top
/// segment's lumped drag acts like a width increase `h/2`), at second order against `w₀ + h/2`.
fn assert_first_order_then_second_at_w_eff(errs: &[(f64, f64)]) {
    for w in errs.windows(2) {
        let r = w[0].0 / w[1].0;
        assert!(r > 1.8 && r < 2.2, "convergence ratio {r} ({errs:?})");
        let r2 = w[0].1 / w[1].1;
        assert!(r2 > 3.5, "w_eff convergence ratio {r2} ({errs:?})");
    }
}

/// `|series key(t[i]) − value| < tol` for each `(i, value)` of the Ref table.
fn assert_ref(rec: &RunRecord, key: &str, t: &[f64], table: &[(usize, f64)], tol: f64) {
    let v = series(rec, key);
    for &(i, r) in table {
        assert!(
            (v[i] - r).abs() < tol,
            "{key}(t={}) = {} vs Ref {r}",
            t[i],
            v[i]
        );
    }
}

#[test]
fn edge_form_reproduces_ref_top_displacements_and_spread_m10() {
    let t = [1.0, 10.0, 50.0, 100.0, 150.0];
    let rec = run(
        &ShearConfig::default(),
        &nh(1.0),
        ModelKind::Discrete,
        None,
        &t,
        1e-10,
    );
    let top = [1.14651, 4.55847, 9.09173, 9.90271, 9.98958];
    let top: Vec<_> = top.into_iter().enumerate().collect();
    assert_ref(&rec, "top_displacement", &t, &top, 5e-6);
    let spread = [(1, 0.6783), (2, 0.1155), (3, 0.0124)];
    assert_ref(&rec, "shear_spread", &t, &spread, 5e-5);
}

#[test]
fn edge_form_reproduces_ref_top_displacements_m50() {
    let cfg = ShearConfig {
        cells: 50,
        ..Default::default()
    };
    let t = [10.0, 50.0, 100.0];
    let rec = run(&cfg, &nh(1.0), ModelKind::Discrete, None, &t, 1e-10);
    let top = [(0, 4.56206), (1, 10.79085), (2, 15.46268)];
    assert_ref(&rec, "top_displacement", &t, &top, 5e-6);
}

#[test]
fn edge_form_matches_the_exact_discrete_solution() {
    // docs/model.md §4.6: eigen-expansion with q_j = (2j+1)π/(2M+1); integrator-limited accuracy.
    // Elastic and Kelvin–Voigt cells (same modes, each slowed by 1 + 4v sin²(q_j/2)).
    for (m, beta0, gamma0, mu, drag, force, eta) in [
        (10, 1.0, 1.0, 1.0, 0.5, 1.0, 0.0),
        (7, 2.0, 0.5, 1.5, 0.3, -0.4, 0.0),
        (10, 1.0, 1.0, 1.0, 0.5, 1.0, 1.5),
        (7, 2.0, 0.5, 1.5, 0.3, -0.4, 0.2),
    ] {
        let p = ShearParams {
            cells: m,
            gamma0,
            beta0,
            drag,
            force,
            eta,
        };
        let col = ShearColumn::discrete(nh(mu), &p).unwrap();
        let y0 = col.initial_state();
        let times = [0.5, 1.0, 10.0, 50.0, 100.0];
        let mut prob = ArrayProblem::new(col);
        let opts = Options {
            rtol: 1e-12,
            atol: 1e-14,
            ..Options::default()
        };
        let sol = Solver::new(MethodKind::Bdf, opts)
            .solve(&mut prob, 0.0, &y0, &times)
            .unwrap();
        let ex = ShearDiscreteExact::new(m, gamma0, beta0, mu, drag, force).with_viscosity(eta);
        let elastic = ShearDiscreteExact::new(m, gamma0, beta0, mu, drag, force);
        let (mut worst, mut lag) = (0.0f64, 0.0f64);
        for (t, y) in sol.t.iter().zip(&sol.y) {
            for ((a, b), c) in y.iter().zip(ex.edges(*t)).zip(elastic.edges(*t)) {
                worst = worst.max((a - b).abs());
                lag = lag.max((b - c).abs());
            }
        }
        eprintln!("M = {m}, η = {eta}: max |x_e − exact| = {worst:.2e} (viscous lag {lag:.2e})");
        assert!(worst < 1e-9, "M = {m}: {worst:e}");
        assert!(
            eta == 0.0 || lag > 1e6 * worst,
            "η = {eta} changes nothing: {lag:e}"
        );
    }
}

#[test]
fn a_drag_far_below_the_stiffness_follows_the_exact_impulsive_start() {
    // A force applied at t = 0 moves the top edge at F/K: an impulsive layer of duration ~K.
    // Below K ≈ 1e-16 the drag cancelled in BDF's ∂F/∂ẏ = J(1) − J(0) and Newton ran on the
    // stiffness alone inside the layer, failing at every step size at t = 0. Inside the
    // layer (t = K/2 … 50K) and after it, the edges follow the exact eigen-expansion.
    // Radau IIA and ESDIRK form ∂F/∂ẏ as (J(γ/h) − J(0))·h/γ at their step, without BDF's
    // rescue of lost columns: checked here on the same layer, where their steps shrink from
    // the starting estimate into it. Radau IIA meets the same bound (measured 7.7e-11).
    // ESDIRK, second order under error-per-step control, errs by 1.13e-7 at this rtol at
    // every drag from 1e-3 to 1e-250 (docs/model.md §8.1, tolerance proportionality ~rtol^0.7):
    // what is asserted for it is that the error does not grow once the drag is lost to
    // rounding, against its own run at K = 1e-3, where no column is lost.
    for (method, bound) in [
        (MethodKind::Bdf, None),
        (MethodKind::Radau, None),
        (MethodKind::Esdirk, Some(1e-3)),
    ] {
        let bound = bound.map_or(1e-8, |k| 1.5 * impulsive_start_error(method, k).0);
        for drag in [1e-16, 1e-20, 1e-60, 1e-100, 1e-150, 1e-250] {
            let (worst, steps) = impulsive_start_error(method, drag);
            assert!(
                worst < bound,
                "{method:?} K = {drag:e}: {worst:e} (bound {bound:e})"
            );
            // the layer, then the climb through the decades between K and 1 (about 3.3 steps
            // each); with the BDF history's coefficients overflowing, K = 1e-80 took 2 881
            let most = 700.0 + 4.0 * (1.0 / drag).log10();
            assert!(
                method != MethodKind::Bdf || (steps as f64) < most,
                "K = {drag:e}: {steps} steps"
            );
        }
    }
}

/// Largest error of the edges against the exact eigen-expansion inside the impulsive layer of
/// drag `drag` and after it (M = 6, rtol 1e-10), and the steps taken.
fn impulsive_start_error(method: MethodKind, drag: f64) -> (f64, usize) {
    let p = ShearParams {
        cells: 6,
        drag,
        ..ShearParams::default()
    };
    let col = ShearColumn::discrete(nh(1.0), &p).unwrap();
    let y0 = col.initial_state();
    let times = [0.5 * drag, drag, 10.0 * drag, 50.0 * drag, 1.0];
    let mut prob = ArrayProblem::new(col);
    let opts = Options {
        rtol: 1e-10,
        atol: 1e-12,
        ..Options::default()
    };
    let sol = Solver::new(method, opts)
        .solve(&mut prob, 0.0, &y0, &times)
        .unwrap_or_else(|e| panic!("{method:?} K = {drag:e}: {e}"));
    let ex = ShearDiscreteExact::new(6, p.gamma0, p.beta0, 1.0, drag, p.force);
    let mut worst = 0.0f64;
    for (t, y) in sol.t.iter().zip(&sol.y) {
        for (a, b) in y.iter().zip(ex.edges(*t)) {
            worst = worst.max((a - b).abs());
        }
    }
    eprintln!(
        "{method:?} K = {drag:e}: {} steps, {} Jacobians, max |x_e − exact| = {worst:.2e}",
        sol.stats.steps, sol.stats.jacobian_evals
    );
    assert_eq!(sol.t.len(), times.len());
    (worst, sol.stats.steps)
}

#[test]
fn steady_shear_angle_is_force_over_beta0_mu() {
    // tan θ = F_A/(β₀μ) in every cell (docs/model.md §4.4)
    let cfg = ShearConfig {
        beta0: 2.0,
        force: 0.5,
        ..Default::default()
    };
    let rec = run(&cfg, &nh(0.5), ModelKind::Discrete, None, &[2000.0], 1e-10);
    let expect = 0.5 / (2.0 * 0.5);
    assert!((rec.series.max_stretch[0] - expect).abs() < 1e-8);
    assert!((rec.series.min_stretch[0] - expect).abs() < 1e-8);
    assert!((series(&rec, "top_displacement")[0] - 10.0 * expect).abs() < 1e-7);
    assert!((series(&rec, "mean_shear_angle")[0] - expect.atan()).abs() < 1e-8);
}

#[test]
fn nonlinear_law_steady_shear_solves_tau_equals_force_over_beta0() {
    // Ogden (α = 3, 1.5): τ(T) is nonlinear; the steady state has τ(T) = F_A/β₀ in every cell.
    let law = Ogden::new(vec![(0.4, 3.0), (0.4, 1.5)]).unwrap();
    let cfg = ShearConfig {
        force: 1.5,
        ..Default::default()
    };
    let rec = run(&cfg, &law, ModelKind::Discrete, None, &[4000.0], 1e-10);
    let t = rec.series.max_stretch[0];
    assert!((rec.series.min_stretch[0] - t).abs() < 1e-8);
    assert!(
        (law.shear(t).tau - 1.5).abs() < 1e-8,
        "τ({t}) = {}",
        law.shear(t).tau
    );
    assert!(
        (t - 1.5 / law.shear_modulus()).abs() > 1e-2,
        "law is effectively linear here"
    );
}

#[test]
fn cell_centre_form_gives_identical_trajectories_to_edge_form() {
    // docs/model.md §4.5: the thesis form with K_th = 1 is exactly the edge form with K = ½,
    // with elastic and with Kelvin–Voigt cells.
    for (m, viscosity) in [(10, None), (50, None), (10, kelvin_voigt(0.8))] {
        let times = [0.5, 1.0, 10.0, 50.0, 100.0];
        let mk = |form| ShearConfig {
            cells: m,
            form,
            viscosity,
            ..Default::default()
        };
        let edge = profiles(&mk(ShearForm::Edge), ModelKind::Discrete, None, &times);
        let cc = profiles(
            &mk(ShearForm::CellCentre),
            ModelKind::Discrete,
            None,
            &times,
        );
        let mut worst = 0.0f64;
        for (a, b) in edge.profiles.iter().zip(&cc.profiles) {
            for (u, v) in a.extra["x_edge"].iter().zip(&b.extra["x_edge"]) {
                worst = worst.max((u - v).abs());
            }
        }
        eprintln!("M = {m}: max |x_e(edge) − x_e(cell-centre)| = {worst:.2e}");
        assert!(worst < 1e-8, "M = {m}: {worst:e}");
    }
}

fn kelvin_voigt(eta: f64) -> Option<ViscosityModel> {
    Some(ViscosityModel::KelvinVoigt { eta })
}

#[test]
fn viscous_continuum_converges_to_the_viscous_series_solution() {
    // K x_t = β₀γ₀(μ x_yy + (η/2) x_yyt): the same modes, mode j slowed by 1 + E k_j²,
    // E = β₀γ₀η/(2K) = 2 for η = 2, K = ½ (w₀ = 10, D = 2). First order in h, as elastic.
    let cfg = ShearConfig {
        viscosity: kelvin_voigt(2.0),
        ..Default::default()
    };
    let (d, e, w0) = (2.0, 2.0, 10.0);
    let times = [1.0, 10.0, 50.0];
    let mut errs = Vec::new();
    for m in [20, 40, 80, 160] {
        let rec = profiles(&cfg, ModelKind::Continuum, Some(m), &times);
        let h = w0 / m as f64;
        let worst = |e: f64, w: f64| {
            rec.profiles
                .iter()
                .map(|p| viscous_series_gap(p, h, d, e, w))
                .fold(0.0, f64::max)
        };
        let (worst_w0, worst_eff) = (worst(e, w0), worst(e, w0 + 0.5 * h));
        // the elastic series is far off: the viscosity is felt
        let elastic = worst(0.0, w0 + 0.5 * h);
        assert!(
            elastic > 100.0 * worst_eff,
            "m = {m}: {elastic} vs {worst_eff}"
        );
        errs.push((worst_w0, worst_eff));
    }
    eprintln!("viscous continuum vs series (w0, w0 + h/2), m = 20, 40, 80, 160: {errs:?}");
    assert_first_order_then_second_at_w_eff(&errs);
}

#[test]
fn viscosity_key_is_kelvin_voigt_only_and_checked() {
    let cfg: ShearConfig =
        toml::from_str("viscosity = { model = \"kelvin_voigt\", eta = 0.4 }").unwrap();
    assert!(cfg.validate().is_ok());
    assert_eq!(cfg.params().eta, 0.4);
    let bad = ShearConfig {
        viscosity: kelvin_voigt(-1.0),
        ..Default::default()
    };
    let e = bad.validate().unwrap_err();
    assert_eq!(e.key, "viscosity.eta");
    let maxwell: ShearConfig =
        toml::from_str("viscosity = { model = \"maxwell\", mu_m = 1.0, eta_m = 1.0 }").unwrap();
    let e = maxwell.validate().unwrap_err();
    assert_eq!(e.key, "viscosity.model");
    assert!(e.to_string().contains("kelvin_voigt"), "{e}");
}

#[test]
fn continuum_solver_converges_to_the_series_solution() {
    // K x_t = β₀γ₀μ x_yy on (0, w₀ = 10), β₀μ x_y(w₀) = F_A: conservative scheme on m segments
    // against the closed-form series (docs/model.md §4.6); error falls as m grows (first order: the
    // top segment's lumped drag K h/γ₀ acts like a width increase h/2).
    let cfg = ShearConfig::default();
    let (d, w0) = (2.0, 10.0);
    let times = [1.0, 10.0, 50.0];
    let mut errs = Vec::new();
    for m in [20, 40, 80, 160] {
        let rec = profiles(&cfg, ModelKind::Continuum, Some(m), &times);
        let h = w0 / m as f64;
        let (mut worst, mut worst_eff) = (0.0f64, 0.0f64);
        for p in &rec.profiles {
            worst = worst.max(series_gap(p, h, d, w0));
            worst_eff = worst_eff.max(series_gap(p, h, d, w0 + 0.5 * h));
        }
        errs.push((worst, worst_eff));
    }
    eprintln!("continuum vs series (w0, w0 + h/2), m = 20, 40, 80, 160: {errs:?}");
    assert_first_order_then_second_at_w_eff(&errs);
}

#[test]
fn discrete_column_matches_series_with_effective_width() {
    // docs/model.md §4.6: with w_eff = (M + ½)γ₀ the series matches the discrete model to ≤ 1.2e-2 at
    // t = 1 and ≤ 3e-3 for t ≥ 10 (M = 10).
    let times = [1.0, 10.0, 50.0, 100.0];
    let rec = profiles(&ShearConfig::default(), ModelKind::Discrete, None, &times);
    for p in &rec.profiles {
        let worst = series_gap(p, 1.0, 2.0, 10.5);
        eprintln!("t = {}: max |x_e − series(w_eff)| = {worst:.2e}", p.t);
        if p.t < 5.0 {
            // docs/model.md quotes the t = 1 value to two digits (measured 1.2047e-2)
            assert!((worst - 1.2e-2).abs() < 0.05e-2, "t = {}: {worst}", p.t);
        } else {
            assert!(worst <= 3e-3, "t = {}: {worst}", p.t);
        }
    }
}

#[test]
fn discrete_converges_to_continuum_as_cells_shrink() {
    // Fixed macroscale: w₀ = 1 (γ₀ = 1/M), edge drag K = K̂γ₀ with K̂ = ½ so D = β₀μ/K̂ = 2,
    // F_A = 1. The discrete column of M cells approaches the continuum series; the error is
    // O(1/M) (lumped top drag: w_eff = w₀ + γ₀/2).
    let times = [0.02, 0.1, 0.5];
    let mut errs = Vec::new();
    for m in [10, 20, 40, 80] {
        let g = 1.0 / m as f64;
        let cfg = ShearConfig {
            cells: m,
            gamma0: g,
            drag: Some(0.5 * g),
            ..Default::default()
        };
        let rec = profiles(&cfg, ModelKind::Discrete, None, &times);
        let worst = rec
            .profiles
            .iter()
            .map(|p| series_gap(p, g, 2.0, 1.0))
            .fold(0.0, f64::max);
        errs.push(worst);
    }
    eprintln!("discrete vs continuum series, M = 10, 20, 40, 80: {errs:?}");
    for w in errs.windows(2) {
        let r = w[0] / w[1];
        assert!(r > 1.7 && r < 2.3, "convergence ratio {r} ({errs:?})");
    }
}

#[test]
fn cell_centre_form_is_discrete_only() {
    let cfg = ShearConfig {
        form: ShearForm::CellCentre,
        ..Default::default()
    };
    let err = run_shear(
        &cfg,
        &nh(1.0),
        ModelKind::Continuum,
        None,
        &solver(1e-8),
        &OutputTimes::at(&[1.0]),
    )
    .unwrap_err();
    assert!(err.to_string().contains("form"), "{err}");
}
