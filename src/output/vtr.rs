//! VTK XML rectilinear grids (`.vtr`) for ParaView: a straight line of cells that meet end to
//! end as a one-dimensional grid. Its `N + 1` boundaries are the x coordinates, each cell the
//! interval between two of them, and the cell's fields its cell data.
//!
//! *Why not an unstructured grid*: a `.vtu` spells the same line out as `3(N + 1)` point
//! coordinates (two thirds of them zeros), `2N` connectivity indices, `N` offsets and `N` cell
//! types, all compressed at every snapshot; at 10⁵ cells those four arrays took a third of a
//! snapshot's compression time. Here the topology is the extent `0 N 0 0 0 0` and the geometry
//! one array of `N + 1` numbers. Arrays are encoded as in [`super::vtu`] (binary, zlib,
//! UInt64 headers). The writer of a scenario's snapshots picks this form for every run whose
//! profiles are all straight lines of joined cells, and a `.vtu` for rings, sheets and cells
//! that do not meet.

use super::vtu::{
    cell_data_start, joined_boundaries, line_cells, line_fields, time_field, Array, Values,
};
use crate::observe::Profile;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// A one-dimensional rectilinear grid: the cells' boundaries along x, per-cell data.
///
/// ```
/// use celltissue::output::vtr::{vtr_string, Rectilinear};
/// // two cells, [0, 0.9] and [0.9, 2.0], carrying a pressure
/// let g = Rectilinear { x: vec![0.0, 0.9, 2.0], cell_data: vec![("pressure".into(), vec![1.0, 2.0])] };
/// let xml = vtr_string(0.5, &g).unwrap();
/// assert!(xml.contains("WholeExtent=\"0 2 0 0 0 0\"") && xml.contains("Name=\"pressure\""));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rectilinear {
    /// The `N + 1` boundaries, increasing.
    pub x: Vec<f64>,
    /// Per-cell fields by name (each `N` long).
    pub cell_data: Vec<(String, Vec<f64>)>,
}

/// The rectilinear grid of a line profile whose cells meet end to end in increasing order
/// along x; `None` for cells that do not ([`line_boundaries`]), which
/// [`super::vtu::line_grid`] draws instead.
///
/// ```
/// use celltissue::observe::Profile;
/// use celltissue::output::vtr::line_rectilinear;
/// let p = Profile { t: 0.0, x_ref: vec![0.5, 1.5], x: vec![0.45, 1.35],
///     stretch: vec![0.9, 0.9], pressure: vec![1.2, 1.2], extra: Default::default() };
/// let g = line_rectilinear(&p).unwrap();
/// assert!((g.x[1] - 0.9).abs() < 1e-12 && (g.x[2] - 1.8).abs() < 1e-12);
/// assert_eq!(g.cell_data[0], ("stretch".to_string(), vec![0.9, 0.9]));
/// ```
pub fn line_rectilinear(p: &Profile) -> Option<Rectilinear> {
    let x = line_boundaries(p)?;
    Some(Rectilinear {
        cell_data: line_fields(p, x.len() - 1),
        x,
    })
}

/// The `N + 1` boundaries of a line profile's cells when they meet end to end in increasing
/// order along x; `None` for a gap, an overlap, a cell of no length or no cell.
///
/// ```
/// use celltissue::observe::Profile;
/// use celltissue::output::vtr::line_boundaries;
/// let p = Profile { t: 0.0, x_ref: vec![0.5, 1.5], x: vec![0.5, 1.5],
///     stretch: vec![1.0, 1.0], pressure: vec![0.0, 0.0], extra: Default::default() };
/// assert_eq!(line_boundaries(&p), Some(vec![0.0, 1.0, 2.0]));
/// ```
pub fn line_boundaries(p: &Profile) -> Option<Vec<f64>> {
    let mut ends = p.cell_ends();
    ends.truncate(line_cells(p));
    let x = joined_boundaries(&ends)?;
    x.windows(2).all(|w| w[1] > w[0]).then_some(x)
}

/// The `.vtr` document of `grid` at time `t`; the arrays compressed concurrently on the rayon
/// pool, as a `.vtu`'s.
///
/// ```
/// use celltissue::output::vtr::{vtr_string, Rectilinear};
/// let g = Rectilinear { x: vec![0.0, 1.0], cell_data: vec![("p".into(), vec![1.5])] };
/// let s = vtr_string(0.5, &g).unwrap();
/// assert!(s.contains("<Coordinates>") && s.contains("compressor=\"vtkZLibDataCompressor\""));
/// ```
pub fn vtr_string(t: f64, grid: &Rectilinear) -> io::Result<String> {
    use rayon::prelude::*;
    let zero = [0.0];
    let f64s = |name, v| Array {
        ty: "Float64",
        name,
        comps: 1,
        values: Values::F64(v),
    };
    // the cell data, then the three coordinate arrays
    let mut arrays: Vec<Array> = grid.cell_data.iter().map(|(n, v)| f64s(n, v)).collect();
    arrays.push(f64s("x_coordinates", &grid.x));
    arrays.push(f64s("y_coordinates", &zero[..]));
    arrays.push(f64s("z_coordinates", &zero[..]));
    let elements = arrays
        .par_iter()
        .map(Array::element)
        .collect::<io::Result<Vec<String>>>()?;
    let cells = grid.x.len().saturating_sub(1);
    let extent = format!("0 {cells} 0 0 0 0");
    let mut s = String::with_capacity(1024 + elements.iter().map(String::len).sum::<usize>());
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"RectilinearGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n");
    let _ = writeln!(s, "<RectilinearGrid WholeExtent=\"{extent}\">");
    s.push_str(&time_field(t)?);
    let _ = writeln!(s, "<Piece Extent=\"{extent}\">");
    s.push_str(cell_data_start(&grid.cell_data));
    let fields = grid.cell_data.len();
    for e in &elements[..fields] {
        s.push_str(e);
    }
    s.push_str("</CellData>\n<Coordinates>\n");
    for e in &elements[fields..] {
        s.push_str(e);
    }
    s.push_str("</Coordinates>\n</Piece>\n</RectilinearGrid>\n</VTKFile>\n");
    Ok(s)
}

/// Writes `grid` at time `t` to `path` atomically.
///
/// ```
/// use celltissue::output::vtr::{write_vtr, Rectilinear};
/// let dir = std::env::temp_dir().join(format!("ct_vtr_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let g = Rectilinear { x: vec![0.0, 1.0], cell_data: vec![] };
/// write_vtr(&dir.join("line_0000.vtr"), 1.0, &g).unwrap();
/// assert!(std::fs::read_to_string(dir.join("line_0000.vtr")).unwrap().contains("RectilinearGrid"));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_vtr(path: &Path, t: f64, grid: &Rectilinear) -> io::Result<()> {
    let text = vtr_string(t, grid)?;
    super::atomic::write(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn profile(x: Vec<f64>, lengths: Vec<f64>) -> Profile {
        let n = x.len();
        Profile {
            t: 0.0,
            x_ref: (0..n).map(|j| j as f64 + 0.5).collect(),
            x,
            stretch: vec![1.0; n],
            pressure: vec![0.0; n],
            extra: BTreeMap::from([("length".to_string(), lengths)]),
        }
    }

    #[test]
    fn only_cells_meeting_in_increasing_order_make_a_rectilinear_line() {
        // meeting end to end
        let g = line_rectilinear(&profile(vec![0.5, 2.0], vec![1.0, 2.0])).unwrap();
        assert_eq!(g.x, [0.0, 1.0, 3.0]);
        // a gap between the cells, a cell of no length, no cell
        assert!(line_rectilinear(&profile(vec![0.5, 2.5], vec![1.0, 2.0])).is_none());
        assert!(line_rectilinear(&profile(vec![0.5, 1.0, 1.5], vec![1.0, 0.0, 1.0])).is_none());
        assert!(line_rectilinear(&profile(vec![], vec![])).is_none());
    }

    #[test]
    fn the_extent_counts_cells_and_the_sections_hold_their_arrays() {
        let g = Rectilinear {
            x: vec![0.0, 1.0, 2.5, 3.0],
            cell_data: vec![
                ("stretch".into(), vec![1.0, 1.5, 0.5]),
                ("pressure".into(), vec![0.1, 0.2, 0.3]),
            ],
        };
        let s = vtr_string(2.0, &g).unwrap();
        let section = |open: &str, close: &str| {
            let a = s.find(open).unwrap();
            s[a..a + s[a..].find(close).unwrap()].to_string()
        };
        assert!(s.contains("<Piece Extent=\"0 3 0 0 0 0\">"));
        let cell_data = section("<CellData", "</CellData>");
        assert!(cell_data.contains("Scalars=\"pressure\""));
        assert_eq!(cell_data.matches("<DataArray").count(), 2);
        let coordinates = section("<Coordinates>", "</Coordinates>");
        for axis in ["x", "y", "z"] {
            assert!(coordinates.contains(&format!("Name=\"{axis}_coordinates\"")));
        }
        assert!(section("<FieldData>", "</FieldData>").contains("Name=\"TIME\""));
    }
}
