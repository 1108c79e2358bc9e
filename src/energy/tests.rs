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

/// HGO's energy at a full deformation gradient, written out independently of the law's code:
/// `C = FᵀF`, `W = c/2 (tr C − 3) + k₁/(2k₂)[exp(k₂E²) − 1]` for `E = aᵀCa − 1 > 0`.
fn hgo_at_gradient(p: (f64, f64, f64, f64), f: [[f64; 3]; 3]) -> f64 {
    let (c, k1, k2, theta) = p;
    let mut cg = [[0.0; 3]; 3];
    for (i, row) in cg.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| f[k][i] * f[k][j]).sum();
        }
    }
    let a = [theta.cos(), theta.sin(), 0.0];
    let i4: f64 = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| a[i] * cg[i][j] * a[j])
        .sum();
    let e = i4 - 1.0;
    let fibre = if e > 0.0 {
        k1 / (2.0 * k2) * ((k2 * e * e).exp() - 1.0)
    } else {
        0.0
    };
    0.5 * c * (cg[0][0] + cg[1][1] + cg[2][2] - 3.0) + fibre
}

/// Simple shear `[[1, T, 0], [0, s, 0], [0, 0, 1]]`.
fn sheared(t: f64, s: f64) -> [[f64; 3]; 3] {
    [[1.0, t, 0.0], [0.0, s, 0.0], [0.0, 0.0, 1.0]]
}

#[test]
fn hgo_shear_follows_the_fibre_through_the_deformation_gradient() {
    // τ = dW/dT, dτ/dT and p = ∂W/∂F₂₂ by central differences of W(F) at the full gradient
    // (step 10⁻⁵: their truncation error reaches 2e-8 relative where E = 4, exp(k₂E²) = e²⁴).
    let h = 1e-5;
    for theta in [
        0.0,
        0.4,
        -0.4,
        std::f64::consts::FRAC_PI_4,
        1.2,
        std::f64::consts::FRAC_PI_2,
    ] {
        let p = (0.9, 0.7, 1.5, theta);
        let law = Hgo::new(p.0, p.1, p.2, p.3).unwrap();
        let w = |t: f64, s: f64| hgo_at_gradient(p, sheared(t, s));
        let tau = |t: f64| (w(t + h, 1.0) - w(t - h, 1.0)) / (2.0 * h);
        for t in [-1.5, -0.3, 0.2, 0.9, 2.0] {
            let r = law.shear(t);
            let scale = r.tau.abs().max(1.0);
            assert!(
                (r.tau - tau(t)).abs() < 1e-7 * scale,
                "θ={theta} T={t}: {} vs {}",
                r.tau,
                tau(t)
            );
            let e = 2.0 * t * theta.sin() * theta.cos() + (t * theta.sin()).powi(2);
            if e.abs() > 1e-2 {
                let dtau = (tau(t + h) - tau(t - h)) / (2.0 * h);
                assert!(
                    (r.dtau - dtau).abs() < 1e-5 * r.dtau.abs().max(1.0),
                    "θ={theta} T={t}"
                );
            }
            let pressure = (w(t, 1.0 + h) - w(t, 1.0 - h)) / (2.0 * h);
            assert!(
                (law.shear_pressure(t) - pressure).abs() < 1e-7 * scale,
                "θ={theta} T={t}"
            );
        }
    }
    // The principal-stretch reading, right for isotropic laws, is wrong for the fibre.
    let law = Hgo::new(0.5, 1.0, 1.0, 0.5).unwrap();
    assert!((ad::shear(&law, 0.5).tau - law.shear(0.5).tau).abs() > 0.1);
}

#[test]
fn isotropic_shear_pressure_is_the_gradient_of_w_in_f22() {
    // For a law of the principal stretches, W at the singular values of F = [[1, T], [0, s]]
    // differentiated in s at s = 1 is the pressure the default computes from B's eigenvectors.
    let h = 1e-6;
    for law in laws().into_iter().filter(|l| l.name() != "hgo") {
        assert!(law.shear_is_exact(), "{}", law.name());
        for t in [-1.2, 0.3, 1.0, 2.5] {
            if law.name() == "gent" && t * t >= 1.9 {
                continue; // past Gent's lock (I₁ − 3 = T² < jm = 2)
            }
            let w = |s: f64| {
                let (tr, det) = (1.0 + t * t + s * s, s);
                let root = (tr * tr - 4.0 * det * det).sqrt();
                let (a, b) = (((tr + root) / 2.0).sqrt(), ((tr - root) / 2.0).sqrt());
                law.energy([a, b, 1.0])
            };
            let pressure = (w(1.0 + h) - w(1.0 - h)) / (2.0 * h);
            let p = law.shear_pressure(t);
            assert!(
                (p - pressure).abs() < 1e-7 * p.abs().max(1.0),
                "{} T={t}: {p} vs {pressure}",
                law.name()
            );
        }
    }
}

#[test]
fn a_law_reading_its_axes_is_not_exact_in_shear_unless_it_says_how() {
    let axial = Expression::new("mu/2*(I1 - 3) + k*(l1 - 1)^2", [("mu", 1.0), ("k", 0.5)]).unwrap();
    assert!(!axial.shear_is_exact());
    assert!(!AnyEnergy::from(axial.clone()).shear_is_exact());
    assert!(!Scaled::new(axial, 2.0).unwrap().shear_is_exact());
    // written symmetric in l1, l2, the same kind of term is a law of the principal stretches
    let symmetric = Expression::new(
        "mu/2*(I1 - 3) + k*((l1 - 1)^2 + (l2 - 1)^2)",
        [("mu", 1.0), ("k", 0.5)],
    )
    .unwrap();
    assert!(symmetric.shear_is_exact());
    // the fibre law follows its fibre through the shear itself
    assert!(Hgo::new(0.9, 0.7, 1.5, 0.4).unwrap().shear_is_exact());
    assert!(AnyEnergy::from(Hgo::new(0.9, 0.7, 1.5, 0.4).unwrap()).shear_is_exact());
}
