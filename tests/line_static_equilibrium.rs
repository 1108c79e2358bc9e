//! Static equilibrium of the line (MODEL.md §5.2): N = 100, l = 90, uniform and Gaussian
//! (2.82) μ, sampled at cell centres (default) or integer points; the bracketing solve and the
//! Newton solve of the static banded problem agree; long-time limits of dynamic runs match.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::{Field, Sampling};
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::static_solve::{
    invert_stretch, neo_hookean_stretch, static_equilibrium, static_newton,
};
use celltissue::NeoHookean;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn params(mu: Field, sampling: Sampling) -> LineParams {
    let mut p = LineParams::unit_cells(100);
    p.mu = mu;
    p.sampling = sampling;
    p.right = RightEnd::Prescribed(Ramp::Constant(90.0));
    p
}

fn gaussian() -> Field {
    Field::gaussian_bump(1.0, 1.0, 0.5, 0.1)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn uniform_mu_matches_exact_solution() {
    let line = discrete(nh(), &params(Field::Constant(1.0), Sampling::Centres)).unwrap();
    let s = static_equilibrium(&line, 90.0).unwrap();
    // Ref: S = −0.424568, max p = 1.234568 = 1/(1−k₁)², min λ = 0.9
    assert!(rel(s.stress, -0.424568) < 1e-6, "{}", s.stress);
    assert!((s.max_pressure() - 1.0 / 0.81).abs() < 1e-12);
    assert!((s.min_stretch() - 0.9).abs() < 1e-12);
    assert!((s.x[100] - 90.0).abs() < 1e-10);
}

#[test]
fn gaussian_mu_at_cell_centres() {
    let line = discrete(nh(), &params(gaussian(), Sampling::Centres)).unwrap();
    let s = static_equilibrium(&line, 90.0).unwrap();
    // Ref: S = −0.502154, max p = 2.265536, min λ = 0.883155
    assert!(rel(s.stress, -0.502154) < 2e-6, "S = {}", s.stress);
    assert!(
        rel(s.max_pressure(), 2.265536) < 1e-6,
        "{}",
        s.max_pressure()
    );
    assert!(rel(s.min_stretch(), 0.883155) < 2e-6, "{}", s.min_stretch());
}

#[test]
fn gaussian_mu_at_integer_points_reproduces_thesis_2_267() {
    let line = discrete(nh(), &params(gaussian(), Sampling::IntegerPoints)).unwrap();
    let s = static_equilibrium(&line, 90.0).unwrap();
    // Ref: S = −0.502154, max p = 2.266775 (thesis ≈ 2.267), min λ = 0.883154
    assert!(rel(s.stress, -0.502154) < 2e-6, "S = {}", s.stress);
    assert!(
        rel(s.max_pressure(), 2.266775) < 1e-6,
        "{}",
        s.max_pressure()
    );
    assert!(rel(s.min_stretch(), 0.883154) < 2e-6, "{}", s.min_stretch());
}

#[test]
fn newton_inversion_equals_closed_form() {
    for &s in &[-5.0, -0.5, 0.0, 0.3, 10.0] {
        let a = neo_hookean_stretch(s);
        let b = invert_stretch(&nh(), 1.0, s).unwrap();
        assert!((a - b).abs() < 1e-14 * a, "{s}: {a} vs {b}");
    }
}

#[test]
fn static_newton_agrees_with_bracketing_solve() {
    for sampling in [Sampling::Centres, Sampling::IntegerPoints] {
        let line = discrete(nh(), &params(gaussian(), sampling)).unwrap();
        let s = static_equilibrium(&line, 90.0).unwrap();
        let y = static_newton(&line, 0.0, None, 1e-13).unwrap();
        let err = (1..100)
            .map(|j| (y[j - 1] - s.x[j]).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-10, "max |x_newton − x_bracket| = {err:e}");
    }
}

#[test]
fn random_heterogeneous_mu_static_newton_and_bracket_agree() {
    let mu = Field::Random {
        low: 0.5,
        high: 3.0,
        seed: 42,
    };
    let line = discrete(nh(), &params(mu, Sampling::Centres)).unwrap();
    let s = static_equilibrium(&line, 90.0).unwrap();
    for j in 0..100 {
        let sig = line.cells.mu[j] * (s.lambda[j].powi(2) - s.lambda[j].powi(-2));
        assert!((sig - s.stress).abs() < 1e-12, "cell {} σ = {sig}", j + 1);
    }
    let y = static_newton(&line, 0.0, None, 1e-13).unwrap();
    let err = (1..100)
        .map(|j| (y[j - 1] - s.x[j]).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-10, "{err:e}");
}
