//! AD responses (`celltissue::energy::ad`) against the closed forms of docs/model.md §1.3–§1.5, to
//! 1e-12 relative, for every sample law (docs/model.md §5.1).

use celltissue::energy::ad;
use celltissue::{
    Hgo, LineResponse, MooneyRivlin, NeoHookean, Ogden, ShearResponse, SheetResponse, StrainEnergy,
};
use std::f64::consts::PI;

const STRETCHES: [f64; 7] = [0.5, 0.8, 0.95, 1.0, 1.05, 1.3, 2.0];
const SHEARS: [f64; 6] = [-1.5, -0.3, 0.0, 0.2, 0.9, 2.5];

/// `|x − y| ≤ 1e-12·max(|x|, |y|)`, with a 1e-14 absolute floor for values that vanish.
fn close(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-12 * x.abs().max(y.abs()) + 1e-14
}

fn check_line(what: &str, got: LineResponse, want: LineResponse) {
    let pairs = [
        ("sigma", got.sigma, want.sigma),
        ("dsigma", got.dsigma, want.dsigma),
        ("pressure", got.pressure, want.pressure),
        ("dpressure", got.dpressure, want.dpressure),
    ];
    for (name, g, w) in pairs {
        assert!(
            close(g, w),
            "{what}: line {name}: AD {g} vs closed form {w}"
        );
    }
}

fn check_sheet(what: &str, got: SheetResponse, want: SheetResponse) {
    let mut pairs = vec![
        ("s11", got.s11, want.s11),
        ("s22", got.s22, want.s22),
        ("pressure", got.pressure, want.pressure),
    ];
    for i in 0..2 {
        for k in 0..2 {
            pairs.push(("tangent", got.tangent[i][k], want.tangent[i][k]));
        }
    }
    for (name, g, w) in pairs {
        assert!(
            close(g, w),
            "{what}: sheet {name}: AD {g} vs closed form {w}"
        );
    }
}

fn check_shear(what: &str, got: ShearResponse, want: ShearResponse) {
    assert!(
        close(got.tau, want.tau),
        "{what}: tau {} vs {}",
        got.tau,
        want.tau
    );
    assert!(
        close(got.dtau, want.dtau),
        "{what}: dtau {} vs {}",
        got.dtau,
        want.dtau
    );
}

/// Principal stretches of simple shear `T`: `(s, λ₊, λ₋)`, `s = √(1 + T²/4)`.
fn shear_stretches(t: f64) -> (f64, f64, f64) {
    let s = (1.0 + 0.25 * t * t).sqrt();
    (s, s + 0.5 * t, s - 0.5 * t)
}

#[test]
fn neo_hookean() {
    let mu = 1.7;
    let law = NeoHookean::new(mu).unwrap();
    for a in STRETCHES {
        let want = LineResponse {
            sigma: mu * (a * a - a.powi(-2)),
            dsigma: 2.0 * mu * (a + a.powi(-3)),
            pressure: mu * a.powi(-2),
            dpressure: -2.0 * mu * a.powi(-3),
        };
        check_line(&format!("NH a={a}"), ad::line(&law, a), want);
        check_line(&format!("NH override a={a}"), law.line(a), want);
        for b in STRETCHES {
            let l3 = 1.0 / (a * b);
            let want = SheetResponse {
                s11: mu * (a * a - l3 * l3),
                s22: mu * (b * b - l3 * l3),
                pressure: mu * l3 * l3,
                tangent: [
                    [
                        2.0 * mu * (a + a.powi(-3) * b.powi(-2)),
                        2.0 * mu * a.powi(-2) * b.powi(-3),
                    ],
                    [
                        2.0 * mu * a.powi(-3) * b.powi(-2),
                        2.0 * mu * (b + a.powi(-2) * b.powi(-3)),
                    ],
                ],
            };
            check_sheet(&format!("NH ({a},{b})"), ad::sheet(&law, a, b), want);
            check_sheet(&format!("NH override ({a},{b})"), law.sheet(a, b), want);
        }
    }
    for t in SHEARS {
        let want = ShearResponse {
            tau: mu * t,
            dtau: mu,
        };
        check_shear(&format!("NH T={t}"), ad::shear(&law, t), want);
        check_shear(&format!("NH override T={t}"), law.shear(t), want);
    }
}

#[test]
fn mooney_rivlin() {
    let (c1, c2) = (0.35, 0.4);
    let law = MooneyRivlin::new(c1, c2).unwrap();
    let s = c1 + c2;
    for a in STRETCHES {
        let want = LineResponse {
            sigma: 2.0 * s * (a * a - a.powi(-2)),
            dsigma: 4.0 * s * (a + a.powi(-3)),
            pressure: 2.0 * c1 * a.powi(-2) + 2.0 * c2 * (1.0 + a.powi(-2)),
            dpressure: -4.0 * s * a.powi(-3),
        };
        check_line(&format!("MR a={a}"), law.line(a), want);
        for b in STRETCHES {
            let l3s = (a * b).powi(-2);
            let (g1, g2) = (c1 + c2 * b * b, c1 + c2 * a * a);
            let want = SheetResponse {
                s11: 2.0 * (a * a - l3s) * g1,
                s22: 2.0 * (b * b - l3s) * g2,
                pressure: 2.0 * l3s * (c1 + c2 * (a * a + b * b)),
                tangent: [
                    [
                        4.0 * (a + l3s / a) * g1,
                        4.0 * l3s / b * g1 + 4.0 * c2 * b * (a * a - l3s),
                    ],
                    [
                        4.0 * l3s / a * g2 + 4.0 * c2 * a * (b * b - l3s),
                        4.0 * (b + l3s / b) * g2,
                    ],
                ],
            };
            check_sheet(&format!("MR ({a},{b})"), law.sheet(a, b), want);
        }
    }
    for t in SHEARS {
        let want = ShearResponse {
            tau: 2.0 * s * t,
            dtau: 2.0 * s,
        };
        check_shear(&format!("MR T={t}"), law.shear(t), want);
    }
}

#[test]
fn ogden() {
    let terms = vec![(0.9, 2.5), (-0.08, -1.7), (0.02, 5.0)];
    let law = Ogden::new(terms.clone()).unwrap();
    let sum = |f: &dyn Fn(f64, f64) -> f64| terms.iter().map(|&(m, al)| f(m, al)).sum::<f64>();
    for a in STRETCHES {
        let want = LineResponse {
            sigma: sum(&|m, al| m * (a.powf(al) - a.powf(-al))),
            dsigma: sum(&|m, al| m * al * (a.powf(al - 1.0) + a.powf(-al - 1.0))),
            pressure: sum(&|m, al| m * a.powf(-al)),
            dpressure: sum(&|m, al| -m * al * a.powf(-al - 1.0)),
        };
        check_line(&format!("Ogden a={a}"), law.line(a), want);
        for b in STRETCHES {
            let l3 = 1.0 / (a * b);
            let want = SheetResponse {
                s11: sum(&|m, al| m * (a.powf(al) - l3.powf(al))),
                s22: sum(&|m, al| m * (b.powf(al) - l3.powf(al))),
                pressure: sum(&|m, al| m * l3.powf(al)),
                tangent: [
                    [
                        sum(&|m, al| m * al * (a.powf(al - 1.0) + l3.powf(al) / a)),
                        sum(&|m, al| m * al * l3.powf(al) / b),
                    ],
                    [
                        sum(&|m, al| m * al * l3.powf(al) / a),
                        sum(&|m, al| m * al * (b.powf(al - 1.0) + l3.powf(al) / b)),
                    ],
                ],
            };
            check_sheet(&format!("Ogden ({a},{b})"), law.sheet(a, b), want);
        }
    }
    for t in SHEARS {
        let (s, lp, lm) = shear_stretches(t);
        let want = ShearResponse {
            tau: sum(&|m, al| m * (lp.powf(al) - lm.powf(al)) / (2.0 * s)),
            dtau: sum(&|m, al| {
                m * (al * (lp.powf(al) + lm.powf(al)) / (4.0 * s * s)
                    - (lp.powf(al) - lm.powf(al)) * t / (8.0 * s.powi(3)))
            }),
        };
        check_shear(&format!("Ogden T={t}"), law.shear(t), want);
    }
}

#[test]
fn ogden_shear_keeps_its_digits_at_large_amounts_of_shear() {
    // A term with α < 0 reads λ₋ ≈ 1/T. As the difference √(1 + T²/4) − T/2 it lost about T²ε
    // of its value (1e-8 at T = 10⁴), and a shear column whose top cell softens without bound
    // failed its Newton iterations on that noise. With α = −2, λ₊⁻² + λ₋⁻² = λ₊² + λ₋² = T² + 2
    // (λ₊λ₋ = 1, λ₊ − λ₋ = T), so μ = −1 gives Ŵ = T²/2: τ = T and dτ/dT = 1 exactly, with
    // no principal stretch in the answer.
    let law = Ogden::new(vec![(-1.0, -2.0)]).unwrap();
    for t in [1e2, 1e4, 1e6, -1e4] {
        let want = ShearResponse { tau: t, dtau: 1.0 };
        check_shear(&format!("Ogden α = −2, T={t}"), law.shear(t), want);
        check_shear(&format!("Ogden α = −2 AD, T={t}"), ad::shear(&law, t), want);
    }
}

/// `(ψ₄, dψ₄/dI₄)` of the HGO fibre term; zero for `I₄ ≤ 1`.
fn psi4(k1: f64, k2: f64, i4: f64) -> (f64, f64) {
    let e = i4 - 1.0;
    if e <= 0.0 {
        return (0.0, 0.0);
    }
    let x = (k2 * e * e).exp();
    (k1 * e * x, k1 * (1.0 + 2.0 * k2 * e * e) * x)
}

#[test]
fn hgo_all_angles_both_sides_of_i4_equal_one() {
    let (c, k1, k2) = (0.8, 0.6, 1.2);
    for theta in [0.0, PI / 6.0, PI / 4.0, PI / 3.0] {
        let law = Hgo::new(c, k1, k2, theta).unwrap();
        let (co, si) = (theta.cos().powi(2), theta.sin().powi(2));
        let (mut active, mut inactive) = (0, 0);
        let mut count = |i4: f64| {
            if i4 > 1.0 {
                active += 1
            } else {
                inactive += 1
            }
        };
        for a in STRETCHES {
            // docs/model.md §1.3 line closed form.
            let i4 = a * a * co + a.powi(-2) * si;
            count(i4);
            let (p4, dp4) = psi4(k1, k2, i4);
            let (f, df) = (2.0 * p4, 2.0 * dp4);
            let q = a * a * co - a.powi(-2) * si;
            let di4 = 2.0 * a * co - 2.0 * a.powi(-3) * si;
            let dq = 2.0 * a * co + 2.0 * a.powi(-3) * si;
            let want = LineResponse {
                sigma: c * (a * a - a.powi(-2)) + f * q,
                dsigma: 2.0 * c * (a + a.powi(-3)) + df * di4 * q + f * dq,
                pressure: (c + f * si) * a.powi(-2),
                dpressure: -2.0 * (c + f * si) * a.powi(-3) + df * di4 * si * a.powi(-2),
            };
            check_line(&format!("HGO θ={theta} a={a}"), law.line(a), want);
            for b in STRETCHES {
                let l3s = (a * b).powi(-2);
                let i4 = a * a * co + b * b * si;
                count(i4);
                let (p4, dp4) = psi4(k1, k2, i4);
                let want = SheetResponse {
                    s11: c * (a * a - l3s) + 2.0 * p4 * a * a * co,
                    s22: c * (b * b - l3s) + 2.0 * p4 * b * b * si,
                    pressure: c * l3s,
                    tangent: [
                        [
                            2.0 * c * (a + l3s / a)
                                + 4.0 * dp4 * a.powi(3) * co * co
                                + 4.0 * p4 * a * co,
                            2.0 * c * l3s / b + 4.0 * dp4 * b * si * a * a * co,
                        ],
                        [
                            2.0 * c * l3s / a + 4.0 * dp4 * a * co * b * b * si,
                            2.0 * c * (b + l3s / b)
                                + 4.0 * dp4 * b.powi(3) * si * si
                                + 4.0 * p4 * b * si,
                        ],
                    ],
                };
                check_sheet(&format!("HGO θ={theta} ({a},{b})"), law.sheet(a, b), want);
            }
        }
        for t in SHEARS {
            // docs/model.md §1.5: the shear carries the fibre to (cos θ + T sin θ, sin θ), so
            // I₄ = 1 + T sin 2θ + T² sin²θ and I₁ = 3 + T²
            let i4 = 1.0 + t * (2.0 * theta).sin() + t * t * si;
            count(i4);
            let di4 = (2.0 * theta).sin() + 2.0 * t * si;
            let (p4, dp4) = psi4(k1, k2, i4);
            let want = ShearResponse {
                tau: c * t + p4 * di4,
                dtau: c + dp4 * di4 * di4 + 2.0 * p4 * si,
            };
            check_shear(&format!("HGO θ={theta} T={t}"), law.shear(t), want);
            let p = law.shear_pressure(t);
            assert!(close(p, c + 2.0 * p4 * si), "HGO θ={theta} T={t}: p {p}");
        }
        assert!(
            active > 5 && inactive > 5,
            "θ={theta}: {active} active, {inactive} inactive"
        );
    }
}
