//! The line's own Jacobian (`Line::jacobian_into`, one streaming sweep) against the coloured
//! AD Jacobian the integrators assemble from `ArrayProblem::directional`: every entry of the
//! band, for every feature of the residual, at a random non-uniform state with nonzero `ẏ`,
//! for `c ∈ {0, 0.7, 1}`; and the macroscale family integrated with either Jacobian takes the
//! same steps and Newton iterations.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::{Active, Field, MaxwellBranch, TanhGrowth};
use celltissue::line::build::{continuum, discrete, LineParams};
use celltissue::line::observe::Snapshot;
use celltissue::line::run::{integrate, LineModel, SolveSettings};
use celltissue::line::{Line, LineConfig};
use celltissue::substrate::{DragForm, WidthRule};
use celltissue::{ArrayProblem, CellArray, MooneyRivlin, NeoHookean, Scalar, StrainEnergy};
use integrators::linalg::Matrix;
use integrators::system::SystemCache;
use integrators::{Options, ResidualError, Stats, System};
use std::sync::Arc;

/// A line that does not provide its Jacobian: the integrators colour its AD residual.
struct NoJac<A>(A);

impl<A: CellArray> CellArray for NoJac<A> {
    integrators::forward_problem!(0: dim, pattern, residual<S: Scalar>, atol, algebraic);
}

impl<E: StrainEnergy> LineModel for NoJac<Line<E>> {
    fn initial_state(&self) -> Vec<f64> {
        self.0.initial_state()
    }
    fn initial_derivative_guess(&self) -> Vec<f64> {
        self.0.initial_derivative_guess()
    }
    fn observe(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError> {
        self.0.snapshot(t, y, yp)
    }
    fn breakpoints(&self) -> Vec<f64> {
        LineModel::breakpoints(&self.0)
    }
}

/// `J(c)` at `(t, y, ẏ)` as the solver builds it for `problem`, with the solver's counters.
fn assembled<A: CellArray>(
    problem: &mut ArrayProblem<A>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    c: f64,
) -> (Matrix, Stats) {
    let opts = Options::default();
    let mut stats = Stats::default();
    let mut cache = SystemCache::default();
    cache.rebuild(problem, &opts).expect("cache");
    let mut sys = System::new(problem, &opts, &mut stats, &mut cache);
    let mut m = sys.new_matrix();
    sys.jacobian(t, y, yp, c, &mut m).expect("jacobian");
    (m, stats)
}

/// Deterministic pseudo-random numbers in [−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A random non-uniform state: boundaries moved by up to 15 % of a cell, `g` and the viscous
/// stretches `a_v` in 0.8..1.2, every `ẏ` nonzero.
fn random_state<E: StrainEnergy>(line: &Line<E>, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Lcg(seed);
    let mut y = line.initial_state();
    let lay = line.layout();
    for (j, &k) in lay.xi.iter().enumerate() {
        if k != celltissue::line::array::NONE {
            let h = line.cells().l0[j.min(line.n_cells() - 1)];
            y[k] += 0.15 * h * rng.next();
        }
    }
    for &k in lay.gi.iter().chain(&lay.vi) {
        if k != celltissue::line::array::NONE {
            y[k] = 1.0 + 0.2 * rng.next();
        }
    }
    let yp = (0..y.len()).map(|_| 0.3 * rng.next() + 0.05).collect();
    (y, yp)
}

/// Both Jacobians of `line` at a random state agree to 1e-12 in every band entry (relative
/// to the largest entry of the row: entries that cancel to ~0 are compared at that scale), and
/// the line's own one is used (no directional call).
fn check<E: StrainEnergy + Clone>(name: &str, line: Line<E>) {
    let (y, yp) = random_state(&line, 7 + line.n_cells() as u64);
    let n = y.len();
    for c in [0.0, 0.7, 1.0] {
        for t in [0.0, 0.37] {
            let (own, s_own) = assembled(&mut ArrayProblem::new(line.clone()), t, &y, &yp, c);
            let (ad, s_ad) = assembled(&mut ArrayProblem::new(NoJac(line.clone())), t, &y, &yp, c);
            assert_eq!(s_own.directional_calls, 0, "{name}: own Jacobian not used");
            assert!(
                s_ad.directional_calls > 0,
                "{name}: AD reference not coloured"
            );
            let mut nonzero = 0;
            for i in 0..n {
                let scale = (0..n).map(|j| ad.get(i, j).abs()).fold(0.0, f64::max);
                // (a growth row at c = 0 where G'(σ) = 0 is empty: then equal means both 0)
                for j in 0..n {
                    let (a, b) = (own.get(i, j), ad.get(i, j));
                    assert!(
                        (a - b).abs() <= 1e-12 * scale,
                        "{name} c={c} t={t}: J[{i},{j}] own {a:e} vs AD {b:e} (row scale {scale:e})"
                    );
                    nonzero += (b != 0.0) as usize;
                }
            }
            // the comparison covers the whole structure, not an empty matrix
            assert!(
                nonzero >= 2 * n - 1,
                "{name}: only {nonzero} nonzero entries"
            );
        }
    }
}

fn base(n: usize) -> LineParams {
    let mut p = LineParams::unit_cells(n);
    p.ref_lengths = (0..n)
        .map(|i| 1.0 + 0.3 * ((i as f64) * 1.7).sin())
        .collect();
    p.right = RightEnd::Prescribed(Ramp::Constant(p.total_length() * 1.1));
    p.k = Field::gaussian_bump(0.4, 0.5, 0.3, 0.2);
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.2);
    p.eta = Field::Constant(0.0);
    p
}

/// Active stress (a Gaussian amplitude) and an exponential ramp of the prescribed end.
fn active_ramp(p: &mut LineParams) {
    p.active = Some(Active {
        beta: -1.0,
        omega: 0.9,
    });
    p.active_amp = Field::gaussian_bump(0.5, 0.5, 0.4, 0.3);
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: p.total_length(),
        k1: 0.2,
        t_ramp: 1.0,
    });
}

fn law() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

#[test]
fn own_jacobian_equals_coloured_ad_for_every_feature() {
    let n = 9;
    for form in [DragForm::Boundary, DragForm::Centre] {
        let f = format!("{form:?}");
        // plain elastic line with drag, prescribed end
        check(&format!("{f} elastic"), discrete(law(), &base(n)).unwrap());
        // viscosity (non-uniform), min width rule, aspect ratio and lateral stretch
        let mut p = base(n);
        p.eta = Field::gaussian_bump(0.3, 0.7, 0.6, 0.2);
        p.width = WidthRule::Min;
        p.gamma0 = 0.8;
        p.g2 = 1.3;
        check(
            &format!("{f} viscous min-width"),
            discrete(law(), &p).unwrap(),
        );
        // mean width, viscosity, K = 0 (algebraic rows)
        let mut p = base(n);
        p.eta = Field::Constant(0.5);
        p.k = Field::Constant(0.0);
        check(&format!("{f} viscous K=0"), discrete(law(), &p).unwrap());
        // active stress, time-dependent prescribed end
        let mut p = base(n);
        active_ramp(&mut p);
        check(&format!("{f} active ramp"), discrete(law(), &p).unwrap());
        // growth in the state with κ = (g g₂)^m, m ∉ {0, 1}, viscosity, both width rules
        for (m, width) in [
            (1.5, WidthRule::Mean),
            (0.5, WidthRule::Min),
            (1.0, WidthRule::Mean),
        ] {
            let mut p = base(n);
            p.growth = Some(Arc::new(TanhGrowth::default()));
            p.m = m;
            p.g2 = 1.2;
            p.eta = Field::Constant(0.4);
            p.width = width;
            check(
                &format!("{f} growth m={m} {width:?}"),
                discrete(law(), &p).unwrap(),
            );
        }
        // free right end with an applied force, with and without growth
        for growth in [false, true] {
            let mut p = base(n);
            p.right = RightEnd::Free(Some(Arc::new(|t: f64| (0.3 + 0.1 * t, 0.1))));
            p.eta = Field::Constant(0.2);
            if growth {
                p.growth = Some(Arc::new(TanhGrowth::default()));
                p.m = 1.5;
            }
            check(
                &format!("{f} free end growth={growth}"),
                discrete(law(), &p).unwrap(),
            );
        }
        // free end without force, two cells and one cell (short windows)
        for cells in [1, 2] {
            let mut p = base(cells);
            p.right = RightEnd::Free(None);
            check(
                &format!("{f} free {cells} cells"),
                discrete(law(), &p).unwrap(),
            );
        }
        // a Maxwell branch (Maxwell fluid and standard linear solid) and an external pressure
        // field, without and with growth (whose rate reads the stress the pressure lowers),
        // prescribed and free ends
        for (branch, p_ext, growth, free) in [
            (
                Some(MaxwellBranch::maxwell(0.8, 1.3).unwrap()),
                false,
                false,
                false,
            ),
            (
                Some(MaxwellBranch::standard_linear_solid(0.8, 1.3).unwrap()),
                false,
                false,
                true,
            ),
            (
                Some(MaxwellBranch::standard_linear_solid(0.6, 0.9).unwrap()),
                true,
                true,
                false,
            ),
            (
                Some(MaxwellBranch::maxwell(1.1, 0.7).unwrap()),
                true,
                true,
                true,
            ),
            (None, true, false, false),
            (None, true, true, true),
        ] {
            let mut p = base(n);
            p.maxwell = branch;
            p.eta = Field::Constant(0.3);
            if p_ext {
                p.p_ext = Field::gaussian_bump(0.05, 0.1, 0.4, 0.2);
            }
            if growth {
                p.growth = Some(Arc::new(TanhGrowth::default()));
                p.m = 1.5;
            }
            if free {
                p.right = RightEnd::Free(Some(Arc::new(|t: f64| (0.3 + 0.1 * t, 0.1))));
            }
            check(
                &format!("{f} branch={branch:?} p_ext={p_ext} growth={growth} free={free}"),
                discrete(law(), &p).unwrap(),
            );
        }
        // a branch with active stress, a time-dependent end, the min width rule and growth
        // with κ = (g g₂)^m
        let mut p = base(n);
        p.maxwell = Some(MaxwellBranch::standard_linear_solid(0.5, 0.6).unwrap());
        p.p_ext = Field::Constant(0.04);
        active_ramp(&mut p);
        p.width = WidthRule::Min;
        p.growth = Some(Arc::new(TanhGrowth::default()));
        p.m = 0.5;
        p.g2 = 1.2;
        check(
            &format!("{f} branch active growth"),
            discrete(law(), &p).unwrap(),
        );
        // continuum line (k_face scaled by h/L̄), another strain energy
        let mut p = base(40);
        p.eta = Field::Constant(0.3);
        check(&format!("{f} continuum"), continuum(law(), &p, 11).unwrap());
        p.maxwell = Some(MaxwellBranch::maxwell(0.9, 1.1).unwrap());
        p.p_ext = Field::gaussian_bump(0.05, 0.1, 0.4, 0.2);
        check(
            &format!("{f} continuum branch"),
            continuum(law(), &p, 11).unwrap(),
        );
        check(
            &format!("{f} Mooney-Rivlin"),
            discrete(MooneyRivlin::new(0.3, 0.2).unwrap(), &base(n)).unwrap(),
        );
    }
}

#[test]
fn a_ring_falls_back_to_the_coloured_jacobian() {
    let mut p = base(8);
    p.right = RightEnd::Periodic { gauge: false };
    let line = discrete(law(), &p).unwrap();
    let (y, yp) = random_state(&line, 3);
    let mut jac = Matrix::zeros(line.dim(), &line.pattern());
    assert!(!line.jacobian_into(0.0, &y, &yp, 1.0, &mut jac).unwrap());
    let (_, stats) = assembled(&mut ArrayProblem::new(line), 0.0, &y, &yp, 1.0);
    assert!(stats.directional_calls > 0);
}

#[test]
fn own_jacobian_rejects_a_collapsed_cell_like_the_residual() {
    let line = discrete(law(), &base(6)).unwrap();
    let (mut y, yp) = random_state(&line, 5);
    y[line.layout().xi[3]] = y[line.layout().xi[2]] - 0.1;
    let mut r = vec![0.0; y.len()];
    let res = line.residual(0.0, &y, &yp, &mut r).unwrap_err();
    let mut jac = Matrix::zeros(line.dim(), &line.pattern());
    let jres = line.jacobian_into(0.0, &y, &yp, 1.0, &mut jac).unwrap_err();
    assert_eq!(jres, res);
}

/// The macroscale family (docs/model.md §5.4) at N = 2000: with the line's own Jacobian the BDF
/// run takes the same steps and Newton iterations as with the coloured one (within ±2; the
/// matrices differ by rounding only), and ends at the same state.
#[test]
fn macroscale_family_steps_unchanged() {
    let n = 2000;
    let nf = n as f64;
    let cfg = LineConfig {
        cells: n,
        k: (1.0 / nf).into(),
        t_ramp: nf,
        ..Default::default()
    };
    let line = discrete(law(), &cfg.params(1e-8)).unwrap();
    // BDF, rtol 1e-6, atol 1e-8, max norm, one thread
    let settings = SolveSettings::default();
    let own = integrate(&mut ArrayProblem::new(line.clone()), &settings, &[nf]);
    let ad = integrate(&mut ArrayProblem::new(NoJac(line)), &settings, &[nf]);
    assert!(own.error.is_none() && ad.error.is_none());
    let (so, sa) = (own.stats, ad.stats);
    eprintln!("own: {so:?}\nAD:  {sa:?}");
    assert_eq!(so.directional_calls, 0);
    assert!(sa.directional_calls > 0);
    assert!(
        so.steps.abs_diff(sa.steps) <= 2,
        "steps {} vs {}",
        so.steps,
        sa.steps
    );
    assert!(
        so.newton_iterations.abs_diff(sa.newton_iterations) <= 2,
        "Newton iterations {} vs {}",
        so.newton_iterations,
        sa.newton_iterations
    );
    let (xo, xa) = (&own.snapshots[0].x, &ad.snapshots[0].x);
    let dx = xo
        .iter()
        .zip(xa)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(dx <= 1e-6 * nf, "end states differ by {dx:e}");
}
