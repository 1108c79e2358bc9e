//! A growing line's Newton matrix `∂F/∂y + α·∂F/∂ẏ` (boundary positions interleaved with each
//! cell's growth stretch, a `(2, 2)` band) takes the banded solver's condensed path: the growth
//! rows touch only their cell's two boundaries, so the solver eliminates them and factorises
//! a tridiagonal Schur complement. Checked in the boundary drag form (the default), with and
//! without viscosity, on a free and a prescribed end, against the residual of the solve in the
//! full matrix. The cell-centre form couples a boundary to the stresses of three cells (a
//! `(4, 2)` band) and takes the pivoted band LU.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::TanhGrowth;
use celltissue::line::build::{discrete, LineParams};
use celltissue::substrate::DragForm;
use celltissue::{CellArray, NeoHookean};
use integrators::linalg::{LinearSolver, Matrix};
use std::sync::Arc;

fn check(form: DragForm, eta: f64, right: RightEnd) {
    let n = 60;
    let mut p = LineParams::unit_cells(n);
    p.right = right;
    p.k = 1e-3.into();
    p.eta = eta.into();
    p.form = form;
    p.growth = Some(Arc::new(TanhGrowth::default()));
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let dim = line.dim();
    let mut y = line.initial_state();
    for (k, v) in y.iter_mut().enumerate() {
        *v += 0.05 * (0.3 * k as f64).cos();
    }
    let yp: Vec<f64> = (0..dim).map(|k| 0.01 * (k as f64).sin()).collect();
    let pattern = line.pattern();
    let (mut jy, mut j1) = (Matrix::zeros(dim, &pattern), Matrix::zeros(dim, &pattern));
    assert!(line.jacobian_into(0.0, &y, &yp, 0.0, &mut jy).unwrap());
    assert!(line.jacobian_into(0.0, &y, &yp, 1.0, &mut j1).unwrap());
    j1.axpby(1.0, -1.0, &jy); // ∂F/∂ẏ
    let case = format!("{form:?}, eta = {eta}, dim = {dim}");
    for alpha in [1e-3, 1.0, 1e4] {
        let mut lu = LinearSolver::new(dim, &pattern);
        let mut scratch = Matrix::zeros(dim, &pattern);
        lu.factor_combination(&jy, alpha, &j1, &mut scratch)
            .unwrap();
        assert!(lu.last_factor_condensed(), "{case}, alpha = {alpha}");
        let b: Vec<f64> = (0..dim).map(|k| 1.0 + (0.7 * k as f64).sin()).collect();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        let mut full = Matrix::zeros(dim, &pattern);
        full.axpby(1.0, 1.0, &jy);
        full.axpby(1.0, alpha, &j1);
        let mut back = vec![0.0; dim];
        full.mul_vec(&x, &mut back);
        let scale = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = back
            .iter()
            .zip(&b)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-12 * scale.max(1.0) * alpha.max(1.0),
            "{case}, alpha = {alpha}: residual {worst} (|x| {scale})"
        );
    }
}

#[test]
fn free_end_growing_lines_condense() {
    check(DragForm::Boundary, 0.0, RightEnd::Free(None));
}

#[test]
fn viscous_growing_lines_condense() {
    check(DragForm::Boundary, 0.7, RightEnd::Free(None));
}

#[test]
fn a_prescribed_end_growing_line_condenses() {
    let ramp = Ramp::Exponential {
        l0: 60.0,
        k1: 0.1,
        t_ramp: 1.0,
    };
    check(DragForm::Boundary, 0.0, RightEnd::Prescribed(ramp));
}
