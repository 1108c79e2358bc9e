//! The Newton matrices carried across a division (`Problem::map_jacobian`, implemented by
//! `Dividing`): moved onto the new layout with the rows around the daughters evaluated afresh,
//! they equal the Jacobian of the line after the split, entry by entry, when the old matrices
//! were taken at the event state (the cells away from the division are unchanged by it, and
//! so are their rows); for elastic cells, and for cells with a Maxwell branch (three unknowns
//! a cell) under an external pressure field.

use celltissue::boundary::RightEnd;
use celltissue::cell::{Field, MaxwellBranch, TanhGrowth};
use celltissue::events::{AreaDoubling, Dividing};
use celltissue::line::build::{discrete, LineParams};
use celltissue::substrate::DragForm;
use celltissue::{CellArray, NeoHookean};
use integrators::linalg::Matrix;
use integrators::EventAction;
use std::sync::Arc;

/// `(∂F/∂y, ∂F/∂ẏ)` of the line at `(t, y, ẏ)`, in matrices of size `n` (≥ the line's).
fn pair(div: &Dividing<NeoHookean>, y: &[f64], yp: &[f64], n: usize) -> (Matrix, Matrix) {
    let pattern = div.pattern();
    let (mut jy, mut j1) = (Matrix::zeros(n, &pattern), Matrix::zeros(n, &pattern));
    assert!(div.line.jacobian_into(0.5, y, yp, 0.0, &mut jy).unwrap());
    assert!(div.line.jacobian_into(0.5, y, yp, 1.0, &mut j1).unwrap());
    j1.axpby(1.0, -1.0, &jy);
    (jy, j1)
}

fn check(form: DragForm, fired: &[usize], branch: Option<MaxwellBranch>) {
    let n = 40;
    let mut p = LineParams::unit_cells(n);
    p.right = RightEnd::Free(None);
    p.k = 1e-3.into();
    p.form = form;
    p.growth = Some(Arc::new(TanhGrowth::default()));
    p.maxwell = branch;
    if branch.is_some() {
        p.p_ext = Field::gaussian_bump(0.02, 0.05, 0.5, 0.2);
    }
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
    // a non-uniform state: stretched boundaries, grown cells, moving boundaries
    let dim = div.dim();
    let mut y = div.line.initial_state();
    let yp: Vec<f64> = (0..dim).map(|k| 0.01 * (k as f64).sin()).collect();
    for (k, v) in y.iter_mut().enumerate() {
        *v += 0.05 * (0.3 * k as f64).cos();
    }
    // a daughter adds `g`, `x` and, with a branch, `a_v`
    let new_dim = dim + (2 + usize::from(branch.is_some())) * fired.len();
    // the old pair at the event state, in storage of the new size (as a method's grown matrices)
    let (mut jy, mut jyp) = pair(&div, &y, &yp, new_dim);
    let action = div.handle_event(0.5, fired, &mut y, &yp).unwrap();
    assert_eq!(action, EventAction::Resized);
    assert_eq!(y.len(), new_dim);
    let mut yp_new = vec![0.0; new_dim];
    assert!(div.map_history(0.5, &yp, true, &mut yp_new));
    assert!(div
        .map_jacobian(0.5, &y, &yp_new, &mut jy, &mut jyp)
        .unwrap());
    let (fy, fyp) = pair(&div, &y, &yp_new, new_dim);
    let mut worst: f64 = 0.0;
    for i in 0..new_dim {
        for j in 0..new_dim {
            for (a, b) in [(&jy, &fy), (&jyp, &fyp)] {
                let d = (a.get(i, j) - b.get(i, j)).abs();
                worst = worst.max(d / b.get(i, j).abs().max(1.0));
            }
        }
    }
    assert!(
        worst <= 1e-13,
        "{form:?} {fired:?} {branch:?}: worst entry off by {worst:e}"
    );
}

#[test]
fn mapped_matrices_equal_the_jacobian_after_the_split() {
    // one cell, two far apart, two adjacent, the first and the last cell (event indices are
    // 0-based cells)
    let branches = [
        None,
        Some(MaxwellBranch::standard_linear_solid(0.7, 1.2).unwrap()),
        Some(MaxwellBranch::maxwell(0.9, 0.8).unwrap()),
    ];
    for fired in [&[17][..], &[5, 30], &[11, 12], &[0], &[39]] {
        for branch in branches {
            check(DragForm::Boundary, fired, branch);
            check(DragForm::Centre, fired, branch);
        }
    }
}
