//! Structure of the line's residual (docs/model.md §2.9): declared bandwidths for each form, the AD
//! Jacobian columns equal finite differences of the residual, the conservative continuum is a
//! second-order consistent discretisation of the continuum force balance, and invalid states
//! are rejected naming the cell.

use celltissue::array::CellArray;
use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::{Active, Field, TanhGrowth};
use celltissue::line::build::{continuum, discrete, LineParams};
use celltissue::line::Line;
use celltissue::substrate::{DragForm, WidthRule};
use celltissue::NeoHookean;
use integrators::{Pattern, ResidualError};
use num_dual::Dual64;
use std::sync::Arc;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn base(n: usize) -> LineParams {
    let mut p = LineParams::unit_cells(n);
    p.k = Field::Constant(0.3);
    p.eta = Field::Constant(0.7);
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.2);
    p
}

fn growing(mut p: LineParams, form: DragForm, m: f64) -> LineParams {
    p.growth = Some(Arc::new(TanhGrowth::default()));
    p.form = form;
    p.m = m;
    p.right = RightEnd::Free(None);
    p
}

/// A perturbed state and derivative with positive stretches.
fn state(line: &Line<NeoHookean>) -> (Vec<f64>, Vec<f64>) {
    let mut y = line.initial_state();
    let n = y.len();
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.05 * ((i as f64) * 0.7).sin();
    }
    let yp = (0..n).map(|i| 0.1 * ((i as f64) * 1.3).cos()).collect();
    (y, yp)
}

fn check_jacobian(line: &Line<NeoHookean>) {
    let (y, yp) = state(line);
    let n = y.len();
    let t = 0.37;
    let c = 2.5;
    let mut r0 = vec![0.0; n];
    line.residual(t, &y, &yp, &mut r0).unwrap();
    let pattern = line.pattern();
    for j in 0..n {
        // AD column
        let yd: Vec<Dual64> = (0..n)
            .map(|i| Dual64::new(y[i], if i == j { 1.0 } else { 0.0 }))
            .collect();
        let ypd: Vec<Dual64> = (0..n)
            .map(|i| Dual64::new(yp[i], if i == j { c } else { 0.0 }))
            .collect();
        let mut rd = vec![Dual64::new(0.0, 0.0); n];
        line.residual(t, &yd, &ypd, &mut rd).unwrap();
        // central FD column
        let h = 1e-6;
        let mut yph = y.clone();
        let mut ypph = yp.clone();
        yph[j] += h;
        ypph[j] += c * h;
        let mut rp = vec![0.0; n];
        line.residual(t, &yph, &ypph, &mut rp).unwrap();
        yph[j] -= 2.0 * h;
        ypph[j] -= 2.0 * c * h;
        let mut rm = vec![0.0; n];
        line.residual(t, &yph, &ypph, &mut rm).unwrap();
        for i in 0..n {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            assert!(
                (rd[i].eps - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                "J[{i},{j}]: AD {} vs FD {fd}",
                rd[i].eps
            );
            if rd[i].eps != 0.0 {
                assert!(pattern.contains(i, j), "({i},{j}) outside {pattern:?}");
            }
            assert!((rd[i].re - r0[i]).abs() < 1e-14 * (1.0 + r0[i].abs()));
        }
    }
}

#[test]
fn bandwidths_match_model_section_2_9() {
    let mut p = base(12);
    p.right = RightEnd::Prescribed(Ramp::Constant(11.0));
    let l = discrete(nh(), &p).unwrap();
    assert_eq!(l.pattern(), Pattern::Banded { lower: 1, upper: 1 });
    let l = discrete(nh(), &growing(base(12), DragForm::Boundary, 1.0)).unwrap();
    assert_eq!(l.pattern(), Pattern::Banded { lower: 2, upper: 2 });
    let l = discrete(nh(), &growing(base(12), DragForm::Centre, 1.0)).unwrap();
    assert_eq!(l.pattern(), Pattern::Banded { lower: 4, upper: 2 });
    assert_eq!(l.dim(), 24);
    let mut p = base(12);
    p.form = DragForm::Centre;
    p.right = RightEnd::Free(None);
    let l = discrete(nh(), &p).unwrap();
    assert_eq!(l.pattern(), Pattern::Banded { lower: 2, upper: 1 });
    let mut p = base(12);
    p.right = RightEnd::Periodic { gauge: false };
    let l = discrete(nh(), &p).unwrap();
    assert!(matches!(l.pattern(), Pattern::Sparse(_)));
    assert_eq!(l.dim(), 12);
    assert!(l.pattern().colour_count(12) <= 4);
}

#[test]
fn ad_jacobian_equals_finite_differences() {
    let mut p = base(9);
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: 9.0,
        k1: 0.1,
        t_ramp: 1.0,
    });
    check_jacobian(&discrete(nh(), &p).unwrap());
    p.width = WidthRule::Min;
    check_jacobian(&discrete(nh(), &p).unwrap());
    for form in [DragForm::Boundary, DragForm::Centre] {
        for m in [0.0, 1.0, 0.5] {
            check_jacobian(&discrete(nh(), &growing(base(9), form, m)).unwrap());
        }
    }
    let mut p = base(9);
    p.right = RightEnd::Periodic { gauge: false };
    p.active = Some(Active {
        beta: -1.0,
        omega: 1.0 / 9.0,
    });
    check_jacobian(&discrete(nh(), &p).unwrap());
    let mut p = growing(base(9), DragForm::Boundary, 1.0);
    p.right = RightEnd::Periodic { gauge: false };
    check_jacobian(&discrete(nh(), &p).unwrap());
}

/// The conservative continuum (docs/model.md §3.3a: n segments of length h, drag K·h per node) is
/// a second-order discretisation of the continuum force balance K v = W σ_X (docs/model.md §3.1):
/// on smooth fields x(X), v(X) = ẋ(X) (heterogeneous Gaussian μ, η > 0, W = γ₀/λ), each
/// node's residual divided by h equals K v − W σ_X to O(h²). The reference operator is
/// evaluated from the closed-form fields (σ_X by a fourth-order difference with step 1e-3,
/// error ~1e-12), not through the scheme. A wrong drag scaling (K instead of K·h), stretch
/// (Δx instead of Δx/h), face width or field sampling leaves an O(1) or O(h) consistency
/// error and fails the order check.
#[test]
fn continuum_residual_is_second_order_consistent() {
    let l0 = 40.0;
    let (k, eta, c) = (0.3, 0.7, 0.95);
    let pi = std::f64::consts::PI;
    // x(X) = cX + 0.01 l0 sin(πX/l0), v(X) = 0.05 sin(2πX/l0): x(0) = 0, x(l0) = c l0, v = 0
    // at both ends (a held right end)
    let dx = |x: f64| c + 0.01 * pi * (pi * x / l0).cos();
    let v = |x: f64| 0.05 * (2.0 * pi * x / l0).sin();
    let dv = |x: f64| 0.05 * 2.0 * pi / l0 * (2.0 * pi * x / l0).cos();
    let mu = |x: f64| 1.0 + (-(x - 0.5 * l0).powi(2) / (2.0 * (0.2 * l0).powi(2))).exp();
    let sigma = |x: f64| {
        let lam = dx(x);
        mu(x) * (lam * lam - 1.0 / (lam * lam)) + eta * dv(x) * (1.0 + 1.0 / (lam * lam))
    };
    let d = 1e-3;
    let sigma_x = |x: f64| {
        (-sigma(x + 2.0 * d) + 8.0 * sigma(x + d) - 8.0 * sigma(x - d) + sigma(x - 2.0 * d))
            / (12.0 * d)
    };
    let mut errs = Vec::new();
    for n in [20usize, 40, 80, 160] {
        let mut p = base(40);
        p.right = RightEnd::Prescribed(Ramp::Constant(c * l0));
        let line = continuum(nh(), &p, n).unwrap();
        assert_eq!(line.gamma0, 1.0);
        let h = l0 / n as f64;
        let xi = &line.layout().xi;
        let mut y = vec![0.0; line.num_unknowns()];
        let mut yp = vec![0.0; y.len()];
        for j in 1..n {
            let xj = j as f64 * h;
            y[xi[j]] = c * xj + 0.01 * l0 * (pi * xj / l0).sin();
            yp[xi[j]] = v(xj);
        }
        let mut r = vec![0.0; y.len()];
        line.residual(0.0, &y, &yp, &mut r).unwrap();
        let err = (1..n)
            .map(|j| {
                let xj = j as f64 * h;
                let exact = k * v(xj) - sigma_x(xj) / dx(xj);
                (r[xi[j]] / h - exact).abs()
            })
            .fold(0.0, f64::max);
        println!("n = {n}: max |R/h − (K v − W σ_X)| = {err:.3e}");
        errs.push(err);
    }
    for w in errs.windows(2) {
        let q = (w[0] / w[1]).log2();
        assert!((q - 2.0).abs() < 0.1, "consistency order {q} ({errs:?})");
    }
}

#[test]
fn forms_b_and_c_agree_for_uniform_kappa() {
    // m = 0: forward substitution of (C) from the wall gives (B) — same solution ẏ
    // (the residuals differ row by row, but F_B = L·F_C with L lower bidiagonal)
    let pb = growing(base(10), DragForm::Boundary, 0.0);
    let pc = growing(base(10), DragForm::Centre, 0.0);
    let lb = discrete(nh(), &pb).unwrap();
    let lc = discrete(nh(), &pc).unwrap();
    let (y, yp) = state(&lb);
    let mut rb = vec![0.0; y.len()];
    let mut rc = vec![0.0; y.len()];
    lb.residual(0.0, &y, &yp, &mut rb).unwrap();
    lc.residual(0.0, &y, &yp, &mut rc).unwrap();
    // x-rows: R_C(cell j) = R_B(j−1) + R_B(j) with K uniform, κ = 1
    let xi = &lb.layout().xi;
    for j in 1..=10 {
        let expect = rb[xi[j]] + if j >= 2 { rb[xi[j - 1]] } else { 0.0 };
        assert!((rc[xi[j]] - expect).abs() < 1e-12, "cell {j}");
    }
}

#[test]
fn inverted_cell_is_rejected_naming_it() {
    let mut p = base(5);
    p.right = RightEnd::Prescribed(Ramp::Constant(5.0));
    let l = discrete(nh(), &p).unwrap();
    let mut y = l.initial_state();
    y[2] = 1.5; // x_3 < x_2: cell 3 inverted
    let yp = vec![0.0; y.len()];
    let mut r = vec![0.0; y.len()];
    match l.residual(0.0, &y, &yp, &mut r) {
        Err(ResidualError::Recoverable { reason, component }) => {
            assert!(reason.contains("cell 3"), "{reason}");
            assert_eq!(component, Some(2));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn centre_form_on_a_ring_is_rejected() {
    let mut p = base(6);
    p.form = DragForm::Centre;
    p.right = RightEnd::Periodic { gauge: false };
    let e = discrete(nh(), &p).err().unwrap();
    assert!(e.to_string().contains("drag_form"), "{e}");
}
