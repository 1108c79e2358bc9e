//! Division against docs/model.md §5.5 Ref values (thesis Fig. 3.3): N₀ = 100 neo-Hookean cells,
//! σ₀ = 0.1, free right end, η = 0, division when `g g₂` reaches 2.
//!
//! Measured (BDF, rtol 1e-8, atol 1e-10 in cell units) vs Ref:
//!
//! | quantity | Ref | measured |
//! |---|---|---|
//! | K = 1e-5, m = 0: first division (free-end cell 100) | 2.0086 | 2.008588 |
//! | all 100 originals divided (last: cell 1, at the wall) | 2.5948 | 2.594794 |
//! | N(2.5), N(3), N(5), N(6) | 166, 200, 248, 288 | 166, 200, 248, 288 |
//! | second wave starts at the free end | ≈ 4.02 | 4.020666 |
//! | K = 1e-5, m = 1: first / all originals divided | 2.0121 / 2.8723 | 2.012098 / 2.872323 |
//! | K = 1e-2, m = 0: first division (cell 100) | 2.5824 | 2.582356 |
//! | K = 1e-2, m = 0: divisions by t = 6 | 4 | 4 (cells 100, 99, 98, 103; median x_d/l = 0.979) |
//!
//! Every division conserved the existing boundaries and `l` exactly (0.0), `Σ L₀g` to 3e-16
//! (relative), and the daughters' `α`, `σ_el`, `p_el` to ≤ 1.2e-13.

use celltissue::boundary::RightEnd;
use celltissue::cell::TanhGrowth;
use celltissue::events::{AreaDoubling, Dividing, InvariantReport};
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::substrate::DragForm;
use celltissue::{ArrayProblem, NeoHookean};
use std::sync::Arc;

fn run(
    k: f64,
    m: f64,
    form: DragForm,
    t_end: f64,
) -> (ArrayProblem<Dividing<NeoHookean>>, Vec<f64>, Vec<usize>) {
    let mut p = LineParams::unit_cells(100);
    p.right = RightEnd::Free(None);
    p.k = k.into();
    p.m = m;
    p.form = form;
    p.growth = Some(Arc::new(TanhGrowth::default()));
    p.atol_cell = 1e-10;
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let mut div = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
    div.check_invariants = Some(InvariantReport::default());
    let mut prob = ArrayProblem::new(div);
    let settings = SolveSettings {
        rtol: 1e-8,
        atol: 1e-10,
        ..Default::default()
    };
    let t_out: Vec<f64> = (0..=(t_end * 2.0) as usize)
        .map(|i| 0.5 * i as f64)
        .collect();
    let traj = integrate(&mut prob, &settings, &t_out);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let lengths = traj.snapshots.iter().map(|s| s.length()).collect();
    let cells = traj.snapshots.iter().map(|s| s.alpha.len()).collect();
    println!("stats: {:?}", traj.stats);
    (prob, lengths, cells)
}

fn check_invariants(rep: &InvariantReport) {
    println!("invariants: {rep:?}");
    assert!(rep.events > 0);
    assert_eq!(rep.boundary_shift, 0.0, "existing boundaries move");
    assert!(rep.length_change == 0.0);
    assert!(
        rep.sum_l0g_rel < 1e-14,
        "Σ L0 g changes by {}",
        rep.sum_l0g_rel
    );
    assert!(rep.alpha_jump < 1e-12, "α jumps by {}", rep.alpha_jump);
    assert!(
        rep.sigma_el_jump < 1e-11,
        "σ_el jumps by {}",
        rep.sigma_el_jump
    );
    assert!(rep.p_el_jump < 1e-11, "p_el jumps by {}", rep.p_el_jump);
}

#[test]
fn k1e5_m0() {
    let (prob, l, n) = run(1e-5, 0.0, DragForm::Boundary, 6.0);
    let log = &prob.array.log;
    let first = &log.records[0];
    let wave_end = &log.records[99];
    println!(
        "first {:?}\n100th {:?}\n101st {:?}",
        first, wave_end, log.records[100]
    );
    println!("N at t = 0, 0.5, ..: {n:?}\nl: {l:?}");
    assert_eq!(first.parent, 100, "free-end cell first");
    assert!(
        (first.t - 2.0086).abs() < 2e-4,
        "first division at {}",
        first.t
    );
    assert!(
        (wave_end.t - 2.5948).abs() < 3e-4,
        "first wave ends at {}",
        wave_end.t
    );
    assert_eq!(wave_end.parent, 1, "last of the first wave at the wall");
    let at = |t: f64| log.cells_at(100, t);
    println!(
        "N(2.5) {} N(3) {} N(5) {} N(6) {}",
        at(2.5),
        at(3.0),
        at(5.0),
        at(6.0)
    );
    assert_eq!([at(2.5), at(3.0), at(5.0), at(6.0)], [166, 200, 248, 288]);
    assert_eq!(n[5], 166);
    assert_eq!(n[12], 288);
    check_invariants(&prob.array.check_invariants.unwrap());
}

#[test]
fn k1e5_m1() {
    let (prob, _, _) = run(1e-5, 1.0, DragForm::Boundary, 3.0);
    let log = &prob.array.log;
    println!("first {:?}\n100th {:?}", log.records[0], log.records[99]);
    assert!((log.records[0].t - 2.0121).abs() < 2e-4);
    assert!((log.records[99].t - 2.8723).abs() < 3e-4);
    check_invariants(&prob.array.check_invariants.unwrap());
}

#[test]
fn k1e2_m0_proliferating_rim() {
    let (prob, _, _) = run(1e-2, 0.0, DragForm::Boundary, 6.0);
    let log = &prob.array.log;
    for r in &log.records {
        println!("{r:?}");
    }
    assert!((log.records[0].t - 2.5824).abs() < 3e-4);
    assert_eq!(log.records[0].parent, 100);
    assert_eq!(log.len(), 4);
    let med = log.median_x_over_length(0.0, 6.0).unwrap();
    println!("median x_d/l = {med}");
    assert!(med > 0.9);
}
