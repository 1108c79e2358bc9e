//! The dividing cell's age in every division record ([`DivisionRecord::age`], its cycle time):
//! exact where growth is unstressed, the births it implies are the log's own division times,
//! compression only lengthens the cycle, and the cell-number grid's ages are the discrete
//! line's. The density continuum, which has no individual cells, records none.

use celltissue::events::{run_proliferation, ProliferationConfig};
use celltissue::line::run::SolveSettings;
use celltissue::line::OutputTimes;
use celltissue::observe::{DivisionRecord, ModelKind, RunRecord};

/// A proliferating line from the `[model]` keys in `keys`, run to the last of `series`.
fn run(keys: &str, model: ModelKind, nodes: Option<usize>, series: &[f64]) -> RunRecord {
    let table: toml::Table = toml::from_str(keys).unwrap();
    let cfg = ProliferationConfig::from_table(&table).unwrap();
    if model == ModelKind::Continuum {
        cfg.validate_continuum().unwrap();
    }
    let times = OutputTimes {
        series: series.to_vec(),
        profiles: vec![],
    };
    let rec = run_proliferation(&cfg, model, nodes, &SolveSettings::default(), &times);
    assert!(rec.error.is_none(), "{:?}", rec.error);
    assert!(!rec.divisions.is_empty());
    rec
}

fn ages(rec: &RunRecord) -> Vec<f64> {
    rec.divisions
        .iter()
        .map(|d| d.age.expect("an age in every record"))
        .collect()
}

/// Every division's birth `t − age` is t = 0 or the time of an earlier division, and no time
/// is the birth of more records' parents than twice the records at it (two daughters each; on
/// the cell-number grid a record is a segment's or a member's, and a split segment's halves
/// divide as two records). Returns how many records were born at a division.
fn births_are_division_times(log: &[DivisionRecord], tol: f64) -> usize {
    // the events, records within `tol` of each other's time counted as one
    let mut events: Vec<(f64, usize)> = Vec::new();
    for d in log {
        match events.last_mut() {
            Some((t, n)) if (*t - d.t).abs() <= tol * t.max(1.0) => *n += 1,
            _ => events.push((d.t, 1)),
        }
    }
    let mut born = vec![0usize; events.len()];
    let mut checked = 0;
    for d in log {
        let b = d.t - d.age.unwrap();
        if b.abs() <= tol {
            continue;
        }
        let i = events
            .iter()
            .position(|&(t, _)| (t - b).abs() <= tol * t.max(1.0))
            .unwrap_or_else(|| panic!("division at t = {} born at {b}: no division then", d.t));
        assert!(events[i].0 < d.t - tol, "born at {b}, not before {}", d.t);
        born[i] += 1;
        assert!(
            born[i] <= 2 * events[i].1,
            "more births at {} than daughters",
            events[i].0
        );
        checked += 1;
    }
    checked
}

/// Without drag nothing is stressed, so every cell grows at the unstressed rate
/// `ġ = G_m/2` from `g = 1` to the threshold `ratio`: each cycle lasts exactly
/// `T₀ = 2(ratio − 1)/G_m` (G_m = 2, ratio = 1.5: T₀ = 0.5), from the first generation on, on
/// the discrete line and on the cell-number grid alike.
#[test]
fn without_drag_every_cycle_is_the_unstressed_one() {
    let keys = "cells = 8\nK = 0\nright_end = \"free\"\n\
                growth = { sigma0 = 0.1, gm = 2 }\n";
    let series = [0.0, 0.7, 1.2, 1.7];
    for (division, model, nodes) in [
        (
            "division = { rule = \"area\", ratio = 1.5 }",
            ModelKind::Discrete,
            None,
        ),
        (
            "division = { rule = \"area\", ratio = 1.5, cell_grid = {} }",
            ModelKind::Continuum,
            Some(4),
        ),
    ] {
        let rec = run(&format!("{keys}{division}"), model, nodes, &series);
        let a = ages(&rec);
        let worst = a.iter().map(|a| (a / 0.5 - 1.0).abs()).fold(0.0, f64::max);
        println!(
            "{model:?}: {} divisions, ages within {worst:.1e} of T₀ = 0.5",
            a.len()
        );
        // three generations: t = 0.5, 1, 1.5
        assert_eq!(rec.divisions.last().unwrap().cells_after, 64, "{model:?}");
        assert!(worst < 1e-6, "{model:?}: {worst:e}");
        assert!(births_are_division_times(&rec.divisions, 1e-9) > 0);
    }
}

/// Each cell draws its threshold θ from U[1.8, 2.2] at birth (`random_area`), so without drag
/// its cycle lasts `2(θ − 1)/G_m` ∈ [1.6, 2.4] (G_m = 1): the ages fill that interval, and
/// each birth is a recorded division, on the discrete line and inside the cell-number grid's
/// segments, whose cells divide one by one.
#[test]
fn drawn_thresholds_spread_the_cycle_over_their_interval() {
    let keys = "cells = 16\nK = 0\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n";
    let rule = "rule = \"random_area\", mean = 2.0, spread = 0.2, seed = 7";
    let series = [0.0, 3.0, 6.0, 8.0];
    for (division, model, nodes) in [
        (
            format!("division = {{ {rule} }}"),
            ModelKind::Discrete,
            None,
        ),
        (
            format!("division = {{ {rule}, cell_grid = {{}} }}"),
            ModelKind::Continuum,
            Some(4),
        ),
    ] {
        let rec = run(&format!("{keys}{division}"), model, nodes, &series);
        let a = ages(&rec);
        let (lo, hi) = a
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        println!(
            "{model:?}: {} divisions, ages in [{lo:.4}, {hi:.4}]",
            a.len()
        );
        assert!(a.len() > 50, "{model:?}: {}", a.len());
        assert!(
            lo >= 1.6 * (1.0 - 1e-6) && hi <= 2.4 * (1.0 + 1e-6),
            "{model:?}"
        );
        assert!(lo < 1.7 && hi > 2.3, "{model:?}: [{lo}, {hi}]");
        let checked = births_are_division_times(&rec.divisions, 1e-9);
        assert!(checked > a.len() / 2, "{model:?}: {checked}");
    }
}

/// Fig 3.3d's rim (K = 1e-2, t ≤ 200): the drag holds the growing line in compression, and
/// compression slows the tanh law's growth, so no cycle is shorter than the unstressed T₀ = 2
/// (measured: the shortest 2.58, at the free end); a cell behind x/l = 0.8 takes more than
/// five times as long (measured: 18.4 at the least, up to 118). The cell-number grid records
/// the discrete line's ages up to its merging: measured, the sorted ages differ by at most
/// 1.4e-1 relative merging below θ = 1e-2 of the unstressed rate, 1.3e-5 below 1e-3 (below
/// 1e-4 nothing merges by t = 200 and the grid is the discrete line).
#[test]
fn compression_lengthens_the_cycle_and_the_cell_grid_keeps_the_ages() {
    let keys = "cells = 100\nK = 1e-2\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n";
    let series = [0.0, 50.0, 100.0, 200.0];
    let d = run(
        &format!("{keys}division = {{ rule = \"area\" }}"),
        ModelKind::Discrete,
        None,
        &series,
    );
    let ad = ages(&d);
    let shortest = ad.iter().copied().fold(f64::INFINITY, f64::min);
    let interior = d
        .divisions
        .iter()
        .filter(|r| r.x_over_length < 0.8)
        .map(|r| r.age.unwrap())
        .fold(f64::INFINITY, f64::min);
    println!(
        "{} divisions; shortest cycle {shortest:.4}, shortest behind x/l = 0.8 {interior:.2}",
        ad.len()
    );
    assert!(shortest > 2.0, "{shortest}");
    assert!(interior > 5.0 * shortest, "{interior}");
    assert!(births_are_division_times(&d.divisions, 1e-9) > ad.len() / 2);
    // the grid's records, one per dividing cell or in-phase segment: the same ages, closer
    // as the merging threshold falls
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v
    };
    let ad = sorted(ad);
    let mut gaps = Vec::new();
    for theta in [1e-2, 1e-3] {
        let c = run(
            &format!(
                "{keys}division = {{ rule = \"area\", cell_grid = {{ merge_below = {theta:e} }} }}"
            ),
            ModelKind::Continuum,
            Some(100),
            &series,
        );
        let ac = sorted(ages(&c));
        assert_eq!(ac.len(), ad.len());
        let gap = ad
            .iter()
            .zip(&ac)
            .map(|(a, b)| (a - b).abs() / a)
            .fold(0.0, f64::max);
        println!("cell grid, θ = {theta:e}: largest relative gap in the sorted ages {gap:.1e}");
        gaps.push(gap);
    }
    assert!(gaps[1] < 1e-4 && gaps[1] < gaps[0] / 100.0, "{gaps:?}");
}

/// The density continuum's divisions are its density crossing whole cells: no cell has an
/// age, so its records carry none, and its files leave the column out.
#[test]
fn the_density_continuum_records_no_age() {
    let keys = "cells = 20\nK = 1e-3\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
                division = { rule = \"area\" }";
    let rec = run(keys, ModelKind::Continuum, Some(20), &[0.0, 3.0]);
    assert!(rec.divisions.iter().all(|d| d.age.is_none()));
    let csv = celltissue::output::files::divisions_csv(&rec);
    assert_eq!(
        csv.lines().next(),
        Some("t,parent,x,x_over_length,cells_after")
    );
    let d = run(keys, ModelKind::Discrete, None, &[0.0, 3.0]);
    let csv = celltissue::output::files::divisions_csv(&d);
    assert_eq!(
        csv.lines().next(),
        Some("t,parent,x,x_over_length,cells_after,age,cell,daughter_1,daughter_2")
    );
}

/// The ages' births are division times wherever cells divide: on a ring inside its fixed
/// circumference, and on a line whose divisions due within a window are brought forward
/// (`batch_within`), where a cell's age runs from the event that made it, the time it was
/// actually born in the model.
#[test]
fn births_are_division_times_on_a_ring_and_within_a_window() {
    let ring = "cells = 20\nright_end = \"periodic\"\nK = 0.1\n\
                mu = { type = \"random\", low = 0.5, high = 2.0, seed = 3 }\n\
                growth = { sigma0 = 10.0 }\ndivision = { rule = \"area\" }";
    let window = "cells = 100\nK = 1e-5\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
                  division = { rule = \"area\", batch_within = 1e-2 }";
    for (keys, end) in [(ring, 40.0), (window, 6.0)] {
        let rec = run(keys, ModelKind::Discrete, None, &[0.0, end]);
        let n = rec.divisions.len();
        let checked = births_are_division_times(&rec.divisions, 1e-12);
        println!("{n} divisions, {checked} of them born at a division");
        assert!(checked > n / 3, "{checked} of {n}");
        assert!(ages(&rec).iter().all(|&a| a > 0.0));
    }
}
