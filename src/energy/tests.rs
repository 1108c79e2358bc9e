//! Unit tests of the AD plumbing and the sample laws (docs/model.md §5.1).

use super::*;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

fn laws() -> Vec<AnyEnergy> {
    vec![
        NeoHookean::new(1.3).unwrap().into(),
        MooneyRivlin::new(0.4, 0.25).unwrap().into(),
        Ogden::new(vec![(0.8, 3.0), (-0.05, -2.0)]).unwrap().into(),
        Hgo::new(0.9, 0.7, 1.5, 0.4).unwrap().into(),
        Gent::new(1.1, 2.0).unwrap().into(),
    ]
}

#[test]
fn small_strain_moduli() {
    for law in laws() {
        let mu = law.shear_modulus();
        let h = ad::line(&law, 1.0);
        assert!(
            rel(h.dsigma, 4.0 * mu) < 1e-13,
            "{}: {}",
            law.name(),
            h.dsigma
        );
        assert!(h.sigma.abs() < 1e-15);
        let s = ad::sheet(&law, 1.0, 1.0);
        assert!(rel(s.tangent[0][0], 4.0 * mu) < 1e-13, "{}", law.name());
        assert!(rel(s.tangent[0][1], 2.0 * mu) < 1e-13, "{}", law.name());
        assert!(rel(s.tangent[1][0], 2.0 * mu) < 1e-13, "{}", law.name());
        assert!(rel(s.tangent[1][1], 4.0 * mu) < 1e-13, "{}", law.name());
        let t = ad::shear(&law, 0.0);
        assert!(
            t.tau.abs() < 1e-15 && rel(t.dtau, mu) < 1e-13,
            "{}",
            law.name()
        );
    }
}

#[test]
fn neo_hookean_closed_forms_match_ad() {
    let law = NeoHookean::new(1.7).unwrap();
    for &a in &[0.3, 0.8, 1.0, 1.25, 3.0] {
        let (c, d) = (law.line(a), ad::line(&law, a));
        for (x, y) in [
            (c.sigma, d.sigma),
            (c.dsigma, d.dsigma),
            (c.pressure, d.pressure),
            (c.dpressure, d.dpressure),
        ] {
            assert!(
                rel(y, x) < 1e-12 || (x - y).abs() < 1e-15,
                "a={a}: {x} vs {y}"
            );
        }
        for &b in &[0.6, 1.0, 1.4] {
            let (c, d) = (law.sheet(a, b), ad::sheet(&law, a, b));
            assert!(rel(d.s11, c.s11) < 1e-12 || c.s11 == 0.0);
            assert!(rel(d.pressure, c.pressure) < 1e-12);
            for i in 0..2 {
                for k in 0..2 {
                    assert!(rel(d.tangent[i][k], c.tangent[i][k]) < 1e-12);
                }
            }
        }
        let (c, d) = (law.shear(a - 1.0), ad::shear(&law, a - 1.0));
        assert!((c.tau - d.tau).abs() < 1e-12 * c.tau.abs().max(1.0));
        assert!(rel(d.dtau, c.dtau) < 1e-12);
    }
}

#[test]
fn hgo_fibre_term_exactly_zero_when_compressed() {
    let law = Hgo::new(1.0, 5.0, 3.0, 0.0).unwrap();
    let nh = NeoHookean::new(1.0).unwrap();
    for &a in &[0.5, 0.9, 1.0] {
        assert_eq!(law.line(a), ad::line(&nh, a));
        assert_eq!(law.sheet(a, 1.0 / a), ad::sheet(&nh, a, 1.0 / a));
    }
    assert_eq!(law.fibre_energy(num_dual::Dual64::new(1.0, 1.0)).eps, 0.0);
}

#[test]
fn scaled_is_linear() {
    let base = Ogden::new(vec![(1.0, 4.0)]).unwrap();
    let s = Scaled::new(base.clone(), 2.5).unwrap();
    let (a, b) = (s.line(1.3), base.line(1.3));
    assert!(rel(a.dsigma, 2.5 * b.dsigma) < 1e-15);
    let d = ad::line(&s, 1.3);
    assert!(rel(d.sigma, a.sigma) < 1e-13 && rel(d.dpressure, a.dpressure) < 1e-13);
}
