//! Changing a [`Line`](celltissue::line::Line)'s per-cell fields through the public API:
//! the residual sees the change. The residual caches which fields are uniform
//! (and then reads one value instead of the vector); a public change that left that cache
//! stale would be ignored silently. Each edited line is compared with a line built afresh
//! with the same fields, which has no history to go stale.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::Field;
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::{FieldsMut, Line};
use celltissue::{CellArray, NeoHookean};

fn params(n: usize) -> LineParams {
    let mut p = LineParams::unit_cells(n);
    p.k = Field::Constant(0.3);
    p.eta = Field::Constant(0.7);
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: n as f64,
        k1: 0.1,
        t_ramp: 1.0,
    });
    p
}

fn residual(line: &Line<NeoHookean>) -> Vec<f64> {
    let y: Vec<f64> = line
        .initial_state()
        .iter()
        .enumerate()
        .map(|(i, x)| x * (1.0 - 0.01 * (i % 3) as f64))
        .collect();
    let yp: Vec<f64> = (0..y.len()).map(|i| 0.02 * i as f64 - 0.05).collect();
    let mut r = vec![0.0; y.len()];
    line.residual(0.3, &y, &yp, &mut r).unwrap();
    r
}

/// One edit of a line's fields.
type Edit = fn(FieldsMut<'_>);

fn build(p: &LineParams) -> Line<NeoHookean> {
    discrete(NeoHookean::new(1.0).unwrap(), p).unwrap()
}

#[test]
fn editing_mu_eta_l0_and_k_changes_the_residual() {
    let n = 6;
    let uniform = build(&params(n));
    let r0 = residual(&uniform);
    let per_cell = |v: Vec<f64>| Field::PerCell { values: v };

    // μ of cell 3
    let mut edited = uniform.clone();
    edited.edit_fields(|f| f.mu[2] = 2.0).unwrap();
    let mut p = params(n);
    p.mu = per_cell(vec![1.0, 1.0, 2.0, 1.0, 1.0, 1.0]);
    let r_mu = residual(&edited);
    assert_ne!(r_mu, r0, "the μ edit was ignored");
    assert_eq!(r_mu, residual(&build(&p)));

    // η of cell 1
    let mut edited = uniform.clone();
    edited.edit_fields(|f| f.eta[0] = 0.0).unwrap();
    let mut p = params(n);
    p.eta = per_cell(vec![0.0, 0.7, 0.7, 0.7, 0.7, 0.7]);
    let r_eta = residual(&edited);
    assert_ne!(r_eta, r0, "the η edit was ignored");
    assert_eq!(r_eta, residual(&build(&p)));

    // face drag of boundary 2
    let mut edited = uniform.clone();
    edited.edit_fields(|f| f.k_face[2] = 0.9).unwrap();
    let r_k = residual(&edited);
    assert_ne!(r_k, r0, "the K edit was ignored");
    // only the row of boundary 2 (unknown 1) changes, by ΔK·ẋ₂
    let yp2 = 0.02 * 1.0 - 0.05;
    for (i, (a, b)) in r_k.iter().zip(&r0).enumerate() {
        if i == 1 {
            assert!((a - b - 0.6 * yp2).abs() < 1e-15, "{a} vs {b}");
        } else {
            assert_eq!(a, b, "row {i}");
        }
    }

    // reference lengths: L₀ of cells 1 and 2 swapped to 0.5 and 1.5 (Σ L₀ unchanged)
    let mut edited = uniform.clone();
    edited
        .edit_fields(|f| {
            f.l0[0] = 0.5;
            f.l0[1] = 1.5;
        })
        .unwrap();
    assert_eq!(edited.l0_total(), 6.0);
    assert_ne!(residual(&edited), r0, "the L₀ edit was ignored");
}

#[test]
fn a_bad_edit_is_rejected_naming_the_field_and_leaves_the_line_unchanged() {
    let mut line = build(&params(4));
    let before = residual(&line);
    let cases: [(Edit, &str); 4] = [
        (|f| f.mu[1] = 0.0, "mu[1]"),
        (|f| f.eta[3] = f64::NAN, "eta[3]"),
        (|f| f.l0[0] = -1.0, "L0[0]"),
        (|f| f.k_face[4] = f64::INFINITY, "K (face)[4]"),
    ];
    for (edit, key) in cases {
        let e = line.edit_fields(edit).unwrap_err().to_string();
        assert!(e.contains(key), "{e}");
        assert_eq!(residual(&line), before);
        assert_eq!(line.cells().mu, vec![1.0; 4]);
    }
}
