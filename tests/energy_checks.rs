//! Independent checks of the constitutive layer (docs/model.md §1, §5.1): central finite differences
//! of `W` (no AD), small-strain moduli, the HGO one-sided tangent, monotonicity, law
//! equivalences and constructor errors.

// 2×2 tangents are compared entry by entry; index loops read best here.
#![allow(clippy::needless_range_loop)]

use celltissue::energy::ad;
use celltissue::{
    AnyEnergy, EnergyError, Hgo, MooneyRivlin, NeoHookean, Ogden, Scaled, StrainEnergy,
};
use std::f64::consts::PI;

fn rel(x: f64, y: f64) -> f64 {
    (x - y).abs() / x.abs().max(y.abs()).max(1e-12)
}

/// Difference relative to `max(|x|, |y|, 1)`: for FD checks of values that may vanish (the
/// sample laws have moduli of order 1).
fn near(x: f64, y: f64) -> f64 {
    (x - y).abs() / x.abs().max(y.abs()).max(1.0)
}

fn sample_laws() -> Vec<AnyEnergy> {
    vec![
        NeoHookean::new(1.0).unwrap().into(),
        NeoHookean::new(0.37).unwrap().into(),
        MooneyRivlin::new(0.3, 0.2).unwrap().into(),
        MooneyRivlin::new(1.0, 0.0).unwrap().into(),
        Ogden::new(vec![(1.0, 2.0)]).unwrap().into(),
        Ogden::new(vec![(0.6, 3.0), (-0.1, -2.0)]).unwrap().into(),
        Ogden::new(vec![(1.2, 0.5), (0.01, 8.0), (-0.02, -4.0)])
            .unwrap()
            .into(),
        Hgo::new(1.0, 0.5, 1.0, 0.0).unwrap().into(),
        Hgo::new(0.7, 2.0, 0.3, PI / 6.0).unwrap().into(),
        Hgo::new(1.0, 1.0, 0.0, PI / 3.0).unwrap().into(),
        Hgo::new(1.0, 0.3, 0.8, PI / 4.0).unwrap().into(),
    ]
}

/// `W` in plain `f64`.
fn w<E: StrainEnergy>(law: &E, l1: f64, l2: f64, l3: f64) -> f64 {
    law.energy([l1, l2, l3])
}

/// Fourth-order central first and second differences of `f` at `x` with step `h`.
fn d12(f: impl Fn(f64) -> f64, x: f64, h: f64) -> (f64, f64) {
    let (m2, m1, z, p1, p2) = (f(x - 2.0 * h), f(x - h), f(x), f(x + h), f(x + 2.0 * h));
    let d1 = (m2 - 8.0 * m1 + 8.0 * p1 - p2) / (12.0 * h);
    let d2 = (-m2 + 16.0 * m1 - 30.0 * z + 16.0 * p1 - p2) / (12.0 * h * h);
    (d1, d2)
}

/// Line responses from fourth-order central differences of `W(a, 1/a, 1)` and of `W₂`.
fn fd_line<E: StrainEnergy>(law: &E, a: f64) -> [f64; 4] {
    let h = 1e-3 * a;
    let (dw, d2w) = d12(|a| w(law, a, 1.0 / a, 1.0), a, h);
    let p = |a: f64| d12(|l2| w(law, a, l2, 1.0), 1.0 / a, 1e-3 / a).0 / a;
    [a * dw, dw + a * d2w, p(a), d12(p, a, h).0]
}

/// Does a stretch pair sit within `d` of the HGO switch `I₄ = 1`? (FD is invalid across it.)
fn near_kink(law: &AnyEnergy, l1: f64, l2: f64, d: f64) -> bool {
    match law {
        AnyEnergy::Hgo(h) => (h.i4(l1, l2) - 1.0).abs() < d,
        _ => false,
    }
}

#[test]
fn line_matches_central_differences_of_w() {
    for law in sample_laws() {
        for a in [0.4, 0.7, 0.9, 1.1, 1.5, 2.2] {
            if near_kink(&law, a, 1.0 / a, 1e-2) {
                continue;
            }
            let r = law.line(a);
            let fd = fd_line(&law, a);
            let got = [r.sigma, r.dsigma, r.pressure, r.dpressure];
            // FD round-off grows with |W| (stiff HGO fibres at large stretch): ~1e-16·|W|/h².
            let noise = 1e-8 * w(&law, a, 1.0 / a, 1.0).abs();
            for k in 0..4 {
                assert!(
                    (got[k] - fd[k]).abs() <= 2e-6 * got[k].abs().max(fd[k].abs()) + noise,
                    "{law:?} a={a} component {k}: {} vs FD {}",
                    got[k],
                    fd[k]
                );
            }
        }
    }
}

#[test]
fn sheet_matches_central_differences_of_w() {
    let h = 1e-4;
    for law in sample_laws() {
        let wh = |l1: f64, l2: f64| w(&law, l1, l2, 1.0 / (l1 * l2));
        let s11 = |l1: f64, l2: f64| l1 * (wh(l1 + h, l2) - wh(l1 - h, l2)) / (2.0 * h);
        let s22 = |l1: f64, l2: f64| l2 * (wh(l1, l2 + h) - wh(l1, l2 - h)) / (2.0 * h);
        for (l1, l2) in [(0.8, 1.1), (1.3, 0.9), (1.2, 1.2), (0.7, 0.75), (1.6, 0.5)] {
            if near_kink(&law, l1, l2, 2e-2) {
                continue;
            }
            let r = law.sheet(l1, l2);
            let l3 = 1.0 / (l1 * l2);
            let p = l3 * (w(&law, l1, l2, l3 + h) - w(&law, l1, l2, l3 - h)) / (2.0 * h);
            let g = 1e-3;
            let t = [
                [
                    (s11(l1 + g, l2) - s11(l1 - g, l2)) / (2.0 * g),
                    (s11(l1, l2 + g) - s11(l1, l2 - g)) / (2.0 * g),
                ],
                [
                    (s22(l1 + g, l2) - s22(l1 - g, l2)) / (2.0 * g),
                    (s22(l1, l2 + g) - s22(l1, l2 - g)) / (2.0 * g),
                ],
            ];
            let what = format!("{law:?} ({l1},{l2})");
            assert!(near(r.s11, s11(l1, l2)) < 1e-6, "{what} s11");
            assert!(near(r.s22, s22(l1, l2)) < 1e-6, "{what} s22");
            assert!(near(r.pressure, p) < 1e-6, "{what} p {} vs {p}", r.pressure);
            for i in 0..2 {
                for k in 0..2 {
                    assert!(
                        near(r.tangent[i][k], t[i][k]) < 1e-4,
                        "{what} tangent[{i}][{k}] {} vs FD {}",
                        r.tangent[i][k],
                        t[i][k]
                    );
                }
            }
        }
    }
}

/// `W` at the simple shear `[[1, T, 0], [0, s, 0], [0, 0, 1]]`: for a law of the principal
/// stretches, `W` at the singular values of `[[1, T], [0, s]]`; for HGO, its fibre
/// `a = (cos θ, sin θ)` carried to `Fa = (cos θ + T sin θ, s sin θ)` (docs/model.md §1.5).
/// Returns `W` and whether the fibre invariant is within `d` of its kink.
fn sheared_w(law: &AnyEnergy, t: f64, s: f64, d: f64) -> (f64, bool) {
    match law {
        AnyEnergy::Hgo(h) => {
            let (c, k1, k2, th) = h.params();
            let i1 = 2.0 + t * t + s * s;
            let e = (th.cos() + t * th.sin()).powi(2) + (s * th.sin()).powi(2) - 1.0;
            let fibre = match (e > 0.0, k2 == 0.0) {
                (false, _) => 0.0,
                (true, true) => 0.5 * k1 * e * e,
                (true, false) => k1 / (2.0 * k2) * (k2 * e * e).exp_m1(),
            };
            (0.5 * c * (i1 - 3.0) + fibre, e.abs() < d)
        }
        _ => {
            let (tr, det) = (1.0 + t * t + s * s, s);
            let root = (tr * tr - 4.0 * det * det).sqrt();
            let (a, b) = (((tr + root) / 2.0).sqrt(), ((tr - root) / 2.0).sqrt());
            (w(law, a, b, 1.0), false)
        }
    }
}

#[test]
fn shear_matches_central_differences_of_w() {
    let wh = |law: &AnyEnergy, t: f64| sheared_w(law, t, 1.0, 0.0).0;
    for law in sample_laws() {
        for t in [-1.2f64, -0.4, 0.3, 0.8, 2.0] {
            if sheared_w(&law, t, 1.0, 1e-2).1 {
                continue;
            }
            // the pressure balancing σ₂₂ = 0 is ∂W/∂F₂₂
            let h = 1e-6;
            let p = (sheared_w(&law, t, 1.0 + h, 0.0).0 - sheared_w(&law, t, 1.0 - h, 0.0).0)
                / (2.0 * h);
            assert!(
                near(law.shear_pressure(t), p) < 1e-7,
                "{law:?} T={t} p {} vs {p}",
                law.shear_pressure(t)
            );
            let (h1, h2) = (1e-5, 1e-4);
            let tau = (wh(&law, t + h1) - wh(&law, t - h1)) / (2.0 * h1);
            let dtau = (wh(&law, t + h2) - 2.0 * wh(&law, t) + wh(&law, t - h2)) / (h2 * h2);
            let r = law.shear(t);
            assert!(
                rel(r.tau, tau) < 1e-7,
                "{law:?} T={t} tau {} vs {tau}",
                r.tau
            );
            assert!(
                rel(r.dtau, dtau) < 1e-5,
                "{law:?} T={t} dtau {} vs {dtau}",
                r.dtau
            );
        }
    }
}

#[test]
fn small_strain_limits_every_law() {
    for law in sample_laws() {
        let mu = law.shear_modulus();
        let l = law.line(1.0);
        assert_eq!(l.sigma, 0.0, "{law:?}");
        assert!(
            rel(l.dsigma, 4.0 * mu) < 1e-14,
            "{law:?}: dσ/da(1) = {}",
            l.dsigma
        );
        let s = law.sheet(1.0, 1.0);
        let want = [[4.0 * mu, 2.0 * mu], [2.0 * mu, 4.0 * mu]];
        for i in 0..2 {
            for k in 0..2 {
                assert!(rel(s.tangent[i][k], want[i][k]) < 1e-14, "{law:?}");
            }
        }
        let t = law.shear(0.0);
        assert_eq!(t.tau, 0.0);
        assert!(rel(t.dtau, mu) < 1e-14, "{law:?}: τ'(0) = {}", t.dtau);
    }
    // Ogden: dσ/da(1) = 2 Σ μ_p α_p.
    let og = Ogden::new(vec![(0.6, 3.0), (-0.1, -2.0)]).unwrap();
    assert!(rel(og.line(1.0).dsigma, 2.0 * (1.8 + 0.2)) < 1e-14);
}

#[test]
fn hgo_one_sided_tangent_at_identity() {
    let (c, k1) = (0.9, 0.7);
    for theta in [0.0, PI / 6.0, PI / 4.0, PI / 3.0] {
        let law = Hgo::new(c, k1, 1.3, theta).unwrap();
        let tensile = 4.0 * c + 4.0 * k1 * (2.0 * theta).cos().powi(2);
        // The fibres stretch for a > 1 if θ < π/4 and for a < 1 if θ > π/4 (both at π/4).
        let s = if theta < PI / 4.0 - 1e-12 { 1.0 } else { -1.0 };
        let h = 1e-7;
        let on = law.line(1.0 + s * h).dsigma;
        let off = law.line(1.0 - s * h).dsigma;
        assert!(
            (on - tensile).abs() < 1e-5,
            "θ={theta}: tensile side {on} vs {tensile}"
        );
        if theta != PI / 4.0 {
            assert!(
                (off - 4.0 * c).abs() < 1e-5,
                "θ={theta}: inactive side {off}"
            );
        }
        // Independent one-sided finite difference of σ_el.
        let fd = s * (law.line(1.0 + s * h).sigma - law.line(1.0).sigma) / h;
        assert!(
            (fd - tensile).abs() < 1e-5,
            "θ={theta}: FD {fd} vs {tensile}"
        );
        // At a = 1 itself (I₄ = 1) the fibres are off.
        assert!(rel(law.line(1.0).dsigma, 4.0 * c) < 1e-14);
    }
}

#[test]
fn hgo_fibre_term_exactly_zero_for_i4_at_most_one() {
    let law = Hgo::new(1.0, 3.0, 2.0, PI / 6.0).unwrap();
    let matrix = NeoHookean::new(1.0).unwrap();
    let mut checked = 0;
    for &l1 in &[0.5, 0.8, 0.95, 1.0] {
        for &l2 in &[0.6, 0.9, 1.0] {
            if law.i4(l1, l2) > 1.0 {
                continue;
            }
            checked += 1;
            assert_eq!(law.fibre_energy(law.i4(l1, l2)), 0.0);
            let e = law.energy([l1, l2, 1.0 / (l1 * l2)]);
            let m = matrix.energy([l1, l2, 1.0 / (l1 * l2)]);
            assert_eq!(e, m);
            assert_eq!(law.sheet(l1, l2), ad::sheet(&matrix, l1, l2));
        }
    }
    assert!(checked >= 8);
    for a in [0.8, 0.9, 1.0] {
        // θ = π/6: I₄ = ¾a² + ¼a⁻² ≤ 1 for a ∈ [1/√3, 1].
        assert!(law.i4(a, 1.0 / a) <= 1.0);
        assert_eq!(law.line(a), ad::line(&matrix, a));
    }
}

#[test]
fn mooney_rivlin_equals_neo_hookean_in_line_only() {
    let (c1, c2) = (0.3, 0.45);
    let mr = MooneyRivlin::new(c1, c2).unwrap();
    let nh = NeoHookean::new(2.0 * (c1 + c2)).unwrap();
    for a in [0.5, 0.9, 1.4, 2.0] {
        let (x, y) = (mr.line(a), nh.line(a));
        assert!(rel(x.sigma, y.sigma) < 1e-13 && rel(x.dsigma, y.dsigma) < 1e-13);
        // σ_el agrees; the pressure does not: p_el = 2C₁a⁻² + 2C₂(1 + a⁻²) = μa⁻² + 2C₂.
        assert!(rel(x.pressure, y.pressure + 2.0 * c2) < 1e-13);
        assert!(rel(x.dpressure, y.dpressure) < 1e-13);
    }
    let (x, y) = (mr.sheet(1.5, 1.0), nh.sheet(1.5, 1.0));
    // σ₁₁ = 2(λ₁² − λ₃²)(C₁ + C₂λ₂²) = 1.5·(2.25 − 1/2.25) vs μ(λ₁² − λ₃²) = 1.5·(2.25 − 1/2.25)
    // at λ₂ = 1, so compare at λ₂ ≠ 1 as well:
    assert!(rel(x.s11, y.s11) < 1e-13);
    let (x, y) = (mr.sheet(1.5, 1.3), nh.sheet(1.5, 1.3));
    assert!(rel(x.s11, y.s11) > 0.1, "MR {} vs NH {}", x.s11, y.s11);
    assert!(rel(x.tangent[0][1], y.tangent[0][1]) > 0.1);
}

#[test]
fn ogden_one_term_alpha_two_is_neo_hookean() {
    let og = Ogden::new(vec![(1.3, 2.0)]).unwrap();
    let nh = NeoHookean::new(1.3).unwrap();
    assert_eq!(og.shear_modulus(), 1.3);
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()) + 1e-14;
    for a in [0.4, 0.9, 1.0, 1.7] {
        let (x, y) = (og.line(a), nh.line(a));
        assert!(close(x.sigma, y.sigma) && close(x.dsigma, y.dsigma));
        assert!(close(x.pressure, y.pressure) && close(x.dpressure, y.dpressure));
        for b in [0.8, 1.0, 1.25] {
            let (x, y) = (og.sheet(a, b), nh.sheet(a, b));
            assert!(close(x.s11, y.s11) && close(x.s22, y.s22) && close(x.pressure, y.pressure));
            for i in 0..2 {
                for k in 0..2 {
                    assert!(close(x.tangent[i][k], y.tangent[i][k]));
                }
            }
        }
        let (x, y) = (og.shear(a - 1.0), nh.shear(a - 1.0));
        assert!(close(x.tau, y.tau) && close(x.dtau, y.dtau));
    }
}

#[test]
fn line_stress_strictly_increasing_on_grid() {
    for law in sample_laws() {
        let mut prev = f64::NEG_INFINITY;
        for i in 0..=400 {
            let a = 0.25 + 2.75 * i as f64 / 400.0;
            let r = law.line(a);
            assert!(r.sigma > prev, "{law:?}: σ_el not increasing at a={a}");
            assert!(r.dsigma > 0.0, "{law:?}: dσ_el/da = {} at a={a}", r.dsigma);
            prev = r.sigma;
        }
    }
}

#[test]
fn scaled_responses_scale_linearly() {
    for law in sample_laws() {
        let s = Scaled::new(law.clone(), 2.5).unwrap();
        assert!(rel(s.shear_modulus(), 2.5 * law.shear_modulus()) < 1e-15);
        let (x, y) = (s.line(1.3), law.line(1.3));
        assert!(rel(x.sigma, 2.5 * y.sigma) < 1e-15 && rel(x.dpressure, 2.5 * y.dpressure) < 1e-15);
        // The AD of the scaled energy agrees with the scaled responses.
        let z = ad::line(&s, 1.3);
        assert!(rel(z.dsigma, x.dsigma) < 1e-12);
        let (x, y) = (s.sheet(1.2, 0.9), law.sheet(1.2, 0.9));
        assert!(rel(x.tangent[1][0], 2.5 * y.tangent[1][0]) < 1e-15);
        assert!(rel(s.shear(0.4).tau, 2.5 * law.shear(0.4).tau) < 1e-15);
    }
}

#[test]
fn constructor_errors_name_the_field() {
    let msg = |e: EnergyError| e.to_string();
    assert_eq!(
        msg(NeoHookean::new(-1.0).unwrap_err()),
        "mu = -1 must be finite and > 0"
    );
    assert_eq!(
        msg(NeoHookean::new(f64::NAN).unwrap_err()),
        "mu = NaN must be finite and > 0"
    );
    assert_eq!(
        msg(MooneyRivlin::new(-0.5, 1.0).unwrap_err()),
        "c1 = -0.5 must be finite and >= 0"
    );
    assert_eq!(
        msg(MooneyRivlin::new(0.0, 0.0).unwrap_err()),
        "c1 + c2 = 0 must be finite and > 0"
    );
    assert_eq!(
        msg(Ogden::new(vec![(1.0, 2.0), (-1.0, 3.0)]).unwrap_err()),
        "terms[1].mu_p*alpha_p = -3 must be > 0"
    );
    assert_eq!(
        msg(Ogden::new(vec![(1.0, f64::INFINITY)]).unwrap_err()),
        "terms[0].alpha_p = inf must be finite"
    );
    assert_eq!(Ogden::new(vec![]).unwrap_err(), EnergyError::EmptyOgden);
    assert_eq!(
        msg(Hgo::new(0.0, 1.0, 1.0, 0.0).unwrap_err()),
        "c = 0 must be finite and > 0"
    );
    assert_eq!(
        msg(Hgo::new(1.0, 1.0, -2.0, 0.0).unwrap_err()),
        "k2 = -2 must be finite and >= 0"
    );
    assert_eq!(
        msg(Hgo::new(1.0, 1.0, 1.0, f64::NAN).unwrap_err()),
        "theta = NaN must be finite"
    );
    let nh = NeoHookean::new(1.0).unwrap();
    assert_eq!(
        msg(Scaled::new(nh, 0.0).unwrap_err()),
        "factor = 0 must be finite and > 0"
    );
}
