//! The accuracy contract in cell units (docs/model.md §8.1): the local-error
//! and Newton tests measure stretches, so
//!
//! * shifting the whole problem by 10⁶ cell lengths changes the steps and the stretches only
//!   through the rounding of positions near 10⁶ (translation invariance of the weights and
//!   tested quantities is exact; see the test for the measured effect of rounding);
//! * at rtol 1e-6 the largest stretch error against a tight reference (rtol 1e-10, or 1e-8 and 1e-9 where positions reach 10⁶ and 10⁴ cell lengths) is at most
//!   10·rtol on the macroscale family (`l₀ = N`, `K = 1/N`, ramp time `N`) and on the raw
//!   Chapter 2 problem (`K = 1`, unit-time exponential ramp), at N = 10² and 10⁴. The
//!   macroscale at 10⁶ is `#[ignore]`d (`cargo test --release --test integration accuracy_contract:: --
//!   --ignored`; its reference runs at rtol 1e-8, see the test for why). The raw problem at
//!   N = 10⁴ is checked through its first crushed cells (t ≤ 0.01) in CI and to t = 10 under
//!   `--ignored`, against a reference at rtol 1e-9 (see `RAW_10K_REFERENCE_RTOL` for why not
//!   1e-10);
//! * fig2_7 (K = 0, polynomial ramp, exact solution uniform λ) stays uniform to 1e-5 for every
//!   η ∈ {1e-5, 1e-2, 1, 10};
//! * the same contract on a 50 × 50 free-top sheet;
//! * a viscous line's pressure, which reads the strain rate, and a growing line's ġ output,
//!   within it as well.

use celltissue::boundary::RampKind;
use celltissue::line::build::discrete;
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::line::LineConfig;
use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
use celltissue::{ArrayProblem, NeoHookean};
use integrators::{
    ErrorMap, JacobianSink, MethodKind, Options, Problem, ResidualError, Row, Solver,
};

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).expect("valid")
}

fn settings(rtol: f64) -> SolveSettings {
    SolveSettings {
        rtol,
        atol: 1e-2 * rtol,
        ..Default::default()
    }
}

/// Stretches of every cell at each output time, and the steps taken.
fn line_stretches(cfg: &LineConfig, s: &SolveSettings, t_out: &[f64]) -> (Vec<Vec<f64>>, usize) {
    let p = cfg.params(s.atol);
    let mut prob = ArrayProblem::new(discrete(nh(), &p).expect("valid line"));
    let traj = integrate(&mut prob, s, t_out);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    assert_eq!(traj.snapshots.len(), t_out.len());
    let lam = traj.snapshots.iter().map(|sn| sn.lambda.clone()).collect();
    (lam, traj.stats.steps)
}

/// Largest |λ − λ_ref| over cells and output times.
fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
        .fold(0.0, f64::max)
}

fn macroscale(n: usize) -> LineConfig {
    let nf = n as f64;
    LineConfig {
        cells: n,
        k: (1.0 / nf).into(),
        t_ramp: nf,
        ..Default::default()
    }
}

fn raw(n: usize) -> LineConfig {
    LineConfig {
        cells: n,
        k: 1.0.into(),
        ..Default::default()
    }
}

/// Stretch error at rtol 1e-6 against rtol 1e-10, printed, and checked ≤ 10·rtol.
fn contract(name: &str, cfg: &LineConfig, t_out: &[f64]) {
    contract_against(name, cfg, t_out, 1e-10)
}

/// Stretch error at rtol 1e-6 against a reference at `rtol_ref`, printed, and checked
/// ≤ 10·rtol.
fn contract_against(name: &str, cfg: &LineConfig, t_out: &[f64], rtol_ref: f64) {
    let (loose, steps) = line_stretches(cfg, &settings(1e-6), t_out);
    let (tight, steps_ref) = line_stretches(cfg, &settings(rtol_ref), t_out);
    let err = max_diff(&loose, &tight);
    println!(
        "{name} N = {}: max stretch error {err:.2e} at rtol 1e-6 ({steps} steps; reference at \
         rtol {rtol_ref:e}: {steps_ref} steps)",
        cfg.cells
    );
    assert!(
        err <= 1e-5,
        "{name} N = {}: stretch error {err:e}",
        cfg.cells
    );
}

#[test]
fn macroscale_stretch_error_is_a_few_rtol_at_100_and_10000_cells() {
    for n in [100usize, 10_000] {
        let nf = n as f64;
        contract("macroscale", &macroscale(n), &[0.25 * nf, 0.5 * nf, nf]);
    }
}

/// `solver.newton_alpha_bound` on the macroscale line. The BDF step reuses its Newton matrix
/// while α moves by up to 25 % and scales the correction; on this line the cell-scale error
/// that leaves after one iteration passes IDA's test, and the stretch norm then reads it as
/// local error (BENCHMARKS.md, "What sets the macroscale line's step count"). With the bound,
/// the first iteration's test assumes the rate the change of α implies. Against the rtol 1e-10
/// (N = 10⁴) and 1e-8 (N = 10⁵) references, both runs hold the contract, and the bounded one
/// takes fewer steps: 131 against 167 at N = 10⁴ (and 194 Newton iterations against 221), 137
/// against 205 at N = 10⁵ (209 Newton iterations against 266). These step counts scatter by
/// ±20 % under small changes of the error test: a scratch build scaling the size of the end
/// cell's term alone by 0.95, 0.9, 0.85 or 0.8 gave 250, 212, 203 and 195 unbounded steps at N = 10⁵
/// (173 at 1, which was pinned before that cell was held to its own stretch). The counters
/// of both are pinned: (steps, Newton iterations, factorisations).
#[test]
fn the_newton_alpha_bound_saves_steps_on_the_macroscale_line_within_the_contract() {
    let run = |cfg: &LineConfig, s: &SolveSettings, t_out: &[f64]| {
        let p = cfg.params(s.atol);
        let mut prob = ArrayProblem::new(discrete(nh(), &p).expect("valid line"));
        let traj = integrate(&mut prob, s, t_out);
        assert!(traj.error.is_none(), "{:?}", traj.error);
        let lam: Vec<Vec<f64>> = traj.snapshots.iter().map(|sn| sn.lambda.clone()).collect();
        let st = traj.stats;
        (lam, (st.steps, st.newton_iterations, st.factorizations))
    };
    let pinned = [
        (10_000usize, 1e-10, (167, 221, 47), (131, 194, 40)),
        (100_000, 1e-8, (205, 266, 53), (137, 209, 46)),
    ];
    for (n, rtol_ref, ida, bounded) in pinned {
        let nf = n as f64;
        let cfg = macroscale(n);
        let t_out = [0.25 * nf, 0.5 * nf, nf];
        let (tight, _) = run(&cfg, &settings(rtol_ref), &t_out);
        let (plain, c_plain) = run(&cfg, &settings(1e-6), &t_out);
        let bound = SolveSettings {
            newton_alpha_bound: true,
            ..settings(1e-6)
        };
        let (with_bound, c_bound) = run(&cfg, &bound, &t_out);
        let (e_plain, e_bound) = (max_diff(&plain, &tight), max_diff(&with_bound, &tight));
        println!(
            "N = {n}: IDA's test {c_plain:?}, error {e_plain:.2e}; with the bound {c_bound:?}, \
             error {e_bound:.2e}"
        );
        assert!(
            e_plain <= 1e-5 && e_bound <= 1e-5,
            "N = {n}: {e_plain:e}, {e_bound:e}"
        );
        assert!(c_bound.0 < c_plain.0, "N = {n}");
        assert_eq!(
            (c_plain, c_bound),
            (ida, bounded),
            "N = {n}: counters moved"
        );
    }
}

/// At N = 10⁶ positions reach 10⁶ cell lengths, where rounding alone is ε·10⁶ ≈ 2e-10 of a
/// cell: a reference at rtol 1e-10 would ask for its own noise (the BDF order then collapses,
/// as on the raw problem below, and the run took more than 14 minutes), so the reference runs at
/// rtol 1e-8 (779 steps). Measured with `line_headline macro 1000000 2` (BENCHMARKS.md):
/// 8.7e-8 at rtol 1e-6 (316 steps).
#[test]
#[ignore = "N = 10⁶: about 35 s of solving and 0.75 GB"]
fn macroscale_stretch_error_is_a_few_rtol_at_a_million_cells() {
    let n = 1_000_000usize;
    contract_against("macroscale", &macroscale(n), &[n as f64], 1e-8);
}

#[test]
fn raw_chapter_2_stretch_error_is_a_few_rtol_at_100_cells() {
    contract("raw Ch. 2", &raw(100), &[0.5, 1.0, 2.0, 10.0]);
}

/// The raw problem at N = 10⁴ drives its end 0.1·N = 1000 cell lengths per unit time into a
/// line that relaxes diffusively (μ/K = 1 cell² per unit time), so cells are crushed one after
/// another to λ ≈ 0.08 → 0.01 (a compression front). Its reference runs at rtol 1e-9, not 1e-10:
/// positions reach 10⁴ cell lengths, so rounding puts noise of ε·10⁴/λ ≈ 5e-11 into a crushed
/// cell's stretch, which is what rtol 1e-10 asks for; the BDF order selection then sees the
/// noise in its higher differences and drops from 5 to 2–3 (measured over t ≤ 0.004: 906 steps
/// at rtol 1e-9, 10 886 at 1e-10; over t ≤ 0.01 the 1e-10 run takes 797 793 steps). At rtol
/// 1e-9 the reference's own error is ~1e-9 (the 1e-8 run differs from it by 5.9e-8 over
/// t ≤ 0.01). Measured to t = 10: 2.99e-6 at rtol 1e-6.
const RAW_10K_REFERENCE_RTOL: f64 = 1e-9;

#[test]
fn raw_chapter_2_stretch_error_is_a_few_rtol_at_10000_cells_through_the_first_crushes() {
    // the first ten cells crushed, in ≈ 3 700 steps for both runs
    contract_against(
        "raw Ch. 2",
        &raw(10_000),
        &[0.002, 0.005, 0.01],
        RAW_10K_REFERENCE_RTOL,
    );
}

#[test]
#[ignore = "N = 10⁴ to t = 10: 3.5 min (67 220 steps at rtol 1e-6, 495 769 for the reference)"]
fn raw_chapter_2_stretch_error_is_a_few_rtol_at_10000_cells() {
    contract_against(
        "raw Ch. 2",
        &raw(10_000),
        &[0.5, 1.0, 2.0, 10.0],
        RAW_10K_REFERENCE_RTOL,
    );
}

#[test]
fn fig2_7_stays_uniform_for_every_eta() {
    // K = 0: the exact solution is a uniform stretch λ(t) = 1 − k₁·s(t), for every η
    for eta in [1e-5, 1e-2, 1.0, 10.0] {
        let cfg = LineConfig {
            k: 0.0.into(),
            eta: eta.into(),
            ramp: RampKind::Polynomial,
            ..Default::default()
        };
        let t_out: Vec<f64> = (1..=20).map(|k| 0.05 * k as f64).collect();
        let (lam, steps) = line_stretches(&cfg, &settings(1e-6), &t_out);
        let mut spread: f64 = 0.0;
        let mut exact_err: f64 = 0.0;
        for (l, &t) in lam.iter().zip(&t_out) {
            let (lo, hi) = l
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            spread = spread.max(hi - lo);
            let s = 3.0 * t * t - 2.0 * t.powi(3);
            let exact = 1.0 - 0.1 * s;
            exact_err = exact_err.max((hi - exact).abs().max((lo - exact).abs()));
        }
        println!(
            "fig2_7 η = {eta}: spread {spread:.2e}, error vs exact {exact_err:.2e}, {steps} steps"
        );
        assert!(spread <= 1e-5, "η = {eta}: spread {spread:e}");
        assert!(exact_err <= 1e-5, "η = {eta}: error {exact_err:e}");
    }
}

/// Any problem with every position row moved by `shift` (the unknowns a row of its error map
/// marks as a difference or an anchor): the residual and Jacobian are the inner problem's at
/// the unshifted state, so the solution is the inner one plus `shift`.
struct Shifted<P: Problem> {
    inner: P,
    shift: f64,
    is_position: Vec<bool>,
    buf: Vec<f64>,
    /// Hide the inner problem's error map, so that the integrator weighs every unknown by
    /// `rtol·|y|` (the position-relative test the cell-unit contract replaced).
    position_relative: bool,
}

impl<P: Problem> Shifted<P> {
    fn new(inner: P, shift: f64) -> Self {
        let map = inner.error_map().expect("a cell problem has an error map");
        let is_position = (0..inner.dim())
            .map(|i| !matches!(map.row(i), Row::Own))
            .collect();
        Self {
            inner,
            shift,
            is_position,
            buf: Vec::new(),
            position_relative: false,
        }
    }

    fn unshift(&mut self, y: &[f64]) {
        self.buf.clear();
        self.buf.extend(
            y.iter()
                .zip(&self.is_position)
                .map(|(&v, &p)| if p { v - self.shift } else { v }),
        );
    }
}

impl<P: Problem> Problem for Shifted<P> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        self.unshift(y);
        let y0 = std::mem::take(&mut self.buf);
        let out = self.inner.residual(t, &y0, yp, r);
        self.buf = y0;
        out
    }
    fn directional(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        v: &[f64],
        c: f64,
        r: &mut [f64],
        dr: &mut [f64],
    ) -> Result<bool, ResidualError> {
        self.unshift(y);
        let y0 = std::mem::take(&mut self.buf);
        let out = self.inner.directional(t, &y0, yp, v, c, r, dr);
        self.buf = y0;
        out
    }
    fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        self.unshift(y);
        let y0 = std::mem::take(&mut self.buf);
        let out = self.inner.jacobian(t, &y0, yp, c, jac);
        self.buf = y0;
        out
    }
    fn pattern(&self) -> integrators::Pattern {
        self.inner.pattern()
    }
    fn atol(&self) -> Option<Vec<f64>> {
        self.inner.atol()
    }
    fn error_map(&self) -> Option<ErrorMap> {
        if self.position_relative {
            return None;
        }
        // the wall and the prescribed end move with the positions
        self.inner.error_map().map(|m| m.translated(self.shift))
    }
    fn algebraic(&self) -> Vec<bool> {
        self.inner.algebraic()
    }
}

/// Steps and the solution (unshifted) at `t_out` of a problem solved with every position moved
/// by `shift`, under the cell-unit contract or (`position_relative`) the old position-relative
/// test.
fn solve_shifted<P: Problem>(
    inner: P,
    y0: &[f64],
    shift: f64,
    method: MethodKind,
    t_out: &[f64],
    position_relative: bool,
) -> (usize, Vec<Vec<f64>>) {
    let mut prob = Shifted::new(inner, shift);
    prob.position_relative = position_relative;
    let y: Vec<f64> = y0
        .iter()
        .zip(&prob.is_position)
        .map(|(&v, &p)| if p { v + shift } else { v })
        .collect();
    let opts = Options {
        rtol: 1e-6,
        atol: 1e-8,
        norm: integrators::ErrorNorm::Max,
        ..Default::default()
    };
    let sol = Solver::new(method, opts)
        .solve(&mut prob, 0.0, &y, t_out)
        .unwrap_or_else(|f| panic!("shift {shift}: {}", f.error));
    let back = sol
        .y
        .iter()
        .map(|v| {
            v.iter()
                .zip(&prob.is_position)
                .map(|(&x, &p)| if p { x - shift } else { x })
                .collect()
        })
        .collect();
    (sol.stats.steps, back)
}

#[test]
fn shifting_a_line_by_a_million_cells_changes_neither_steps_nor_stretches() {
    // macroscale N = 100 inside its ramp (no breakpoint), every method
    let cfg = macroscale(100);
    let p = cfg.params(1e-8);
    let line = || ArrayProblem::new(discrete(nh(), &p).expect("valid line"));
    let y0 = discrete(nh(), &p).expect("valid line").initial_state();
    let t_out = [25.0, 50.0, 100.0];
    // stretches from positions: unit reference cells, position rows first-to-last
    let stretch = |y: &Vec<f64>| -> Vec<f64> { y.windows(2).map(|w| w[1] - w[0]).collect() };
    let worst = |a: &[Vec<f64>], b: &[Vec<f64>]| {
        a.iter()
            .zip(b)
            .flat_map(|(a, b)| {
                stretch(a)
                    .into_iter()
                    .zip(stretch(b))
                    .map(|(x, z)| (x - z).abs())
                    .collect::<Vec<_>>()
            })
            .fold(0.0, f64::max)
    };
    for method in [MethodKind::Bdf, MethodKind::Esdirk, MethodKind::Radau] {
        let (s0, y_a) = solve_shifted(line(), &y0, 0.0, method, &t_out, false);
        for shift in [1e4, 1e6, 1e7] {
            let (s1, y_b) = solve_shifted(line(), &y0, shift, method, &t_out, false);
            let change = worst(&y_a, &y_b);
            println!(
                "{method:?}, shift {shift:e}: steps {s0} vs {s1}; stretch change {change:.1e}"
            );
            // Near a shift of 10⁶ a position is known to ulp(10⁶) ≈ 1.2e-10 only, which is above
            // the Newton early-exit threshold (10⁻⁴·0.33·rtol ≈ 3e-11 of a stretch), so
            // rounding flips some of the integrator's decisions. The one-step methods' step
            // sequences do not notice (64 ESDIRK and 33 Radau steps at every shift from 0 to
            // 10⁷). BDF's does: its order and step choices amplify a change in the last bits,
            // and rounding alone moves its count by several per cent. Measured: 111 steps
            // unshifted; 97–117 at shifts from 10² to 10⁷; 105–106 unshifted with every initial
            // value changed by at most 5e-16 relative (eight patterns). So BDF is held to a
            // fifth of its count, the one-step methods to two steps.
            // The stretches: BDF lands on another solution within the tolerance; the one-step
            // methods' differ by rounding, a few ulps of the shifted positions (measured: at
            // most 4).
            let (allowed_steps, allowed_change) = match method {
                MethodKind::Bdf => (s0 / 5, 1e-6),
                _ => (2, 16.0 * f64::EPSILON * shift),
            };
            assert!(
                s0.abs_diff(s1) <= allowed_steps,
                "{method:?}, shift {shift:e}: steps {s0} vs {s1}"
            );
            assert!(
                change <= allowed_change,
                "{method:?}, shift {shift:e}: stretches changed by {change:e}"
            );
        }
    }
    // The band above can fail: the position-relative test this contract replaced weighs a
    // position by rtol·|x|, a whole cell at 10⁶, and took a quarter of the steps there
    // (59 unshifted, 14 at 10⁶).
    let (p0, _) = solve_shifted(line(), &y0, 0.0, MethodKind::Bdf, &t_out, true);
    let (p1, _) = solve_shifted(line(), &y0, 1e6, MethodKind::Bdf, &t_out, true);
    println!("position-relative test: {p0} steps unshifted, {p1} at 10⁶");
    assert!(p0.abs_diff(p1) > p0 / 5, "position-relative: {p0} vs {p1}");
}

#[test]
fn sheet_50_by_50_free_top_stretch_error_is_a_few_rtol() {
    let params = SheetParams {
        cells_x: 50,
        cells_y: 50,
        ..Default::default()
    };
    let t_out = [0.5, 1.0, 2.0, 5.0];
    let run = |rtol: f64| -> (usize, Vec<Vec<f64>>) {
        let sheet = UniaxialSheet::discrete(nh(), &params).expect("valid sheet");
        let y0 = sheet.initial_state();
        let mut prob = ArrayProblem::new(sheet);
        let opts = Options {
            rtol,
            atol: 1e-2 * rtol,
            norm: integrators::ErrorNorm::Max,
            ..Default::default()
        };
        let sol = Solver::new(MethodKind::Bdf, opts)
            .solve(&mut prob, 0.0, &y0, &t_out)
            .unwrap_or_else(|f| panic!("rtol {rtol}: {}", f.error));
        // every cell's stretch in its own direction: the differences the error map declares
        let map = prob.error_map().expect("sheet error map");
        let lam = sol
            .y
            .iter()
            .map(|y| {
                (0..y.len())
                    .filter_map(|i| match map.row(i) {
                        Row::Difference { partner } => Some(y[i] - y[partner]),
                        _ => None,
                    })
                    .collect()
            })
            .collect();
        (sol.stats.steps, lam)
    };
    let (steps, loose) = run(1e-6);
    let (steps_ref, tight) = run(1e-10);
    let err = max_diff(&loose, &tight);
    // cell sizes h_X = h_Y = 1 on the discrete grid: position differences are stretches
    println!("sheet 50×50: stretch error {err:.2e} ({steps} steps; reference {steps_ref})");
    assert!(err <= 1e-5, "sheet stretch error {err:e}");
}

#[test]
fn a_viscous_lines_pressure_holds_the_contract_as_its_stretch_does() {
    // A Kelvin–Voigt cell's pressure reads its strain rate; the interpolated ẏ at an output is
    // not error-controlled, and the pressure erred by 13·rtol (rtol 1e-6) and 66·rtol (1e-8)
    // through it while the stretch erred by 6.5 and 12. The outputs' rates are now solved from
    // their state (`Problem::outputs_read_rates`): 2.5 and 6, below the stretch's.
    use crate::common::profile_gap;
    use celltissue::scenario::{execute::run_spec, load_str};
    let run = |rtol: f64| {
        let text = format!(
            "name = \"v\"\n[solver]\nrtol = {rtol:e}\natol = {:e}\n[output]\nseries = [0]\n\
             profiles = [0.5, 1, 3]\n[model]\nkind = \"line\"\nmodels = [\"discrete\", \"continuum\"]\n\
             nodes = 50\ncells = 50\nK = 1\nt_ramp = 1\neta = 0.5\n",
            rtol * 1e-2
        );
        let s = load_str(&text, std::path::Path::new("v.toml"), &[]).unwrap();
        s.runs
            .iter()
            .map(|spec| {
                let rec = run_spec(spec);
                assert!(rec.error.is_none(), "rtol {rtol:e}: {:?}", rec.error);
                rec
            })
            .collect::<Vec<_>>()
    };
    let reference = run(1e-11);
    for rtol in [1e-6, 1e-8] {
        for (rec, r) in run(rtol).iter().zip(&reference) {
            let stretch = profile_gap(rec, r, |p| &p.stretch);
            let pressure = profile_gap(rec, r, |p| &p.pressure);
            eprintln!(
                "rtol {rtol:e} {:?}: stretch {stretch:.2e}, pressure {pressure:.2e}",
                rec.model
            );
            // (the stretch's own 12·rtol at 1e-8 is this run's global error; the stretch's
            // contract is tested above)
            assert!(
                pressure < 10.0 * rtol,
                "rtol {rtol:e}: pressure {pressure:e}"
            );
            assert!(
                pressure <= stretch,
                "rtol {rtol:e}: pressure {pressure:e} against stretch {stretch:e}"
            );
        }
    }
}

#[test]
fn a_dividing_lines_growth_rate_output_holds_the_contract() {
    // The `g_dot` profile field used to be the interpolated ẏ of the growth rows: at rtol 1e-8
    // it erred by 22·rtol of its largest value while the stretch held 1. It is now the
    // growth row itself, G(σ) at the output's state: 4.3.
    use celltissue::scenario::{execute::run_spec, load_str};
    let run = |rtol: f64| {
        let text = format!(
            "name = \"g\"\n[solver]\nrtol = {rtol:e}\natol = {:e}\n[output]\nseries = [0]\n\
             profiles = [0.5, 1, 3]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\n\
             cells = 50\nK = 1e-2\nright_end = \"free\"\ngrowth = {{ sigma0 = 0.1 }}\n\
             division = {{ rule = \"area\", ratio = 2 }}\n",
            rtol * 1e-2
        );
        let s = load_str(&text, std::path::Path::new("g.toml"), &[]).unwrap();
        let rec = run_spec(&s.runs[0]);
        assert!(rec.error.is_none(), "rtol {rtol:e}: {:?}", rec.error);
        rec
    };
    let (reference, rtol) = (run(1e-11), 1e-8);
    let rec = run(rtol);
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for (p, q) in rec.profiles.iter().zip(&reference.profiles) {
        let (a, b) = (&p.extra["g_dot"], &q.extra["g_dot"]);
        assert_eq!(a.len(), b.len(), "the same divisions at t = {}", p.t);
        for (x, y) in a.iter().zip(b) {
            worst = worst.max((x - y).abs());
            scale = scale.max(y.abs());
        }
    }
    eprintln!("ġ error {:.2e} of its largest value", worst / scale);
    assert!(worst < 10.0 * rtol * scale, "{:e}", worst / scale);
}
