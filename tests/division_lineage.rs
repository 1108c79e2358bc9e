//! Lineage tracing on the dividing line ([`celltissue::events::Lineage`]): the division
//! records form one family tree over the initial cells, the profiles' `id`, `ancestor` and
//! `age` are that tree's leaves at each time, a clone stays one contiguous block of cells (a
//! line's cells never pass each other) in the order of the initial cells, cells without drag
//! double synchronously within every clone, and the proliferating rim of Fig 3.3d is mostly
//! the tip cell's clone.

use celltissue::events::{run_proliferation, ProliferationConfig};
use celltissue::line::run::SolveSettings;
use celltissue::line::OutputTimes;
use celltissue::observe::{ModelKind, RunRecord};
use std::collections::HashMap;

fn run(keys: &str, profiles: &[f64]) -> RunRecord {
    let table: toml::Table = toml::from_str(keys).unwrap();
    let cfg = ProliferationConfig::from_table(&table).unwrap();
    let mut series = vec![0.0];
    series.extend_from_slice(profiles);
    let times = OutputTimes {
        series,
        profiles: profiles.to_vec(),
    };
    let rec = run_proliferation(
        &cfg,
        ModelKind::Discrete,
        None,
        &SolveSettings::default(),
        &times,
    );
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

/// A profile field as integers (identities are stored as exact floating-point numbers).
fn ids(rec: &RunRecord, k: usize, name: &str) -> Vec<u64> {
    rec.profiles[k].extra[name]
        .iter()
        .map(|&v| {
            assert!(v >= 0.0 && v.fract() == 0.0, "{name} = {v}");
            v as u64
        })
        .collect()
}

/// Checks every profile of `rec` (of a line that started with `n0` cells) against the family
/// tree its records make; returns the largest clone's share of the cells at the last profile
/// and the number of cells of each clone there.
fn check_tree(rec: &RunRecord, n0: u64) -> (f64, HashMap<u64, usize>) {
    // parent of every daughter, with its birth time
    let mut born: HashMap<u64, (u64, f64)> = HashMap::new();
    let mut divided: HashMap<u64, f64> = HashMap::new();
    for d in &rec.divisions {
        let (c, [a, b]) = (d.cell.unwrap(), d.daughters.unwrap());
        assert!(divided.insert(c, d.t).is_none(), "cell {c} divided twice");
        // a cell divides only after it was born (or from the start)
        assert!(
            c < n0 || born[&c].1 < d.t,
            "cell {c} divided before its birth"
        );
        for x in [a, b] {
            assert!(
                x >= n0 && born.insert(x, (c, d.t)).is_none(),
                "daughter {x} reused"
            );
        }
    }
    let root = |mut c: u64| {
        while let Some(&(p, _)) = born.get(&c) {
            c = p;
        }
        c
    };
    let mut clones = HashMap::new();
    for k in 0..rec.profiles.len() {
        let t = rec.profiles[k].t;
        let (id, anc) = (ids(rec, k, "id"), ids(rec, k, "ancestor"));
        let age = &rec.profiles[k].extra["age"];
        // the cells alive at t: born by t (or initial), not yet divided
        let alive = |c: &u64| {
            born.get(c).is_none_or(|&(_, tb)| tb <= t) && divided.get(c).is_none_or(|&td| td > t)
        };
        let n_alive = (0..n0).chain(born.keys().copied()).filter(alive).count();
        assert_eq!(
            id.len(),
            n_alive,
            "t = {t}: cells against the tree's leaves"
        );
        for (i, &c) in id.iter().enumerate() {
            assert!(alive(&c), "t = {t}: cell {c} is not a leaf");
            assert_eq!(anc[i], root(c), "t = {t}: ancestor of {c}");
            let birth = born.get(&c).map_or(0.0, |b| b.1);
            assert!(
                (age[i] - (t - birth)).abs() <= 1e-12 * t,
                "t = {t}: age of {c}"
            );
        }
        // a clone is one block, the blocks in the order of the initial cells
        assert!(
            anc.windows(2).all(|w| w[0] <= w[1]),
            "t = {t}: clones interleave"
        );
        clones.clear();
        for &a in &anc {
            *clones.entry(a).or_insert(0usize) += 1;
        }
    }
    let n = rec.profiles.last().unwrap().x.len();
    let largest = clones.values().copied().max().unwrap_or(0);
    (largest as f64 / n as f64, clones)
}

/// Without drag every cell grows unstressed and all divide together at t = 2, 4, …: at t = 5
/// each of the 8 clones holds exactly 4 cells, with identities and ages from the tree.
#[test]
fn without_drag_every_clone_doubles_in_step() {
    let rec = run(
        "cells = 8\nK = 0\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
         division = { rule = \"area\" }",
        &[1.0, 3.0, 5.0],
    );
    let (_, clones) = check_tree(&rec, 8);
    assert_eq!(clones.len(), 8);
    assert!(clones.values().all(|&c| c == 4), "{clones:?}");
    // every cell at t = 5 was born at t = 4
    let age = &rec.profiles[2].extra["age"];
    assert!(age.iter().all(|&a| (a - 1.0).abs() < 1e-7), "{age:?}");
}

/// The proliferating rim (K = 1e-2, t ≤ 200, Fig 3.3d): the tree holds at every profile, and
/// most of the tissue is the clone of the initial tip cell (measured: 296 of 406 cells at
/// t = 200), the divisions having gathered at the free end.
#[test]
fn the_proliferating_rim_is_the_tip_cells_clone() {
    let rec = run(
        "cells = 100\nK = 1e-2\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
         division = { rule = \"area\" }",
        &[50.0, 100.0, 200.0],
    );
    let (share, clones) = check_tree(&rec, 100);
    let tip = clones[&99];
    println!(
        "t = 200: {} cells, the tip cell's clone {tip}, largest share {share:.3}",
        rec.profiles[2].x.len()
    );
    assert!(tip as f64 > 0.6 * rec.profiles[2].x.len() as f64);
    assert_eq!(share, tip as f64 / rec.profiles[2].x.len() as f64);
}

/// The tree on a ring (the cells divide inside a fixed circumference) and with divisions
/// brought forward (`batch_within`, several cells split per event): identities, ancestors
/// and ages follow every split.
#[test]
fn the_tree_holds_on_a_ring_and_within_a_window() {
    let ring = run(
        "cells = 20\nright_end = \"periodic\"\nK = 0.1\n\
         mu = { type = \"random\", low = 0.5, high = 2.0, seed = 3 }\n\
         growth = { sigma0 = 10.0 }\ndivision = { rule = \"area\" }",
        &[10.0, 40.0],
    );
    check_tree(&ring, 20);
    let window = run(
        "cells = 100\nK = 1e-5\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
         division = { rule = \"area\", batch_within = 1e-2 }",
        &[3.0, 6.0],
    );
    check_tree(&window, 100);
    assert!(window.stats.extra["events"] < window.divisions.len() as u64);
}
