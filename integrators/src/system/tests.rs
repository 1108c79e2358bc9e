//! Tests of the assembled system: weights and norms, Jacobian assembly and reuse, consistent initialisation.

use std::sync::Arc;

use super::*;
use crate::pattern::SparsityPattern;

fn with_system<P: Problem, R>(
    p: &mut P,
    opts: &Options,
    f: impl FnOnce(&mut System<'_>) -> R,
) -> (R, Stats) {
    let mut stats = Stats::default();
    let mut cache = SystemCache::default();
    cache.rebuild(&*p, opts).unwrap();
    let r = {
        let mut sys = System::new(p, opts, &mut stats, &mut cache);
        f(&mut sys)
    };
    (r, stats)
}

/// `ẏ_i = −k_i·y_i`.
struct Decay(Vec<f64>);
impl Problem for Decay {
    fn dim(&self) -> usize {
        self.0.len()
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        for i in 0..y.len() {
            r[i] = yp[i] + self.0[i] * y[i];
        }
        Ok(())
    }
    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 0, upper: 0 }
    }
}

#[test]
fn consistent_init_ode_is_one_newton_step() {
    let mut p = Decay(vec![1.0, 2.0, 0.5]);
    let mut y = vec![1.0, -2.0, 3.0];
    let mut yp = vec![0.0; 3];
    let (res, st) = with_system(&mut p, &Options::default(), |s| {
        s.consistent_init(0.0, &mut y, &mut yp)
    });
    res.unwrap();
    assert_eq!(y, vec![1.0, -2.0, 3.0], "differential y untouched");
    for (a, b) in yp.iter().zip([-1.0, 4.0, -1.5]) {
        assert!((a - b).abs() < 1e-12, "{yp:?}");
    }
    assert_eq!(st.jacobian_evals, 1);
    assert_eq!(st.factorizations, 1);
    // base + 1 colour (diagonal) + one trial point
    assert_eq!(st.residual_calls, 3);
}

/// Index-1 DAE: `ẏ0 = −y0 + y1`, `0 = y1³ + y1 − y0²` (algebraic, nonlinear), plus a
/// `ẏ2 = y1·y2` component; dense pattern.
struct Dae {
    directional: bool,
}
impl Problem for Dae {
    fn dim(&self) -> usize {
        3
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] + y[0] - y[1];
        r[1] = y[1].powi(3) + y[1] - y[0] * y[0];
        r[2] = (1.0 + y[0] * y[0]) * yp[2] - y[1] * y[2];
        Ok(())
    }
    fn algebraic(&self) -> Vec<bool> {
        vec![false, true, false]
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
        if !self.directional {
            return Ok(false);
        }
        self.residual(t, y, yp, r)?;
        dr[0] = (1.0 + 0.0 * c) * v[0] - v[1] + c * v[0];
        dr[1] = (3.0 * y[1] * y[1] + 1.0) * v[1] - 2.0 * y[0] * v[0];
        dr[2] =
            2.0 * y[0] * yp[2] * v[0] - y[2] * v[1] - y[1] * v[2] + c * (1.0 + y[0] * y[0]) * v[2];
        Ok(true)
    }
}

#[test]
fn consistent_init_index1_dae_solves_algebraic_component() {
    for directional in [false, true] {
        let mut p = Dae { directional };
        let mut y = vec![2.0, 0.0, 1.5];
        let mut yp = vec![0.0; 3];
        let (res, st) = with_system(&mut p, &Options::default(), |s| {
            s.consistent_init(0.0, &mut y, &mut yp)
        });
        res.unwrap();
        // y1³ + y1 = 4 → y1 = 1.378796...
        let y1 = y[1];
        assert!((y1.powi(3) + y1 - 4.0).abs() < 1e-9, "{y1}");
        assert_eq!((y[0], y[2]), (2.0, 1.5), "differential y untouched");
        assert!((yp[0] - (-2.0 + y1)).abs() < 1e-9);
        assert!((yp[2] - y1 * 1.5 / 5.0).abs() < 1e-9);
        assert!(st.jacobian_evals >= 2 && st.jacobian_evals <= 8, "{st:?}");
        if directional {
            assert!(st.directional_calls > 0);
        }
    }
}

/// `ẏ0 = …` but flagged differential component 1 has no ẏ1: singular init matrix.
struct BadFlags;
impl Problem for BadFlags {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] + y[0];
        r[1] = y[1] - y[0];
        Ok(())
    }
}

#[test]
fn consistent_init_reports_singular_system() {
    let mut p = BadFlags;
    let (mut y, mut yp) = (vec![1.0, 0.0], vec![0.0, 0.0]);
    let (res, _) = with_system(&mut p, &Options::default(), |s| {
        s.consistent_init(3.0, &mut y, &mut yp)
    });
    let e = res.unwrap_err();
    assert!(matches!(e.kind, ErrorKind::Initialisation(_)), "{e}");
    assert_eq!(e.t, 3.0);
    assert_eq!(e.component, Some(1));
}

struct Faulty(u8);
impl Problem for Faulty {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        match self.0 {
            0 => {
                r[0] = 0.0;
                r[1] = f64::NAN;
                Ok(())
            }
            1 => Err(ResidualError::Recoverable {
                reason: "length ≤ 0".into(),
                component: Some(0),
            }),
            _ => Err(ResidualError::Fatal("boom".into())),
        }
    }
    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![1e-6, 1e-9])
    }
}

#[test]
fn residual_failures_are_typed() {
    let opts = Options::default();
    let mut r = [0.0; 2];
    for (mode, check) in [
        (
            0u8,
            Box::new(|f: StepFailure| {
                assert!(
                    matches!(
                        f,
                        StepFailure::Recoverable {
                            component: Some(1),
                            ..
                        }
                    ),
                    "{f:?}"
                )
            }) as Box<dyn Fn(StepFailure)>,
        ),
        (
            1,
            Box::new(|f| {
                assert_eq!(
                    f,
                    StepFailure::Recoverable {
                        reason: RecoverableCause::Rejected("length ≤ 0".into()),
                        component: Some(0)
                    }
                )
            }),
        ),
        (
            2,
            Box::new(|f| match f {
                StepFailure::Fatal(e) => {
                    assert_eq!(e.kind, ErrorKind::Residual("boom".into()));
                    assert_eq!(e.t, 1.5);
                }
                other => panic!("{other:?}"),
            }),
        ),
    ] {
        let mut p = Faulty(mode);
        let (res, st) = with_system(&mut p, &opts, |s| {
            s.residual(1.5, &[1.0; 2], &[0.0; 2], &mut r)
        });
        check(res.unwrap_err());
        assert_eq!(st.residual_calls, 1);
    }
    // init maps a fatal residual to the same error, a recoverable one to Initialisation
    let mut p = Faulty(1);
    let (res, _) = with_system(&mut p, &opts, |s| {
        s.consistent_init(0.0, &mut [1.0; 2], &mut [0.0; 2])
    });
    let e = res.unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::Initialisation(_)) && e.component == Some(0),
        "{e}"
    );
}

#[test]
fn rebuild_validates_sizes() {
    struct Bad(u8);
    impl Problem for Bad {
        fn dim(&self) -> usize {
            3
        }
        fn residual(
            &mut self,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &mut [f64],
        ) -> Result<(), ResidualError> {
            Ok(())
        }
        fn atol(&self) -> Option<Vec<f64>> {
            match self.0 {
                0 => Some(vec![1e-6; 2]),
                1 => Some(vec![1e-6, 0.0, 1e-6]),
                _ => None,
            }
        }
        fn algebraic(&self) -> Vec<bool> {
            vec![false; if self.0 == 2 { 4 } else { 3 }]
        }
        fn pattern(&self) -> Pattern {
            if self.0 == 3 {
                Pattern::Sparse(Arc::new(SparsityPattern::from_entries(2, &[])))
            } else {
                Pattern::Dense
            }
        }
    }
    let opts = Options::default();
    for (k, needle) in [
        (0, "atol() has length 2"),
        (1, "atol()[1]"),
        (2, "algebraic()"),
        (3, "sparse pattern"),
    ] {
        let err = SystemCache::default().rebuild(&Bad(k), &opts).unwrap_err();
        assert!(matches!(err, ErrorKind::InvalidInput(_)), "{err}");
        assert!(err.to_string().contains(needle), "{err}");
    }
}

#[test]
fn weights_norms_and_counted_factorisations() {
    let mut p = Faulty(0);
    let opts = Options {
        rtol: 1e-3,
        ..Options::default()
    };
    let ((), st) = with_system(&mut p, &opts, |s| {
        let mut w = [0.0; 2];
        s.error_weights(&[2.0, -1.0], &mut w);
        assert!((w[0] - 1.0 / (2e-3 + 1e-6)).abs() < 1e-6);
        assert!((w[1] - 1.0 / (1e-3 + 1e-9)).abs() < 1e-6);
        assert!((System::wrms(&[3.0, 4.0], &[1.0, 1.0]) - 12.5f64.sqrt()).abs() < 1e-15);
        assert_eq!(System::worst_component(&[3.0, -4.0], &[1.0, 1.0]), Some(1));
        assert_eq!(
            System::worst_component(&[3.0, f64::NAN], &[1.0, 1.0]),
            Some(1)
        );
        assert_eq!(System::worst_component(&[], &[]), None);
        // dense factor: counted, never symbolic; singular is recoverable naming the column
        let mut m = s.new_matrix();
        let mut lu = s.new_linear_solver();
        m.add(0, 0, 1.0);
        let f = s.factor(&mut lu, &m).unwrap_err();
        assert!(matches!(
            f,
            StepFailure::Recoverable {
                component: Some(1),
                ..
            }
        ));
        m.add(1, 1, 2.0);
        s.factor(&mut lu, &m).unwrap();
        let mut b = [1.0, 1.0];
        s.solve(&lu, &mut b);
        assert_eq!(b, [1.0, 0.5]);
    });
    assert_eq!(
        (
            st.factorizations,
            st.symbolic_factorizations,
            st.linear_solves
        ),
        (2, 0, 1)
    );
}

#[test]
fn sparse_symbolic_factorisation_is_reused() {
    struct Ring;
    impl Problem for Ring {
        fn dim(&self) -> usize {
            8
        }
        fn residual(
            &mut self,
            _: f64,
            y: &[f64],
            yp: &[f64],
            r: &mut [f64],
        ) -> Result<(), ResidualError> {
            for i in 0..8 {
                r[i] = yp[i] - y[(i + 1) % 8] + y[i] * y[i];
            }
            Ok(())
        }
        fn pattern(&self) -> Pattern {
            let e: Vec<_> = (0..8).map(|i| (i, (i + 1) % 8)).collect();
            Pattern::Sparse(Arc::new(SparsityPattern::from_entries(8, &e)))
        }
    }
    let mut p = Ring;
    let opts = Options::default();
    let ((), st) = with_system(&mut p, &opts, |s| {
        let mut m = s.new_matrix();
        let mut lu = s.new_linear_solver();
        let y = [0.5; 8];
        for c in [10.0, 3.0, 100.0] {
            s.jacobian(0.0, &y, &[0.0; 8], c, &mut m).unwrap();
            s.factor(&mut lu, &m).unwrap();
            let mut b = [1.0; 8];
            s.solve(&lu, &mut b);
            let mut back = [0.0; 8];
            m.mul_vec(&b, &mut back);
            assert!(back.iter().all(|x| (x - 1.0).abs() < 1e-12), "{back:?}");
        }
    });
    assert_eq!((st.factorizations, st.symbolic_factorizations), (3, 1));
    assert_eq!(st.jacobian_evals, 3);
}

/// `K·ẏ₀ + 2(y₀ − 1) − (y₁ − y₀) = 0`, `K·ẏ₁ + 2(y₁ − 1) + (y₁ − y₀) = 0`: two boundaries of a
/// line with drag `K` (tiny against the unit stiffness), with its hand-written iteration
/// matrix `J(c) = ∂F/∂y + c·K·I`.
/// `.1`: the matrix through [`Problem::directional`] (as AD gives it) instead.
struct TinyDrag(f64, bool);
impl Problem for TinyDrag {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = self.0 * yp[0] + 2.0 * (y[0] - 1.0) - (y[1] - y[0]);
        r[1] = self.0 * yp[1] + 2.0 * (y[1] - 1.0) + (y[1] - y[0]);
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut crate::problem::JacobianSink,
    ) -> Result<bool, ResidualError> {
        if self.1 {
            return Ok(false);
        }
        jac.add(0, 0, 3.0 + c * self.0);
        jac.add(0, 1, -1.0);
        jac.add(1, 0, -1.0);
        jac.add(1, 1, 3.0 + c * self.0);
        Ok(true)
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
        if !self.1 {
            return Ok(false);
        }
        self.residual(t, y, yp, r)?;
        dr[0] = (3.0 + c * self.0) * v[0] - v[1];
        dr[1] = -v[0] + (3.0 + c * self.0) * v[1];
        Ok(true)
    }
}

#[test]
fn consistent_init_keeps_a_drag_far_below_the_stiffness() {
    // J(1) − J(0) = (3 + K) − 3 is exactly 0 for K < 2.2e-16 ("singular" before); the
    // consistent rates are ẏ = −F(y, 0)/K, of size 1/K
    // (rates of 1/K beyond about 1e150 overflow the RMS norm of the Newton update: not tried)
    for (k, directional) in [1e-6, 1e-16, 1e-30, 1e-100]
        .into_iter()
        .flat_map(|k| [(k, false), (k, true)])
    {
        let mut p = TinyDrag(k, directional);
        let (mut y, mut yp) = (vec![1.5, 0.75], vec![0.0; 2]);
        let (res, _) = with_system(&mut p, &Options::default(), |s| {
            s.consistent_init(0.0, &mut y, &mut yp)
        });
        res.unwrap_or_else(|e| panic!("K = {k:e} (directional: {directional}): {e}"));
        // F(y, 0) = (2·0.5 + 0.75, 2·(−0.25) − 0.75) = (1.75, −1.25)
        let exact = [-1.75 / k, 1.25 / k];
        for (a, b) in yp.iter().zip(exact) {
            assert!(
                (a / b - 1.0).abs() < 1e-12,
                "K = {k:e}: {yp:?} against {exact:?}"
            );
        }
    }
    // a component whose ẏ never enters F is still reported (index > 1), not rescued
    for directional in [false, true] {
        let mut p = TinyDrag(0.0, directional);
        let (mut y, mut yp) = (vec![1.5, 0.75], vec![0.0; 2]);
        let (res, _) = with_system(&mut p, &Options::default(), |s| {
            s.consistent_init(0.0, &mut y, &mut yp)
        });
        assert!(res.unwrap_err().to_string().contains("singular"));
    }
}

/// `y₀ − 1 + 1e300·(1e300·ẏ₀) = 0`: its `∂F/∂ẏ` is 1e600, beyond the doubles.
struct OverflowingRate;
impl Problem for OverflowingRate {
    fn dim(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = y[0] - 1.0 + 1e300 * (1e300 * yp[0]);
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut crate::problem::JacobianSink,
    ) -> Result<bool, ResidualError> {
        jac.add(0, 0, 1.0 + 1e300 * (1e300 * c));
        Ok(true)
    }
}

#[test]
fn consistent_init_says_an_overflowed_matrix_overflowed() {
    // it used to read "∂F/∂(ẏ …) is singular (index > 1, …)", which it is not
    let (mut y, mut yp) = (vec![0.5], vec![0.0]);
    let (res, _) = with_system(&mut OverflowingRate, &Options::default(), |s| {
        s.consistent_init(0.0, &mut y, &mut yp)
    });
    let m = res.unwrap_err().to_string();
    assert!(m.contains("overflowed") && !m.contains("singular"), "{m}");
}
