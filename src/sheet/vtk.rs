//! VTK output of the sheet for ParaView: one `.vtu` (XML unstructured grid, ASCII) per
//! snapshot with one hexahedron per cell (`[x_b(j−1,k), x_b(j,k)] × [y_b(j,k−1), y_b(j,k)] ×
//! [0, H]`) and per-cell `pressure`, `lambda1`, `lambda2`, `lambda3`, `height`, `sigma11`,
//! `sigma22`, `kappa`; and a `.pvd` collection indexing the snapshots by time.
//!
//! Cells do not share vertices (neighbouring cells' faces need not coincide, docs/model.md §4.1).

use super::uniaxial::SheetCell;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

/// Writes one snapshot as a `.vtu` string.
///
/// ```
/// use celltissue::sheet::uniaxial::SheetCell;
/// let c = SheetCell { x: [0.0, 1.0], y: [0.0, 1.0], height: 1.0, stretch: [1.0; 3], ..Default::default() };
/// let s = celltissue::sheet::vtk::vtu_string(0.5, &[c]);
/// assert!(s.contains("NumberOfCells=\"1\"") && s.contains("Name=\"pressure\""));
/// ```
pub fn vtu_string(t: f64, cells: &[SheetCell]) -> String {
    let nc = cells.len();
    let mut s = String::with_capacity(400 + nc * 600);
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n",
    );
    let _ = writeln!(
        s,
        "<FieldData><DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">{t:e}</DataArray></FieldData>"
    );
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{nc}\">",
        8 * nc
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for c in cells {
        for z in [0.0, c.height] {
            for (x, y) in [
                (c.x[0], c.y[0]),
                (c.x[1], c.y[0]),
                (c.x[1], c.y[1]),
                (c.x[0], c.y[1]),
            ] {
                let _ = writeln!(s, "{x:e} {y:e} {z:e}");
            }
        }
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for i in 0..nc {
        let b = 8 * i;
        let _ = writeln!(
            s,
            "{} {} {} {} {} {} {} {}",
            b,
            b + 1,
            b + 2,
            b + 3,
            b + 4,
            b + 5,
            b + 6,
            b + 7
        );
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 0..nc {
        let _ = writeln!(s, "{}", 8 * (i + 1));
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..nc {
        s.push_str("12\n");
    }
    s.push_str("</DataArray>\n</Cells>\n<CellData Scalars=\"pressure\">\n");
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
    for (name, f) in fields {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
        );
        for c in cells {
            let _ = writeln!(s, "{:e}", f(c));
        }
        s.push_str("</DataArray>\n");
    }
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// Writes one snapshot to `path` (`.vtu`).
pub fn write_vtu(path: &Path, t: f64, cells: &[SheetCell]) -> io::Result<()> {
    let mut f = io::BufWriter::new(std::fs::File::create(path)?);
    f.write_all(vtu_string(t, cells).as_bytes())?;
    f.flush()
}

/// Writes a ParaView collection (`.pvd`) listing `(time, file name relative to the .pvd)`.
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> io::Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
    );
    for (t, file) in entries {
        let _ = writeln!(
            s,
            "<DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    std::fs::write(path, s)
}
