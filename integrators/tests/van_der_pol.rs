//! Van der Pol with μ = 1000 (very stiff relaxation oscillations).
//!
//! * Scaled form of the "Test Set for IVP Solvers" (Mazzia & Magherini, problem VDPOL,
//!   ε = 1e-6 ⇔ μ = 1000): y(2) = (0.1706167732170483e1, −0.8928097010247975e0), computed there
//!   with RADAU5 at rtol = atol = 1.1e-18 in extended precision.
//! * Unscaled form on [0, 3000]: the period of the limit cycle is
//!   T ≈ (3 − 2 ln 2)·μ + 3·2.338·μ^{−1/3} (Hairer & Wanner I/II, asymptotic expansion with the
//!   first Airy zero correction) ≈ 1614.2 + 7.0 for μ = 1000; measured from the zero crossings
//!   of y1 located by events.

mod common;

use common::{opts, opts_bound, van_der_pol_scaled_bdf, VanDerPol};
use integrators::adapters::Ode;
use integrators::{MethodKind, Solver};

const VDPOL_REF: [f64; 2] = [0.1706167732170483e1, -0.8928097010247975e0];

/// With IDA's Newton test and with `newton_alpha_bound`.
#[test]
fn bdf_van_der_pol_scaled_matches_test_set_reference() {
    let cases = [(1e-6, 1e-3), (1e-9, 2e-6)];
    for ((rtol, bound), alpha_bound) in cases
        .iter()
        .map(|&c| (c, false))
        .chain(cases.iter().map(|&c| (c, true)))
    {
        let sol = van_der_pol_scaled_bdf(opts_bound(rtol, rtol, alpha_bound));
        let y = &sol.y[0];
        let err = (y[0] - VDPOL_REF[0])
            .abs()
            .max((y[1] - VDPOL_REF[1]).abs() / VDPOL_REF[1].abs());
        eprintln!(
            "rtol {rtol:e}, newton_alpha_bound {alpha_bound}: y = {y:?}, err {err:.3e}, {:?}",
            sol.stats
        );
        assert!(err < bound, "rtol {rtol}: error {err}");
    }
}

#[test]
fn bdf_van_der_pol_mu_1000_period_from_events() {
    let mu = 1000.0;
    let o = opts(1e-7, 1e-7);
    let mut p = Ode(VanDerPol {
        mu,
        crossings: Vec::new(),
    });
    let sol = Solver::new(MethodKind::Bdf, o)
        .solve(&mut p, 0.0, &[2.0, 0.0], &[3000.0])
        .unwrap();
    let c = &p.0.crossings;
    eprintln!("crossings {c:?}, {:?}", sol.stats);
    // y1 starts at 2, crosses zero near T/2 and again near T (each an event)
    assert_eq!(c.len(), 3, "{c:?}");
    assert_eq!(sol.events.len(), 3);
    let period = c[2] - c[0];
    let asymptotic = (3.0 - 2.0 * 2f64.ln()) * mu + 3.0 * 2.338_107 * mu.powf(-1.0 / 3.0);
    eprintln!("period {period}, asymptotic {asymptotic}");
    // the two-term asymptotic formula is accurate to O(ln μ / μ) relative
    assert!((period - asymptotic).abs() / asymptotic < 2e-3, "{period}");
    // half-periods are equal by symmetry
    let h1 = c[1] - c[0];
    let h2 = c[2] - c[1];
    assert!((h1 - h2).abs() < 1e-3 * h1, "{h1} {h2}");

    // a tight-tolerance run agrees on y(3000)
    let tight = opts(1e-10, 1e-10);
    let mut p2 = Ode(VanDerPol {
        mu,
        crossings: Vec::new(),
    });
    let s2 = Solver::new(MethodKind::Bdf, tight)
        .solve(&mut p2, 0.0, &[2.0, 0.0], &[3000.0])
        .unwrap();
    let d = (sol.y[0][0] - s2.y[0][0]).abs();
    eprintln!("y(3000) = {:?} vs tight {:?}", sol.y[0], s2.y[0]);
    assert!(d < 1e-3, "{d}");
    for (a, b) in p.0.crossings.iter().zip(&p2.0.crossings) {
        assert!((a - b).abs() < 0.05, "{a} {b}");
    }
}
