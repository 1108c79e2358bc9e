//! Tests of the ILU(0)-preconditioned BiCGStab solver (against the direct solver on grid matrices) and of its settings' validation.

use super::super::{Inner, LinearSolver, Matrix};
use super::*;
use crate::options::LinearSolverChoice;
use crate::pattern::Pattern;

/// Convection–diffusion on a `g × g` grid (5-point stencil, upwinded convection: a
/// non-symmetric M-matrix) plus `shift·I`, in natural ordering.
fn grid_matrix(g: usize, shift: f64) -> (Pattern, Matrix) {
    let id = |i: usize, j: usize| i * g + j;
    let mut e = Vec::new();
    for i in 0..g {
        for j in 0..g {
            let r = id(i, j);
            if i > 0 {
                e.push((r, id(i - 1, j)));
            }
            if i + 1 < g {
                e.push((r, id(i + 1, j)));
            }
            if j > 0 {
                e.push((r, id(i, j - 1)));
            }
            if j + 1 < g {
                e.push((r, id(i, j + 1)));
            }
        }
    }
    let n = g * g;
    let p = Pattern::Sparse(Arc::new(SparsityPattern::from_entries(n, &e)));
    let mut m = Matrix::zeros(n, &p);
    for i in 0..g {
        for j in 0..g {
            let r = id(i, j);
            m.add(r, r, 4.0 + 0.5 + shift);
            if i > 0 {
                m.add(r, id(i - 1, j), -1.5); // upwind side
            }
            if i + 1 < g {
                m.add(r, id(i + 1, j), -1.0);
            }
            if j > 0 {
                m.add(r, id(i, j - 1), -1.0);
            }
            if j + 1 < g {
                m.add(r, id(i, j + 1), -1.0);
            }
        }
    }
    (p, m)
}

fn iterative(rtol: f64, max_iters: usize) -> LinearSolverChoice {
    LinearSolverChoice::Iterative(IterativeSettings {
        rtol,
        max_iters,
        newton_factor: 0.0,
    })
}

#[test]
fn bicgstab_ilu0_solves_a_known_nonsymmetric_grid_system() {
    let g = 40;
    let n = g * g;
    let (p, m) = grid_matrix(g, 0.0);
    // manufactured solution x*, b = A x*
    let x_star: Vec<f64> = (0..n).map(|k| ((k as f64) * 0.37).sin() + 2.0).collect();
    let mut b = vec![0.0; n];
    m.mul_vec(&x_star, &mut b);
    let mut s = LinearSolver::with_choice(n, &p, iterative(1e-12, 500));
    s.factor(&m).unwrap();
    assert!(s.last_factor_was_symbolic());
    let mut x = b.clone();
    s.solve_in_place(&mut x);
    let err = x
        .iter()
        .zip(&x_star)
        .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
    assert!(err < 1e-9, "max error {err:e}");
    let c = s.krylov_counters();
    assert_eq!((c.solves, c.failures), (1, 0));
    // ILU(0) makes this a short iteration
    assert!(c.iterations >= 1 && c.iterations < 60, "{c:?}");
    // same result as the sparse direct LU
    let mut lu = LinearSolver::new(n, &p);
    lu.factor(&m).unwrap();
    let mut xd = b.clone();
    lu.solve_in_place(&mut xd);
    let diff = x
        .iter()
        .zip(&xd)
        .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
    assert!(diff < 1e-9, "iterative vs direct {diff:e}");
    // refactorisation with new values reuses the symbolic ILU structure
    let (_, m2) = grid_matrix(g, 3.0);
    s.factor(&m2).unwrap();
    assert!(!s.last_factor_was_symbolic());
    let mut b2 = vec![0.0; n];
    m2.mul_vec(&x_star, &mut b2);
    s.solve_in_place(&mut b2);
    let err2 = b2
        .iter()
        .zip(&x_star)
        .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
    assert!(err2 < 1e-9, "after refactor: {err2:e}");
    // a better-conditioned (shifted) matrix needs fewer iterations per solve
    let c2 = s.krylov_counters();
    assert!(c2.iterations - c.iterations <= c.iterations, "{c:?} {c2:?}");
}

#[test]
fn zero_rhs_is_solved_exactly() {
    let (p, m) = grid_matrix(5, 0.0);
    let mut s = LinearSolver::with_choice(25, &p, iterative(1e-10, 10));
    s.factor(&m).unwrap();
    let mut b = vec![0.0; 25];
    s.solve_in_place(&mut b);
    assert!(b.iter().all(|&v| v == 0.0), "{b:?}");
}

#[test]
fn non_convergence_answers_nan_and_is_counted() {
    let g = 30;
    let (p, m) = grid_matrix(g, 0.0);
    let n = g * g;
    let mut s = LinearSolver::with_choice(n, &p, iterative(1e-14, 1));
    s.factor(&m).unwrap();
    let mut b: Vec<f64> = (0..n).map(|k| (k as f64).cos()).collect();
    s.solve_in_place(&mut b);
    assert!(b.iter().all(|v| v.is_nan()));
    let c = s.krylov_counters();
    assert_eq!((c.solves, c.failures, c.iterations), (1, 1, 1));
}

#[test]
fn zero_pivot_and_non_finite_entries_name_a_column() {
    let (p, mut m) = grid_matrix(4, 0.0);
    let mut s = LinearSolver::with_choice(16, &p, iterative(1e-10, 50));
    m.set(0, 0, 0.0);
    // the first ILU(0) pivot is a₀₀ itself
    assert_eq!(s.factor(&m), Err(0));
    m.set(0, 0, 4.5);
    m.set(9, 10, f64::NAN);
    assert_eq!(s.factor(&m), Err(10));
    m.set(9, 10, -1.0);
    s.factor(&m).unwrap();
}

#[test]
fn csr_kernels_match_the_ilu_crate_and_the_matrix_product() {
    // M⁻¹A·v by the fused CSR sweeps vs `Matrix::mul_vec` then faer-precond's own ILU(0)
    // application, on a non-symmetric matrix with a non-uniform diagonal
    let g = 12;
    let n = g * g;
    let (p, mut m) = grid_matrix(g, 0.0);
    for i in 0..n {
        m.add(i, i, 0.1 * ((i as f64) * 0.7).sin());
    }
    let mut s = LinearSolver::with_choice(n, &p, iterative(1e-10, 100));
    s.factor(&m).unwrap();
    let Inner::Iterative(it) = &s.inner else {
        panic!("iterative solver expected")
    };
    let v: Vec<f64> = (0..n).map(|k| ((k as f64) * 1.3).cos()).collect();
    let mut ours = vec![0.0; n];
    it.apply_prec_a(&v, &mut ours, &[]);
    let mut reference = vec![0.0; n];
    m.mul_vec(&v, &mut reference);
    {
        use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
        use faer::matrix_free::Precond;
        let ilu = it.ilu.as_ref().unwrap();
        let mut mem = MemBuffer::new(StackReq::EMPTY);
        ilu.apply_in_place(
            faer::MatMut::from_column_major_slice_mut(&mut reference, n, 1),
            faer::Par::Seq,
            MemStack::new(&mut mem),
        );
    }
    let scale = reference.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let diff = ours
        .iter()
        .zip(&reference)
        .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
    // the factors are stored in f32 (unit roundoff 6e-8): agreement to single precision
    assert!(
        scale > 0.1 && diff < 1e-6 * scale,
        "{diff:e} (scale {scale})"
    );
}

#[test]
fn newton_tolerance_stops_early_and_still_meets_the_newton_test() {
    let g = 60;
    let n = g * g;
    let (p, m) = grid_matrix(g, 0.0);
    let x_star: Vec<f64> = (0..n)
        .map(|k| 1e-3 * (((k as f64) * 0.37).sin() + 2.0))
        .collect();
    let mut b = vec![0.0; n];
    m.mul_vec(&x_star, &mut b);
    // Newton weights of rtol 1e-6, atol 1e-8 at a state of size ~1
    let w = vec![1.0 / (1e-6 + 1e-8); n];
    let settings = |newton_factor| {
        LinearSolverChoice::Iterative(IterativeSettings {
            rtol: 1e-12,
            max_iters: 500,
            newton_factor,
        })
    };
    for norm in [ErrorNorm::Rms, ErrorNorm::Max] {
        let tol = LinearTolerance {
            weights: &w,
            norm,
            target: 0.33,
        };
        let mut tight = LinearSolver::with_choice(n, &p, settings(0.0));
        tight.factor(&m).unwrap();
        let mut x_tight = b.clone();
        // newton_factor = 0: the tolerance is ignored, rtol alone decides
        tight.solve_in_place_to(&mut x_tight, Some(&tol));
        let mut inexact = LinearSolver::with_choice(n, &p, settings(0.05));
        inexact.factor(&m).unwrap();
        let mut x = b.clone();
        inexact.solve_in_place_to(&mut x, Some(&tol));
        let (ct, ci) = (tight.krylov_counters(), inexact.krylov_counters());
        assert_eq!((ct.failures, ci.failures), (0, 0));
        assert!(
            ci.iterations < ct.iterations,
            "inexact {ci:?} vs tight {ct:?}"
        );
        let err: Vec<f64> = x.iter().zip(&x_star).map(|(a, b)| a - b).collect();
        let err_w = norm.of(&err, &w);
        // The solve stops when the *preconditioned residual* is ≤ 0.05·0.33 in the weighted
        // norm; that estimates the error only up to the conditioning of M⁻¹A, which is poor
        // for this unshifted grid operator: the measured error is 0.109 (RMS) / 0.234 (max),
        // 6.6× / 14× the estimate. What Newton needs is an error inside its own tolerance 0.33.
        assert!(err_w < 0.33, "{norm:?}: weighted error {err_w:e}");
        // the tight solve reaches the manufactured solution
        let err_t: Vec<f64> = x_tight.iter().zip(&x_star).map(|(a, b)| a - b).collect();
        assert!(norm.of(&err_t, &w) < 1e-3, "{norm:?}");
    }
}

#[test]
fn non_sparse_patterns_fall_back_to_direct() {
    let p = Pattern::Banded { lower: 1, upper: 1 };
    let mut m = Matrix::zeros(3, &p);
    for i in 0..3 {
        m.add(i, i, 2.0);
    }
    let mut s = LinearSolver::with_choice(3, &p, iterative(1e-8, 10));
    s.factor(&m).unwrap();
    let mut b = vec![2.0; 3];
    s.solve_in_place(&mut b);
    assert_eq!(b, vec![1.0; 3]);
    assert_eq!(s.krylov_counters(), KrylovCounters::default());
}

mod option_tests {
    use crate::options::{IterativeSettings, LinearSolverChoice, Options};

    #[test]
    fn iterative_settings_are_validated_by_field() {
        for (rtol, max_iters, newton_factor, needle) in [
            (0.0, 10, 0.05, "linear_solver.rtol"),
            (1.0, 10, 0.05, "linear_solver.rtol"),
            (f64::NAN, 10, 0.05, "linear_solver.rtol"),
            (1e-6, 0, 0.05, "linear_solver.max_iters"),
            (1e-6, 10, -0.1, "linear_solver.newton_factor"),
            (1e-6, 10, 1.0, "linear_solver.newton_factor"),
            (1e-6, 10, f64::NAN, "linear_solver.newton_factor"),
        ] {
            let o = Options {
                linear_solver: LinearSolverChoice::Iterative(IterativeSettings {
                    rtol,
                    max_iters,
                    newton_factor,
                }),
                ..Options::default()
            };
            let e = o.validate().unwrap_err();
            assert!(e.to_string().contains(needle), "{e}");
        }
        assert_eq!(Options::default().linear_solver, LinearSolverChoice::Direct);
    }
}
