//! Tests of the Radau IIA (order 5) method: its constants and its solutions.

use super::constants::radau_a;
use super::*;

#[test]
fn eigen_decomposition_of_a_inverse_matches_published_constants() {
    let k = Consts::new();
    // T⁻¹ · A⁻¹ · T = [[γ̂, 0, 0], [0, α̂, −β̂], [0, β̂, α̂]]
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            for p in 0..3 {
                for q in 0..3 {
                    *v += k.ti[i][p] * k.a_inv[p][q] * k.t[q][j];
                }
            }
        }
    }
    let expect = [
        [k.gamma, 0.0, 0.0],
        [0.0, k.alpha, -k.beta],
        [0.0, k.beta, k.alpha],
    ];
    for i in 0..3 {
        for j in 0..3 {
            assert!(
                (m[i][j] - expect[i][j]).abs() < 1e-12,
                "({i},{j}): {} vs {}",
                m[i][j],
                expect[i][j]
            );
        }
    }
    // T·T⁻¹ = I
    for i in 0..3 {
        for j in 0..3 {
            let v: f64 = (0..3).map(|p| k.t[i][p] * k.ti[p][j]).sum();
            assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14);
        }
    }
}

#[test]
fn butcher_matrix_satisfies_simplifying_assumptions() {
    // C(3): Σ_j a_ij c_j^(q−1) = c_i^q / q for q = 1, 2, 3 (stage order 3).
    let a = radau_a();
    let c = Consts::new().c;
    for q in 1..=3 {
        for i in 0..3 {
            let lhs: f64 = (0..3).map(|j| a[i][j] * c[j].powi(q - 1)).sum();
            assert!((lhs - c[i].powi(q) / q as f64).abs() < 1e-14);
        }
    }
}

#[test]
fn error_weights_helpers() {
    use crate::options::ErrorNorm;
    assert_eq!(ErrorNorm::Rms.of(&[], &[]), 0.0);
    assert_eq!(ErrorNorm::Max.of(&[], &[]), 0.0);
    assert!(ErrorNorm::Max.of(&[1.0, f64::NAN], &[1.0, 1.0]).is_nan());
    assert_eq!(worst(&[1.0, -5.0, 2.0], &[1.0, 1.0, 1.0]), Some(1));
    assert!(step_too_small(0.0, 1.0, 0.0));
    assert!(!step_too_small(1e-3, 1.0, 0.0));
}
