//! What a division costs the integrator, on the two `models/fig3_3.toml` cases:
//! N₀ = 100 neo-Hookean cells, σ₀ = 0.1, free end, η = 0, m = 0, area rule, default solver
//! (BDF, rtol 1e-6, atol 1e-8, max norm).
//!
//! By default ([`Dividing::carry_history`]) a division is a resize the problem maps
//! (`Problem::map_history`: the interpolated `ẏ` carried onto the new layout, no consistent
//! initialisation) and BDF goes on from it at order 1, its first step checked by step doubling
//! (`Method::resume`). `carry_history = false` is the previous restart (consistent `ẏ`, the
//! pre-event velocities and smoothed new boundaries, order 1, error test against the
//! extrapolated `ẏ`). With the carried history the Newton matrices are carried too
//! (`Problem::map_jacobian`: moved to the new layout, the rows around the daughters evaluated
//! afresh), so a division costs no Jacobian of the whole line. The counters are deterministic
//! and pinned; "Jacobians" below are evaluations of the pair `∂F/∂y`, `∂F/∂ẏ`
//! (`Stats::jacobian_evals` counts each half).

use crate::common::{area_dividing_line, division_cost, DivisionCost as Cost};
use celltissue::line::run::SolveSettings;

fn run(k: f64, t_end: f64, carry: bool) -> Cost {
    run_at(k, t_end, carry, &SolveSettings::default())
}

fn run_at(k: f64, t_end: f64, carry: bool, settings: &SolveSettings) -> Cost {
    let mut div = area_dividing_line(k);
    div.carry_history = carry;
    let c = division_cost(div, settings, t_end);
    let d = c.divisions as f64;
    println!(
        "K = {k:e}, t ≤ {t_end}, carry = {carry}: {} divisions, {} steps ({:.2}/division), \
         {} rejected ({:.3}), {} Jacobians ({:.3}), l = {}",
        c.divisions,
        c.steps,
        c.steps as f64 / d,
        c.rejected,
        c.rejected as f64 / d,
        c.jacobians,
        c.jacobians as f64 / d,
        c.length
    );
    c
}

/// Same divisions (to the tolerances) and same length with and without the carried history.
fn same_solution(a: &Cost, b: &Cost, dt_max: f64, dl_max: f64) {
    assert_eq!(a.divisions, b.divisions);
    let mut ta = a.times.clone();
    let mut tb = b.times.clone();
    ta.sort_by(f64::total_cmp);
    tb.sort_by(f64::total_cmp);
    let dt = ta
        .iter()
        .zip(&tb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let dl = (a.length / b.length - 1.0).abs();
    println!("max |Δt_division| = {dt:e}, |Δl|/l = {dl:e}");
    assert!(dt < dt_max, "division times differ by {dt}");
    assert!(dl < dl_max, "lengths differ by {dl}");
}

#[test]
fn small_drag_division_counters() {
    let new = run(1e-5, 18.0, true);
    let old = run(1e-5, 18.0, false);
    // pinned (measured): 871 divisions (N(18) = 971); carried: 31 559 steps, 1 877 rejected,
    // 640 Jacobians; restart: 35 659 steps, 5 548 rejected, 1 767 Jacobians. (When the carried
    // path's first attempt after a division fails, it retries from at most twice the last
    // division's first accepted step, BDF's `RESUME_GROWTH`: 31 924 steps and 6 019 rejected
    // without it.) Under the
    // cell-unit accuracy contract every cell's stretch is held to rtol, so the fast relaxation
    // of the daughters after each division (time scale ~K) is resolved: ~41 steps per
    // division (4 705 and 8 654 steps under the old rtol·|x| test, which let the positions
    // near x ≈ 1000 err by 1e-3 cell lengths). Against an rtol 1e-9 reference
    // (l = 1383.4339756) the final length errs by 3.5e-7 relative here, 1.6e-6 before. (The
    // carried path's step-doubled estimate is measured in cell units too: 35 591 steps when it
    // was measured on raw positions, so a shift of every boundary beyond a dividing cell
    // counted as an error.)
    assert_eq!(new.divisions, 871);
    assert_eq!(
        (new.steps, new.rejected, new.jacobians),
        (31559, 1877, 640),
        "carried history counters moved"
    );
    assert_eq!(
        (old.steps, old.rejected, old.jacobians),
        (35659, 5548, 1767),
        "restart counters moved"
    );
    // 0.73 Jacobians per division with the carried history and its mapped matrices (2.03 with
    // the restart; 1.09 when every division evaluated a fresh pair)
    assert!(new.jacobians < old.jacobians);
    same_solution(&new, &old, 1e-4, 1e-6);
}

#[test]
fn a_looser_contract_brings_small_drag_divisions_to_about_two_steps() {
    // The relaxation a division starts at K = 1e-5 has an amplitude of order K·v/μ; at rtol
    // 1e-6 the contract resolves it (36 steps per division, above), at rtol 1e-4 it falls
    // below the tolerance: 2.06 steps (the issue asks for at most 2) and almost no rejection
    // per division, bought with stretch errors of up to 0.45 rtol in the Fig 3.3 scenario
    // (BENCHMARKS.md, "What a looser contract buys"). The length stays within rtol of the
    // rtol 1e-9 reference (l = 1383.4339756, above).
    let settings = SolveSettings {
        rtol: 1e-4,
        atol: 1e-6,
        ..Default::default()
    };
    let c = run_at(1e-5, 18.0, true, &settings);
    assert_eq!(c.divisions, 871);
    // measured: 1 794 steps (2.06 per division), 5 rejected, 44 Jacobians; l errs by 1.4e-5
    assert_eq!(
        (c.steps, c.rejected, c.jacobians),
        (1794, 5, 44),
        "counters moved"
    );
    let d = c.divisions as f64;
    assert!(c.steps as f64 / d < 2.2 && (c.rejected as f64) / d < 0.2);
    let dl = (c.length / 1_383.433_975_6 - 1.0).abs();
    assert!(dl < 1e-4, "l(18) = {} errs by {dl:e}", c.length);
}

#[test]
fn large_drag_rim_divisions() {
    let new = run(1e-2, 300.0, true);
    let old = run(1e-2, 300.0, false);
    assert_eq!(new.divisions, old.divisions);
    println!(
        "steps {} vs {}, rejected {} vs {}, Jacobians {} vs {}",
        new.steps, old.steps, new.rejected, old.rejected, new.jacobians, old.jacobians
    );
    // pinned: 460 divisions; carried 26 174 steps, 1 523 rejected, 611 Jacobians; restart
    // 27 556, 2 875, 1 375 (14 899 / 1 658 / 782 and 15 441 / 1 343 / 937 under the old
    // rtol·|x| test: the cell-unit contract resolves each division's transient in every
    // cell's stretch). The transient after each division is longer than a step here and is
    // resolved (steps per division scale with the tolerance, see BENCHMARKS.md): the gain of
    // the carried history is in Jacobians, not steps.
    assert_eq!(new.divisions, 460);
    assert_eq!((new.steps, new.rejected, new.jacobians), (26174, 1523, 611));
    assert_eq!(
        (old.steps, old.rejected, old.jacobians),
        (27556, 2875, 1375)
    );
    // a compressed interior cell grows slowly (ġ ≪ 1), so a state difference δg within the
    // tolerances moves its division by δg/ġ: measured 1.2e-3 at t ≈ 300 (4e-6 relative)
    same_solution(&new, &old, 5e-3, 1e-6);
}

#[test]
fn tiny_drag_divisions_cost_a_few_steps() {
    // K = 1e-7: the daughters relax in a time ≈ K, far below any step, and the divisions are
    // cheap (the transient's amplitude, ∝ K, is below the tolerance). The first step after an
    // event is the pre-event one (≈ 1 after a quiet stretch): it used to fail Newton three
    // times, hand over to the ordinary error test, which read the unresolvable relaxation as a
    // persistent error, and stop at t ≈ 4.0003 with "step size too small".
    let new = run(1e-7, 6.0, true);
    // (the consistent restart, `carry_history = false`, still stops there: its first step is
    // checked by the ordinary error test)
    let tight = SolveSettings {
        rtol: 1e-9,
        atol: 1e-11,
        ..Default::default()
    };
    let reference = run_at(1e-7, 6.0, true, &tight);
    // pinned (measured)
    assert_eq!(new.divisions, PINNED_TINY.0);
    assert_eq!((new.steps, new.rejected, new.jacobians), PINNED_TINY.1);
    assert!(
        new.steps as f64 <= 4.0 * new.divisions as f64,
        "{} steps for {} divisions",
        new.steps,
        new.divisions
    );
    // the Newton matrices are carried across divisions: far fewer than one pair per division
    assert!(
        10 * new.jacobians <= new.divisions,
        "{} Jacobians for {} divisions",
        new.jacobians,
        new.divisions
    );
    same_solution(&new, &reference, 1e-4, 1e-6);
}
/// K = 1e-7, t ≤ 6: 300 divisions; 811 steps (2.70 per division), 13 rejected (0.04), 22
/// Jacobians (0.07; 308 when every division evaluated a fresh pair). The rtol 1e-9 reference
/// takes 11 219 steps (37.4 per division): there the relaxation is above the tolerance and is
/// resolved. Lengths agree to 6.2e-9 relative.
const PINNED_TINY: (usize, (usize, usize, usize)) = (300, (811, 13, 22));

/// `solver.jacobian_age = 100` (the Newton matrices refreshed every 100 steps unless Newton
/// slows, instead of every 50) on both Fig 3.3 cases: under one Jacobian per division, same
/// divisions and length to the tolerances as the default age, and no more than 1 % more steps.
/// The bundled `fig3_3.toml` and `fig3_3d.toml` set it.
#[test]
fn a_longer_jacobian_age_costs_under_one_jacobian_per_division() {
    let aged = SolveSettings {
        jacobian_age: 100,
        ..Default::default()
    };
    // (K, t_end, pinned: divisions, steps, rejected, Jacobians; default age's steps)
    for (k, t_end, pinned, default_steps) in [
        (1e-5, 18.0, (871, 31544, 1872, 323), 31559),
        (1e-2, 300.0, (460, 26258, 1528, 319), 26174),
    ] {
        let base = run(k, t_end, true);
        let new = run_at(k, t_end, true, &aged);
        assert_eq!(base.steps, default_steps);
        assert_eq!(
            (new.divisions, new.steps, new.rejected, new.jacobians),
            pinned,
            "K = {k}: counters moved"
        );
        assert!(new.jacobians < new.divisions, "K = {k}");
        assert!(new.steps * 100 <= base.steps * 101, "K = {k}");
        same_solution(&new, &base, 5e-3, 1e-6);
    }
}

/// Fig 3.3a's κ = A line (`models/fig3_3a_kappa_A.toml`: m = 1, K = 1e-5) at the tightest
/// tolerances, to t = 10.5 (416 divisions).
fn kappa_a_line(rtol: f64, atol: f64) -> celltissue::observe::RunRecord {
    use celltissue::scenario::{execute, load_str};
    let text = format!(
        "name = \"tight\"\n[solver]\nrtol = {rtol:e}\natol = {atol:e}\n\
         [output]\nseries = [0, 10.5]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\n\
         cells = 100\nright_end = \"free\"\nm = 1.0\ngrowth = {{ sigma0 = 0.1 }}\n\
         division = {{ rule = \"area\", ratio = 2.0 }}\nK = 1e-5\n"
    );
    let s = load_str(&text, std::path::Path::new("tight.toml"), &[]).unwrap();
    let mut summary = execute::run_all(&s, execute::run_spec, |_| {});
    summary.runs.remove(0)
}

/// At rtol 1e-11 (atol 1e-13) the division at t ≈ 10.457 has a step-doubled first step whose
/// estimate falls as h² over its three error tries (8.1e4 at h = 8.7e-4, then 1.0e2 and 1.017
/// at 6.1e-9 and 6.1e-10). The ordinary error test used to take over there, and its estimate,
/// which measures the jump of ẏ at the division, falls only as h: the run stopped at
/// t = 10.457 with "step size 1.5e-13 too small". A converging estimate now goes on doubling
/// (`CONVERGING_ORDER`), and the run ends with the divisions and length of an rtol 1e-10 run.
#[test]
fn a_division_at_the_tightest_tolerance_restarts() {
    let tight = kappa_a_line(1e-11, 1e-13);
    assert!(tight.error.is_none(), "{:?}", tight.error);
    let loose = kappa_a_line(1e-10, 1e-12);
    assert!(loose.error.is_none(), "{:?}", loose.error);
    let (nt, nl) = (&tight.series.extra["cells"], &loose.series.extra["cells"]);
    assert_eq!((nt[1], nl[1]), (516.0, 516.0));
    let (lt, ll) = (tight.series.length[1], loose.series.length[1]);
    let dl = (lt / ll - 1.0).abs();
    println!("l(10.5) = {lt} at rtol 1e-11, {ll} at 1e-10: {dl:e} relative");
    // measured 1.2e-10: within the looser run's tolerance
    assert!(dl < 1e-9, "{dl:e}");
    // pinned (measured): 97 633 steps, 1 427 rejected at rtol 1e-11
    assert_eq!(
        (tight.stats.steps, tight.stats.extra["rejected_steps"]),
        (97_633, 1_427)
    );
}
