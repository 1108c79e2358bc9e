//! Static checks of the uniaxial sheet and shear column residuals (docs/model.md §4.1, §4.4):
//! exact steady states have zero residual for any law, the declared sparse pattern contains the
//! AD Jacobian (which matches finite differences), non-positive stretches are rejected naming
//! the unknown, and the cell-centre form is the edge form in other variables.

use celltissue::array::{ArrayProblem, CellArray};
use celltissue::cell::{Field, MaxwellBranch, TanhGrowth};
use celltissue::sheet::exact::{sheet_free_steady, sheet_periodic_steady};
use celltissue::sheet::shear::{ShearCellCentre, ShearColumn, ShearParams};
use celltissue::sheet::uniaxial::{SheetGrowth, SheetParams, UniaxialSheet};
use celltissue::sheet::{GrowthDirections, RightEdge, TopBoundary};
use celltissue::{MooneyRivlin, NeoHookean, StrainEnergy};
use integrators::{Pattern, Problem, ResidualError};
use std::sync::Arc;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

/// State with uniform stretches `(l1, l2)` (positions `x_b = j h_X l1`, `y_b = k h_Y l2`).
fn uniform_state<E: StrainEnergy>(s: &UniaxialSheet<E>, l1: f64, l2: f64) -> Vec<f64> {
    let (n, m) = s.grid();
    let (hx, hy) = s.spacing();
    let mut y = vec![0.0; s.dim()];
    let periodic = s.params().top == TopBoundary::Periodic;
    for j in 1..=n {
        let ks: Vec<usize> = if periodic {
            (0..m).collect()
        } else {
            (1..=m).collect()
        };
        for k in ks {
            y[s.iy(j, k)] = k as f64 * hy * l2;
        }
        if j < n {
            for k in 1..=m {
                y[s.ix(j, k)] = j as f64 * hx * l1;
            }
        }
    }
    y
}

fn max_abs_residual<A: CellArray>(a: &A, t: f64, y: &[f64]) -> f64 {
    let mut r = vec![0.0; a.dim()];
    let yp = vec![0.0; a.dim()];
    a.residual(t, y, &yp, &mut r).unwrap();
    r.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

#[test]
fn exact_free_top_steady_state_has_zero_residual_neo_hookean_and_mooney_rivlin() {
    let p = SheetParams::default();
    let s = sheet_free_steady(&nh(), 0.1).unwrap();
    assert!((s.stretch[0] - 0.9).abs() < 1e-15);
    assert!((s.stretch[1] - 1.054093).abs() < 5e-7);
    assert!((s.stretch[2] - 1.054093).abs() < 5e-7);
    assert!((s.pressure - 1.111111).abs() < 5e-7);
    let sheet = UniaxialSheet::discrete(nh(), &p).unwrap();
    let y = uniform_state(&sheet, s.stretch[0], s.stretch[1]);
    assert!(max_abs_residual(&sheet, 800.0, &y) < 1e-14);

    let mr = MooneyRivlin::new(0.3, 0.2).unwrap();
    let s = sheet_free_steady(&mr, 0.1).unwrap();
    assert!(s.s22.abs() < 1e-14);
    let sheet = UniaxialSheet::discrete(mr, &p).unwrap();
    let y = uniform_state(&sheet, s.stretch[0], s.stretch[1]);
    assert!(max_abs_residual(&sheet, 800.0, &y) < 1e-14);
}

#[test]
fn exact_periodic_steady_state_has_zero_residual() {
    let p = SheetParams {
        top: TopBoundary::Periodic,
        ..Default::default()
    };
    let s = sheet_periodic_steady(&nh(), 0.1).unwrap();
    assert!((s.pressure - 1.234568).abs() < 5e-7);
    let sheet = UniaxialSheet::discrete(nh(), &p).unwrap();
    let y = uniform_state(&sheet, 0.9, 1.0);
    assert!(max_abs_residual(&sheet, 800.0, &y) < 1e-14);
}

/// Full Jacobian `∂F/∂y + c ∂F/∂ẏ` by AD, column by column (small problems only).
fn ad_jacobian<A: CellArray>(
    p: &mut ArrayProblem<A>,
    t: f64,
    y: &[f64],
    yp: &[f64],
    c: f64,
) -> Vec<Vec<f64>> {
    let n = y.len();
    let mut cols = Vec::new();
    let mut r = vec![0.0; n];
    for j in 0..n {
        let mut v = vec![0.0; n];
        v[j] = 1.0;
        let mut dr = vec![0.0; n];
        assert!(p.directional(t, y, yp, &v, c, &mut r, &mut dr).unwrap());
        cols.push(dr);
    }
    cols
}

fn perturbed_state(sheet: &UniaxialSheet<NeoHookean>) -> Vec<f64> {
    let mut y = sheet.initial_state();
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.03 * ((i as f64) * 1.7).sin();
    }
    y
}

#[test]
fn declared_sparse_pattern_contains_ad_jacobian_which_matches_finite_differences() {
    // plain cells, then standard-linear-solid and Maxwell cells (viscous stretches in the
    // state) under a Gaussian external pressure,
    let branches = [
        None,
        Some(MaxwellBranch::standard_linear_solid(0.7, 1.3).unwrap()),
        Some(MaxwellBranch::maxwell(0.7, 1.3).unwrap()),
    ];
    // each with and without Kelvin–Voigt viscosity (rates of the neighbouring faces)
    for (top, m_exp, branch, eta) in [TopBoundary::Free, TopBoundary::Periodic]
        .into_iter()
        .flat_map(|top| [0.0, 1.0].map(|m| (top, m)))
        .flat_map(|(top, m)| branches.map(|b| (top, m, b)))
        .flat_map(|(top, m, b)| [0.0, 0.8].map(|eta| (top, m, b, eta)))
    {
        {
            let p = SheetParams {
                cells_x: 4,
                cells_y: 3,
                drag_exponent: m_exp,
                top,
                branch,
                eta,
                external_pressure: if branch.is_some() {
                    Field::gaussian_bump(0.1, 0.5, 0.4, 0.2)
                } else {
                    Field::Constant(0.0)
                },
                // growing cells with a free side x = l, with and without a branch
                right: if m_exp == 1.0 {
                    RightEdge::Free
                } else {
                    RightEdge::Prescribed
                },
                growth: (m_exp == 1.0).then(|| SheetGrowth {
                    law: Arc::new(TanhGrowth::default()),
                    directions: GrowthDirections::Both,
                }),
                ..Default::default()
            };
            let sheet = UniaxialSheet::discrete(nh(), &p).unwrap();
            let n = sheet.dim();
            let pattern = sheet.pattern();
            assert!(matches!(pattern, Pattern::Sparse(_)));
            let y = perturbed_state(&sheet);
            let yp: Vec<f64> = (0..n).map(|i| 0.1 * (i as f64).cos()).collect();
            let c = 2.5;
            let mut prob = ArrayProblem::new(sheet);
            let jac = ad_jacobian(&mut prob, 0.7, &y, &yp, c);
            let mut r0 = vec![0.0; n];
            prob.residual(0.7, &y, &yp, &mut r0).unwrap();
            for (j, col) in jac.iter().enumerate() {
                // central finite differences of F(y + e v, yp + c e v)
                let e = 1e-6;
                let mut rp = vec![0.0; n];
                let mut rm = vec![0.0; n];
                let mut yy = y.clone();
                let mut yyp = yp.clone();
                yy[j] += e;
                yyp[j] += c * e;
                prob.residual(0.7, &yy, &yyp, &mut rp).unwrap();
                yy[j] -= 2.0 * e;
                yyp[j] -= 2.0 * c * e;
                prob.residual(0.7, &yy, &yyp, &mut rm).unwrap();
                for i in 0..n {
                    let fd = (rp[i] - rm[i]) / (2.0 * e);
                    // the central difference's error scales with the entry: with η the rate
                    // entries reach c·η·(stiffness) ≈ 50, where it measured 2e-7 (4e-9 relative)
                    assert!(
                        (fd - col[i]).abs() < 1e-7 * col[i].abs().max(1.0),
                        "{top:?} m={m_exp} {branch:?} η={eta} ({i},{j}): AD {} FD {fd}",
                        col[i]
                    );
                    if col[i] != 0.0 {
                        assert!(
                            pattern.contains(i, j),
                            "{top:?} entry ({i},{j}) missing from pattern"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn sheet_pattern_is_block_tridiagonal_and_sparse() {
    let p = SheetParams {
        cells_x: 30,
        cells_y: 20,
        ..Default::default()
    };
    let sheet = UniaxialSheet::discrete(nh(), &p).unwrap();
    let n = sheet.dim();
    assert_eq!(n, (2 * 30 - 1) * 20);
    let Pattern::Sparse(sp) = sheet.pattern() else {
        panic!("sheet must declare a sparse pattern")
    };
    // block size 2m: every entry lies within one block of the diagonal block
    let b = 2 * 20;
    for j in 0..n {
        for &i in sp.column(j) {
            assert!(
                (i / b).abs_diff(j / b) <= 1,
                "({i},{j}) outside block tridiagonal"
            );
        }
    }
    // at most 9 entries per column (x-face: 3 x + 4 y neighbours; y-face: 4 x + 3 y)
    assert!(sp.nnz() <= 9 * n, "nnz {}", sp.nnz());
    let colours = sheet.pattern().colour_count(n);
    assert!(colours <= 20, "colours {colours}");
}

#[test]
fn non_positive_stretch_is_recoverable_and_names_the_unknown() {
    let p = SheetParams {
        cells_x: 4,
        cells_y: 3,
        ..Default::default()
    };
    let sheet = UniaxialSheet::discrete(nh(), &p).unwrap();
    let mut y = sheet.initial_state();
    // push x_b(2,2) behind x_b(1,2): cell (2,2) gets λ₁ < 0
    y[sheet.ix(2, 2)] = 0.5;
    let yp = vec![0.0; y.len()];
    let mut r = vec![0.0; y.len()];
    match sheet.residual(0.0, &y, &yp, &mut r) {
        Err(ResidualError::Recoverable { reason, component }) => {
            assert_eq!(component, Some(sheet.ix(2, 2)), "{reason}");
            assert!(reason.contains("λ₁"), "{reason}");
        }
        other => panic!("expected a recoverable error, got {other:?}"),
    }
    let mut y = sheet.initial_state();
    y[sheet.iy(3, 2)] = 0.9; // below y_b(3,1) = 1
    match sheet.residual(0.0, &y, &yp, &mut r) {
        Err(ResidualError::Recoverable { component, .. }) => {
            assert_eq!(component, Some(sheet.iy(3, 2)))
        }
        other => panic!("expected a recoverable error, got {other:?}"),
    }
}

#[test]
fn cell_centre_residual_is_edge_residual_in_centre_variables() {
    // With x_c = (x_{e,k−1} + x_{e,k})/2 and K_th = 2K, F_cc(x_c, ẋ_c) = r_{k−1} + r_k of the edge
    // form (the induction of docs/model.md §4.5), for any state.
    let p = ShearParams::default();
    let edge = ShearColumn::discrete(nh(), &p).unwrap();
    let cc = ShearCellCentre::new(nh(), &p).unwrap();
    let m = p.cells;
    let xe: Vec<f64> = (1..=m)
        .map(|k| 0.3 * k as f64 + 0.1 * (k as f64).sin())
        .collect();
    let xed: Vec<f64> = (1..=m).map(|k| 0.2 * (k as f64).cos()).collect();
    let centre = |v: &[f64]| -> Vec<f64> {
        (0..m)
            .map(|k| 0.5 * (if k == 0 { 0.0 } else { v[k - 1] } + v[k]))
            .collect()
    };
    let (xc, xcd) = (centre(&xe), centre(&xed));
    let mut re = vec![0.0; m];
    let mut rc = vec![0.0; m];
    edge.residual(0.0, &xe, &xed, &mut re).unwrap();
    cc.residual(0.0, &xc, &xcd, &mut rc).unwrap();
    for k in 0..m {
        let expect = re[k] + if k == 0 { 0.0 } else { re[k - 1] };
        assert!(
            (rc[k] - expect).abs() < 1e-13,
            "k={k}: {} vs {expect}",
            rc[k]
        );
    }
    // edges are recovered from centres by the alternating sums
    let back = ShearCellCentre::<NeoHookean>::edges(&xc);
    for k in 0..m {
        assert!((back[k + 1] - xe[k]).abs() < 1e-13);
    }
}
