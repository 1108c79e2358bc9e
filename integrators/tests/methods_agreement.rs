//! All stiff methods (BDF, TR-BDF2, Radau IIA) agree on a nonlinear banded reaction–diffusion
//! problem, through the public driver ([`Solver`]) and its dense output; Dormand–Prince joins on a
//! non-stiff problem. The reference is Radau IIA at a tolerance 10⁵ times tighter.

mod methods_common;

use integrators::{MethodKind, Solver};
use methods_common::*;

fn solve(
    kind: MethodKind,
    rtol: f64,
    atol: f64,
    p: &mut ReactionDiffusion,
    t_out: &[f64],
) -> (Vec<Vec<f64>>, integrators::Stats) {
    let y0 = p.y0();
    let sol = Solver::new(kind, opts(rtol, atol))
        .solve(p, 0.0, &y0, t_out)
        .unwrap_or_else(|e| panic!("{kind}: {e}"));
    (sol.y, sol.stats)
}

#[test]
fn stiff_methods_agree_on_banded_reaction_diffusion() {
    let mut p = ReactionDiffusion { n: 100, d: 0.1 };
    let t_out = [0.5, 1.0, 2.0];
    let (reference, _) = solve(MethodKind::Radau, 1e-11, 1e-13, &mut p, &t_out);
    let (rtol, atol) = (1e-6, 1e-8);
    for kind in [MethodKind::Bdf, MethodKind::Esdirk, MethodKind::Radau] {
        let (y, stats) = solve(kind, rtol, atol, &mut p, &t_out);
        let mut worst: f64 = 0.0;
        for (a, b) in y.iter().zip(&reference) {
            worst = worst.max(max_err(a, b));
        }
        eprintln!(
            "{kind}: max deviation from reference {worst:e} ({} steps, {} jac evals)",
            stats.steps, stats.jacobian_evals
        );
        // |u| ≤ 1 here: a global error of at most 100·rtol is what per-step control at rtol
        // delivers over a few hundred steps (see the per-method tests for the step bounds).
        assert!(worst < 100.0 * rtol, "{kind}: {worst:e}");
    }
}

#[test]
fn all_methods_agree_on_a_nonstiff_ode_through_the_driver() {
    let t_out = [0.5, 1.0, 2.0, 4.0];
    for kind in MethodKind::ALL {
        let sol = Solver::new(kind, opts(1e-8, 1e-10))
            .solve(&mut Nonlinear2, 0.0, &[1.0, 1.0], &t_out)
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        let mut worst: f64 = 0.0;
        for (t, y) in sol.t.iter().zip(&sol.y) {
            worst = worst.max(max_err(y, &Nonlinear2.solution(*t)));
        }
        eprintln!(
            "{kind}: max error at outputs {worst:e} ({} steps)",
            sol.stats.steps
        );
        assert!(worst < 100.0 * 1e-8 * 3.0, "{kind}: {worst:e}");
    }
}

#[test]
fn radau_through_the_driver_on_the_banded_heat_equation() {
    let mut p = Heat { n: 200 };
    let y0 = p.solution(0.0);
    let t_out = [0.01, 0.02, 0.05, 0.1];
    let sol = Solver::new(MethodKind::Radau, opts(1e-8, 1e-10))
        .solve(&mut p, 0.0, &y0, &t_out)
        .unwrap();
    // Steps end at the outputs (`Options::land_on_outputs`, Radau's default); interpolated
    // from the collocation polynomial they would carry its error, of the stage order (3), not
    // the step order (5): allow 10·rtol (|u| ≤ 1).
    for (t, y) in sol.t.iter().zip(&sol.y) {
        let e = max_err(y, &p.solution(*t));
        eprintln!("heat via driver, t = {t}: error {e:e}");
        assert!(e < 1e-7, "t = {t}: {e:e}");
    }
}
