//! Work statistics pinned for canonical problems, so that a cost regression (more steps,
//! residual calls, Jacobians or factorisations for the same answer) fails a test.
//!
//! HOW TO UPDATE: these numbers are exact for the current BDF and System implementation. After
//! an intentional algorithm change, run
//! `cargo test -p integrators --release --test stats_pinned -- --nocapture`, check that the
//! accuracy tests (robertson, van_der_pol, heat_banded, ...) still pass and that the new counts
//! are not worse for a reason you cannot explain, then paste the printed `Stats` below and
//! say why in the commit message.

mod common;

use common::{opts, opts_bound};
use common::{van_der_pol_scaled_bdf, Heat, Robertson};
use integrators::adapters::Ode;
use integrators::{MethodKind, Solver, Stats};

/// The counters that measure cost (events/resizes/symbolic are structural).
fn cost(s: &Stats) -> [usize; 9] {
    [
        s.steps,
        s.rejected_steps,
        s.error_test_failures,
        s.newton_failures,
        s.residual_calls,
        s.jacobian_evals,
        s.factorizations,
        s.linear_solves,
        s.newton_iterations,
    ]
}

fn check(name: &str, s: &Stats, pinned: [usize; 9]) {
    eprintln!("{name}: {:?}", cost(s));
    assert_eq!(
        cost(s),
        pinned,
        "{name}: [steps, rejected, err-test fails, newton fails, residuals, jacobians, \
         factorisations, solves, newton its] changed; see the module docs to update"
    );
}

/// Robertson to t = 1e11 by BDF (exact Jacobian), as `robertson.rs` checks it.
fn robertson_1e11(o: integrators::Options) -> Stats {
    Solver::new(MethodKind::Bdf, o)
        .solve(
            &mut Ode(Robertson {
                exact_jacobian: true,
            }),
            0.0,
            &[1.0, 0.0, 0.0],
            &[1e11],
        )
        .unwrap()
        .stats
}

#[test]
fn pinned_bdf_robertson_1e11() {
    check(
        "robertson",
        &robertson_1e11(opts(1e-6, 1e-8)),
        [686, 43, 43, 0, 1117, 36, 155, 1117, 1114],
    );
}

#[test]
fn pinned_bdf_van_der_pol_scaled() {
    check(
        "vdpol",
        &van_der_pol_scaled_bdf(opts(1e-6, 1e-6)).stats,
        [1021, 47, 47, 0, 1732, 62, 244, 1732, 1728],
    );
}

/// Robertson and the scaled Van der Pol oscillator with `BdfOptions::newton_alpha_bound`
/// (their accuracy is checked in `robertson.rs` and `van_der_pol.rs`): fewer steps and
/// rejections than IDA's test on both; on Van der Pol more Newton iterations.
#[test]
fn pinned_bdf_with_the_newton_alpha_bound() {
    check(
        "robertson, bound",
        &robertson_1e11(opts_bound(1e-6, 1e-8, true)),
        [595, 21, 21, 0, 1008, 32, 126, 1008, 1005],
    );
    check(
        "vdpol, bound",
        &van_der_pol_scaled_bdf(opts_bound(1e-6, 1e-6, true)).stats,
        [987, 17, 17, 0, 1837, 62, 216, 1837, 1833],
    );
}

#[test]
fn pinned_bdf_heat_banded_fd_jacobian() {
    let mut p = Ode(Heat {
        n: 200,
        exact_jacobian: false,
    });
    let y0 = p.0.initial();
    let o = opts(1e-6, 1e-9);
    let sol = Solver::new(MethodKind::Bdf, o)
        .solve(&mut p, 0.0, &y0, &[0.1])
        .unwrap();
    check("heat", &sol.stats, [25, 0, 0, 0, 56, 4, 15, 42, 38]);
}
