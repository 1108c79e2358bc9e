//! VTK output of the sheet for ParaView: one `.vtu` (XML unstructured grid, binary: zlib +
//! base64, see [`crate::output::vtu`]) per snapshot with one hexahedron per cell
//! (`[x_b(j−1,k), x_b(j,k)] × [y_b(j,k−1), y_b(j,k)] × [0, H]`) and per-cell `pressure`,
//! `lambda1`, `lambda2`, `lambda3` (total stretches), `height`, `sigma11`, `sigma22`, `kappa`,
//! `column`, `row`, and for a growing sheet's profile ([`profile_grid`]) the growth stretches
//! `growth_x`, `growth_y`.
//! [`crate::output::vtu`] writes the snapshots (atomically) and the `.pvd` collection indexing
//! them by time.
//!
//! Cells do not share vertices (neighbouring cells' faces need not coincide, docs/model.md §4.1).

use super::uniaxial::SheetCell;
use crate::output::vtu::{self, Grid, VTK_HEXAHEDRON};
use std::io;

/// The sheet's cells as a grid of hexahedra.
///
/// ```
/// use celltissue::sheet::uniaxial::SheetCell;
/// let c = SheetCell { x: [0.0, 2.0], y: [0.0, 1.0], height: 0.5, ..Default::default() };
/// let g = celltissue::sheet::vtk::grid(&[c]);
/// assert_eq!((g.points.len(), g.types.len()), (8, 1));
/// assert_eq!(g.points[6], [2.0, 1.0, 0.5]); // the top face at z = H
/// ```
pub fn grid(cells: &[SheetCell]) -> Grid {
    let nc = cells.len();
    let mut points = Vec::with_capacity(8 * nc);
    for c in cells {
        for z in [0.0, c.height] {
            for (x, y) in [
                (c.x[0], c.y[0]),
                (c.x[1], c.y[0]),
                (c.x[1], c.y[1]),
                (c.x[0], c.y[1]),
            ] {
                points.push([x, y, z]);
            }
        }
    }
    type Field = (&'static str, fn(&SheetCell) -> f64);
    let fields: [Field; 10] = [
        ("pressure", |c| c.pressure),
        ("lambda1", |c| c.stretch[0]),
        ("lambda2", |c| c.stretch[1]),
        ("lambda3", |c| c.stretch[2]),
        ("height", |c| c.height),
        ("sigma11", |c| c.s11),
        ("sigma22", |c| c.s22),
        ("kappa", |c| c.kappa),
        ("column", |c| c.j as f64),
        ("row", |c| c.k as f64),
    ];
    Grid {
        points,
        connectivity: (0..8 * nc as i64).collect(),
        offsets: (1..=nc as i64).map(|k| 8 * k).collect(),
        types: vec![VTK_HEXAHEDRON; nc],
        cell_data: fields
            .iter()
            .map(|(name, f)| (name.to_string(), cells.iter().map(f).collect()))
            .collect(),
    }
}

/// A sheet profile ([`sheet_profile`](super::observe::sheet_profile)) as a grid of
/// hexahedra: [`grid`] of its cells, with the growth stretches `growth_x`, `growth_y` as cell
/// data when the profile has them (a growing sheet's, at every snapshot alike).
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, SheetConfig};
/// use celltissue::SolveSettings;
/// let cfg = SheetConfig { cells_x: 3, cells_y: 2, ..Default::default() };
/// let out = OutputTimes { series: vec![1.0], profiles: vec![1.0] };
/// let rec = run_sheet(&cfg, &cfg.law, ModelKind::Discrete, None, &SolveSettings::default(), &out)?;
/// let g = celltissue::sheet::vtk::profile_grid(&rec.profiles[0]);
/// assert_eq!(g.types.len(), 6);
/// assert!(g.cell_data.iter().all(|(name, _)| name != "growth_x")); // this sheet does not grow
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn profile_grid(p: &crate::observe::Profile) -> Grid {
    let mut g = grid(&super::observe::sheet_cells(p));
    for key in ["growth_x", "growth_y"] {
        if let Some(col) = p.extra.get(key) {
            g.cell_data
                .push((key.to_string(), col[..g.types.len()].to_vec()));
        }
    }
    g
}

/// One snapshot as a `.vtu` string.
///
/// ```
/// use celltissue::sheet::uniaxial::SheetCell;
/// let c = SheetCell { x: [0.0, 1.0], y: [0.0, 1.0], height: 1.0, stretch: [1.0; 3], ..Default::default() };
/// let s = celltissue::sheet::vtk::vtu_string(0.5, &[c]).unwrap();
/// assert!(s.contains("NumberOfCells=\"1\"") && s.contains("Name=\"pressure\""));
/// ```
pub fn vtu_string(t: f64, cells: &[SheetCell]) -> io::Result<String> {
    vtu::vtu_string(t, &grid(cells))
}
