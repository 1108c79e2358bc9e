//! A division rule that reads each cell's geometry: the surface-to-volume rule
//! of the thesis's Ch. 5 ([`SurfaceToVolume`], perimeter/area `2(1/ℓ + 1/W)` of the 2D cell
//! falling to a critical value).
//!
//! Validation: for a nearly stress-free line (K = 1e-8, free end, σ₀ = 0.1, η = 0) every cell
//! keeps `α ≈ 1`, so `ℓ = L₀ g α ≈ g`, `W = γ₀ g₂/α ≈ 1` for unit cells, and `P/A = 3` is
//! reached exactly when `g = 2`: the surface-to-volume rule with critical 3 must reproduce the
//! area-doubling rule's divisions. Under drag (K = 1e-2, compressed interior: `α < 1`) the two
//! rules part: `P/A = 2(1/(αg) + α)` reaches 3 before `g = 2` when `α < 1`.

use celltissue::boundary::RightEnd;
use celltissue::cell::TanhGrowth;
use celltissue::events::{AreaDoubling, Dividing, DivisionRule, SurfaceToVolume};
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::{ArrayProblem, NeoHookean};
use std::sync::Arc;

fn divisions(k: f64, rule: Box<dyn DivisionRule>, t_end: f64) -> Vec<(f64, usize)> {
    let mut p = LineParams::unit_cells(100);
    p.right = RightEnd::Free(None);
    p.k = k.into();
    p.growth = Some(Arc::new(TanhGrowth::default()));
    let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
    let div = Dividing::new(line, rule, 0).unwrap();
    let mut prob = ArrayProblem::new(div);
    let traj = integrate(&mut prob, &SolveSettings::default(), &[0.0, t_end]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    prob.array
        .log
        .records
        .iter()
        .map(|r| (r.t, r.parent))
        .collect()
}

#[test]
fn surface_to_volume_equals_area_doubling_for_stress_free_cells() {
    let area = divisions(1e-8, Box::new(AreaDoubling::default()), 3.0);
    let stv = divisions(1e-8, Box::new(SurfaceToVolume { critical: 3.0 }), 3.0);
    println!(
        "{} vs {} divisions; first {:?} vs {:?}",
        area.len(),
        stv.len(),
        area[0],
        stv[0]
    );
    assert_eq!(area.len(), stv.len());
    assert!(area.len() >= 100);
    let dt = area
        .iter()
        .zip(&stv)
        .map(|(a, b)| (a.0 - b.0).abs())
        .fold(0.0, f64::max);
    println!("max |Δt| = {dt:e}");
    assert!(dt < 1e-4, "division times differ by {dt}");
}

#[test]
fn compressed_cells_divide_earlier_by_surface_to_volume() {
    let area = divisions(1e-2, Box::new(AreaDoubling::default()), 6.0);
    let stv = divisions(1e-2, Box::new(SurfaceToVolume { critical: 3.0 }), 6.0);
    println!("area: {area:?}\nsurface to volume: {stv:?}");
    // K = 1e-2: area rule 2.5824, 3.5352, 4.9374, 5.1841 (cells 100, 99, 98, 103); measured
    // surface to volume: 2.5522, 3.4186, 4.6939, 5.1520, same cells — each one earlier
    assert_eq!(area.len(), 4);
    assert_eq!(
        area.iter().map(|d| d.1).collect::<Vec<_>>(),
        stv.iter().map(|d| d.1).collect::<Vec<_>>()
    );
    for (a, s) in area.iter().zip(&stv) {
        assert!(s.0 < a.0 - 0.01, "cell {}: {} vs {}", a.1, s.0, a.0);
    }
}
