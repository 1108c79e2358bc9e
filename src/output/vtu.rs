//! VTK XML unstructured grids (`.vtu`) for ParaView, binary: every array is a zlib stream,
//! deflated (flate2) where a sample shows it shrinks by more than 40 % and stored otherwise,
//! base64-encoded inline (`format="binary"`, `compressor="vtkZLibDataCompressor"`, UInt64
//! headers, point indices as Int32 while they fit); and `.pvd` collections that index the
//! snapshots of a run by time.
//!
//! `write_snapshots` writes the lines, rings and sheets of a scenario (one snapshot per profile
//! time, `<label>_NNNN.vtu` or `.vtr`, and `<label>.pvd`). A straight line whose cells meet
//! end to end is a rectilinear grid ([`super::vtr`]); otherwise a line's cell is a VTK line
//! segment of its current length about its centre on the x axis — for a ring, the chord of its
//! arc on a circle of the ring's current length — carrying `stretch`, `pressure` and every
//! other per-cell field; a sheet's cell is a hexahedron rebuilt from its profile
//! ([`crate::sheet::vtk`]). The snapshot's time is its field data `TIME`.

use super::OutputError;
use crate::observe::{Profile, Summary};
use crate::scenario::{ModelConfig, Scenario};
use base64::Engine as _;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// VTK cell type: line segment.
pub const VTK_LINE: u8 = 3;
/// VTK cell type: hexahedron.
pub const VTK_HEXAHEDRON: u8 = 12;

/// Runs whose profiles hold more cells than this in total get no `.vtu` snapshots (their
/// `.npz` holds the same data): compressing ~100 MB per snapshot at 10⁶ cells would cost more
/// than the solve.
pub const VTU_MAX_CELLS: usize = 400_000;

/// An unstructured grid: points, cells by connectivity, per-cell data.
///
/// ```
/// use celltissue::output::vtu::{vtu_string, Grid};
/// // one unit square (VTK_QUAD = 9) carrying a pressure
/// let g = Grid {
///     points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
///     connectivity: vec![0, 1, 2, 3], offsets: vec![4], types: vec![9],
///     cell_data: vec![("pressure".into(), vec![1.0])],
/// };
/// let xml = vtu_string(0.5, &g).unwrap();
/// assert!(xml.contains("NumberOfPoints=\"4\"") && xml.contains("Name=\"pressure\""));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grid {
    /// Point coordinates, `[x, y, z]`.
    pub points: Vec<[f64; 3]>,
    /// Point indices of all cells, concatenated.
    pub connectivity: Vec<i64>,
    /// End of each cell in `connectivity`.
    pub offsets: Vec<i64>,
    /// VTK cell type of each cell.
    pub types: Vec<u8>,
    /// Per-cell fields by name (each as long as `types`).
    pub cell_data: Vec<(String, Vec<f64>)>,
}

/// Arrays whose leading [`SAMPLE_BYTES`] deflate to more than this fraction of their size are
/// stored in their zlib stream rather than deflated: the profile's full-precision fields (x,
/// pressure, σ) shrink by a fifth to two fifths at about 170 MB/s, while storing runs at memory
/// speed (at 10⁵ cells and three snapshots, deflating every array was most of the write phase).
const DEFLATE_WORTH: f64 = 0.6;

/// The leading bytes of an array whose deflated size decides how it is encoded
/// ([`DEFLATE_WORTH`]).
const SAMPLE_BYTES: usize = 1 << 16;

/// `raw` as a zlib stream: deflated at the fastest level when its leading [`SAMPLE_BYTES`]
/// shrink to at most [`DEFLATE_WORTH`] of their size, stored ([`stored`]) otherwise. The
/// sample is the start of the deflated stream itself (flushed to measure it), so an array that
/// is deflated is deflated once.
fn zlib(raw: &[u8]) -> io::Result<Vec<u8>> {
    let (sample, rest) = raw.split_at(raw.len().min(SAMPLE_BYTES));
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    z.write_all(sample)?;
    z.flush()?;
    let small = sample.len() < 256;
    if !small && z.get_ref().len() as f64 > DEFLATE_WORTH * sample.len() as f64 {
        return Ok(stored(raw));
    }
    z.write_all(rest)?;
    z.finish()
}

/// `raw` as a zlib stream of stored deflate blocks (RFC 1950/1951: a 2-byte header, blocks of
/// at most 65 535 bytes each behind a 5-byte header, the Adler-32 of `raw`). Written here
/// because miniz_oxide's level 0 runs at the speed of its level 1 (about 170 MB/s on a profile
/// field, against a memory copy for this); any zlib reader (ParaView, meshio, Python's `zlib`)
/// inflates it.
fn stored(raw: &[u8]) -> Vec<u8> {
    const BLOCK: usize = 65_535;
    let blocks = raw.len().div_ceil(BLOCK).max(1);
    let mut out = Vec::with_capacity(raw.len() + 5 * blocks + 6);
    out.extend_from_slice(&[0x78, 0x01]);
    let mut chunks = raw.chunks(BLOCK).peekable();
    if chunks.peek().is_none() {
        out.extend_from_slice(&[1, 0, 0, 0xff, 0xff]);
    }
    while let Some(chunk) = chunks.next() {
        let last = u8::from(chunks.peek().is_none());
        let len = chunk.len() as u16;
        out.push(last);
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(chunk);
    }
    out.extend_from_slice(&adler2::adler32_slice(raw).to_be_bytes());
    out
}

/// One array as VTK's compressed binary: base64(header) + base64(zlib(data)), one block; the
/// zlib stream deflated or stored ([`zlib`]).
fn encode(raw: &[u8]) -> io::Result<String> {
    let packed = zlib(raw)?;
    let n = raw.len() as u64;
    let header: Vec<u8> = if raw.is_empty() {
        [0u64, 0, 0].iter().flat_map(|v| v.to_le_bytes()).collect()
    } else {
        [1u64, n, n, packed.len() as u64]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect()
    };
    let b = base64::engine::general_purpose::STANDARD;
    Ok(format!("{}{}", b.encode(header), b.encode(packed)))
}

/// One data array of a VTK XML document before encoding: its VTK type, `Name`, number of
/// components and values (borrowed from the grid).
pub(super) struct Array<'a> {
    pub(super) ty: &'static str,
    pub(super) name: &'a str,
    pub(super) comps: usize,
    pub(super) values: Values<'a>,
}

/// The values of an [`Array`].
pub(super) enum Values<'a> {
    F64(&'a [f64]),
    Points(&'a [[f64; 3]]),
    I64(&'a [i64]),
    /// Indices written as `Int32` (each fits).
    I64AsI32(&'a [i64]),
    U8(&'a [u8]),
}

impl Array<'_> {
    /// The little-endian bytes of the values.
    fn raw(&self) -> Vec<u8> {
        fn le<const W: usize, T: Copy>(v: &[T], f: impl Fn(T) -> [u8; W]) -> Vec<u8> {
            let mut out = Vec::with_capacity(v.len() * W);
            for &x in v {
                out.extend_from_slice(&f(x));
            }
            out
        }
        match self.values {
            Values::F64(v) => le(v, f64::to_le_bytes),
            Values::Points(p) => le(p.as_flattened(), f64::to_le_bytes),
            Values::I64(v) => le(v, i64::to_le_bytes),
            Values::I64AsI32(v) => le(v, |i| (i as i32).to_le_bytes()),
            Values::U8(v) => v.to_vec(),
        }
    }

    /// The `<DataArray>` element, values encoded ([`encode`]).
    pub(super) fn element(&self) -> io::Result<String> {
        let name = if self.name.is_empty() {
            String::new()
        } else {
            format!(" Name=\"{}\"", self.name)
        };
        let comps = if self.comps > 1 {
            format!(" NumberOfComponents=\"{}\"", self.comps)
        } else {
            String::new()
        };
        Ok(format!(
            "<DataArray type=\"{}\"{name}{comps} format=\"binary\">{}</DataArray>\n",
            self.ty,
            encode(&self.raw())?
        ))
    }
}

/// The `.vtu` document of `grid` at time `t`. The arrays are compressed concurrently on the
/// rayon pool (compression is most of the write phase of a large line: at 10⁵ cells three
/// snapshots took 0.18 s one array after another); the document is the same in any order.
///
/// ```
/// use celltissue::output::vtu::{vtu_string, Grid, VTK_LINE};
/// let g = Grid { points: vec![[0.0; 3], [1.0, 0.0, 0.0]], connectivity: vec![0, 1],
///     offsets: vec![2], types: vec![VTK_LINE], cell_data: vec![("p".into(), vec![1.5])] };
/// let s = vtu_string(0.5, &g).unwrap();
/// assert!(s.contains("NumberOfCells=\"1\"") && s.contains("compressor=\"vtkZLibDataCompressor\""));
/// ```
pub fn vtu_string<'a>(t: f64, grid: &'a Grid) -> io::Result<String> {
    use rayon::prelude::*;
    let array = |ty, name, comps, values| Array {
        ty,
        name,
        comps,
        values,
    };
    // point indices as Int32 where they all fit: half the bytes to compress
    let indices = |name, v: &'a [i64]| {
        if v.iter().all(|&i| i32::try_from(i).is_ok()) {
            array("Int32", name, 1, Values::I64AsI32(v))
        } else {
            array("Int64", name, 1, Values::I64(v))
        }
    };
    // the points, the three cell arrays, then the cell data
    let mut arrays = vec![
        array("Float64", "", 3, Values::Points(&grid.points)),
        indices("connectivity", &grid.connectivity),
        indices("offsets", &grid.offsets),
        array("UInt8", "types", 1, Values::U8(&grid.types)),
    ];
    for (name, v) in &grid.cell_data {
        arrays.push(array("Float64", name, 1, Values::F64(v)));
    }
    let elements = arrays
        .par_iter()
        .map(Array::element)
        .collect::<io::Result<Vec<String>>>()?;
    let mut s = String::with_capacity(1024 + elements.iter().map(String::len).sum::<usize>());
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid>\n");
    s.push_str(&time_field(t)?);
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        grid.points.len(),
        grid.types.len()
    );
    s.push_str("<Points>\n");
    s.push_str(&elements[0]);
    s.push_str("</Points>\n<Cells>\n");
    for e in &elements[1..4] {
        s.push_str(e);
    }
    s.push_str("</Cells>\n");
    s.push_str(cell_data_start(&grid.cell_data));
    for e in &elements[4..] {
        s.push_str(e);
    }
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    Ok(s)
}

/// The opening `<CellData>` tag of a snapshot, naming `pressure` its active scalars when the
/// cells carry one.
pub(super) fn cell_data_start(cell_data: &[(String, Vec<f64>)]) -> &'static str {
    if cell_data.iter().any(|(n, _)| n == "pressure") {
        "<CellData Scalars=\"pressure\">\n"
    } else {
        "<CellData>\n"
    }
}

/// The `<FieldData>` block of a snapshot: its time as one `TIME` value. A field-data array
/// states its `NumberOfTuples` (VTK's reader takes the length of point and cell data from the
/// grid, but of field data only from this attribute: without it VTK's XML readers, ParaView's,
/// read an empty `TIME`).
pub(super) fn time_field(t: f64) -> io::Result<String> {
    Ok(format!(
        "<FieldData>\n<DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"binary\">{}</DataArray>\n</FieldData>\n",
        encode(&t.to_le_bytes())?
    ))
}

/// Writes `grid` at time `t` to `path` atomically.
///
/// ```
/// use celltissue::output::vtu::{line_grid, write_pvd, write_vtu};
/// use celltissue::observe::Profile;
/// let p = Profile { t: 1.0, x_ref: vec![0.5, 1.5], x: vec![0.45, 1.35], stretch: vec![0.9, 0.9],
///                   pressure: vec![1.2, 1.2], ..Default::default() };
/// let dir = std::env::temp_dir().join(format!("ct_vtu_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// write_vtu(&dir.join("line_0000.vtu"), 1.0, &line_grid(&p, false)).unwrap();
/// write_pvd(&dir.join("line.pvd"), &[(1.0, "line_0000.vtu".into())]).unwrap();
/// let pvd = std::fs::read_to_string(dir.join("line.pvd")).unwrap();
/// assert!(pvd.contains("file=\"line_0000.vtu\""));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_vtu(path: &Path, t: f64, grid: &Grid) -> io::Result<()> {
    let text = vtu_string(t, grid)?;
    super::atomic::write(path, text.as_bytes())
}

/// Writes a ParaView collection (`.pvd`) listing `(time, file name relative to the .pvd)`,
/// atomically.
///
/// ```
/// use celltissue::output::vtu::write_pvd;
/// let dir = std::env::temp_dir().join(format!("ct_pvd_doc_{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let entries = [(0.0, "run_0000.vtu".to_string()), (2.5, "run_0001.vtu".to_string())];
/// write_pvd(&dir.join("run.pvd"), &entries).unwrap();
/// let pvd = std::fs::read_to_string(dir.join("run.pvd")).unwrap();
/// assert!(pvd.contains("timestep=\"2.5e0\"") && pvd.contains("file=\"run_0001.vtu\""));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
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
    super::atomic::write(path, s.as_bytes())
}

/// The cells of a line profile as segments on the x axis, each its current extent
/// ([`Profile::cell_ends`]; `ring`: as chords on a circle whose circumference is the ring's
/// current length). Cells that meet end to end share their boundary points.
///
/// ```
/// use celltissue::observe::Profile;
/// let p = Profile { t: 0.0, x_ref: vec![0.5, 1.5], x: vec![0.45, 1.35],
///     stretch: vec![0.9, 0.9], pressure: vec![1.2, 1.2], extra: Default::default() };
/// let g = celltissue::output::vtu::line_grid(&p, false);
/// assert_eq!(g.types.len(), 2);
/// // one polyline: boundaries 0, 0.9, 1.8, the second cell from point 1 to point 2
/// assert_eq!(g.points.len(), 3);
/// assert!((g.points[1][0] - 0.9).abs() < 1e-12 && (g.points[2][0] - 1.8).abs() < 1e-12);
/// assert_eq!(g.connectivity, [0, 1, 1, 2]);
/// // a ring closes on its first point
/// assert_eq!(celltissue::output::vtu::line_grid(&p, true).connectivity, [0, 1, 1, 0]);
/// ```
pub fn line_grid(p: &Profile, ring: bool) -> Grid {
    let n = line_cells(p);
    let mut ends = p.cell_ends();
    ends.truncate(n);
    let circumference: f64 = ends.iter().map(|(a, b)| b - a).sum();
    let place = |s: f64| -> [f64; 3] {
        if ring && circumference > 0.0 {
            let r = circumference / std::f64::consts::TAU;
            let a = std::f64::consts::TAU * s / circumference;
            [r * a.cos(), r * a.sin(), 0.0]
        } else {
            [s, 0.0, 0.0]
        }
    };
    // cells that meet end to end (a line's recorded cell lengths) share their boundary points:
    // one connected polyline of N + 1 points (a ring's N, its last cell closing on the first
    // point), which ParaView can interpolate along; otherwise two points per cell
    let (points, connectivity): (Vec<[f64; 3]>, Vec<i64>) = match joined_boundaries(&ends) {
        Some(boundaries) => {
            let points: Vec<[f64; 3]> = boundaries
                .into_iter()
                .take(if ring { n } else { n + 1 })
                .map(place)
                .collect();
            let m = points.len() as i64;
            (
                points,
                (0..n as i64).flat_map(|j| [j, (j + 1) % m]).collect(),
            )
        }
        None => (
            ends.iter()
                .flat_map(|&(a, b)| [place(a), place(b)])
                .collect(),
            (0..2 * n as i64).collect(),
        ),
    };
    Grid {
        points,
        connectivity,
        offsets: (1..=n as i64).map(|k| 2 * k).collect(),
        types: vec![VTK_LINE; n],
        cell_data: line_fields(p, n),
    }
}

/// The number of cells a line profile draws: the length of its shortest core field.
pub(super) fn line_cells(p: &Profile) -> usize {
    p.x_ref
        .len()
        .min(p.x.len())
        .min(p.stretch.len())
        .min(p.pressure.len())
}

/// The `N + 1` boundaries of cells that meet end to end (each cell's left end, then the last
/// one's right end), or `None` when two neighbours are apart by more than 1e-9 of the line's
/// extent (or there is no cell).
pub(super) fn joined_boundaries(ends: &[(f64, f64)]) -> Option<Vec<f64>> {
    let circumference: f64 = ends.iter().map(|(a, b)| b - a).sum();
    let scale = ends.last()?.1.abs() + circumference.abs();
    let joined = ends
        .windows(2)
        .all(|w| (w[0].1 - w[1].0).abs() <= 1e-9 * scale);
    joined.then(|| {
        ends.iter()
            .map(|e| e.0)
            .chain(ends.last().map(|e| e.1))
            .collect()
    })
}

/// The per-cell fields of the first `n` cells of a line profile: `stretch`, `pressure`, `X`,
/// `x`, then every extra field of `n` values.
pub(super) fn line_fields(p: &Profile, n: usize) -> Vec<(String, Vec<f64>)> {
    let mut fields = vec![
        ("stretch".to_string(), p.stretch[..n].to_vec()),
        ("pressure".to_string(), p.pressure[..n].to_vec()),
        ("X".to_string(), p.x_ref[..n].to_vec()),
        ("x".to_string(), p.x[..n].to_vec()),
    ];
    for (k, v) in &p.extra {
        if v.len() == n {
            fields.push((k.clone(), v.clone()));
        }
    }
    fields
}

/// How the snapshots of one run are drawn.
enum Snapshots {
    /// Straight lines of cells that meet end to end, every profile: `.vtr` (the boundaries
    /// of each profile's cells).
    Rectilinear(Vec<Vec<f64>>),
    /// Anything else (rings, sheets, cells apart): `.vtu` of this grid per profile.
    Unstructured(fn(&Profile) -> Grid),
}

/// Writes the snapshots and a `.pvd` per line, ring or sheet run (not shear columns, nor runs
/// whose profiles exceed [`VTU_MAX_CELLS`] cells in total); returns the paths. A run whose
/// every profile is a straight line of joined cells gets `.vtr` snapshots
/// ([`super::vtr`]), any other `.vtu`: one form per run, so a `.pvd` never mixes the two.
pub(crate) fn write_snapshots(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Result<Vec<PathBuf>, OutputError> {
    use super::vtr::{line_boundaries, write_vtr, Rectilinear};
    let slugs = super::files::unique_slugs(summary.runs.iter().map(|r| r.label.as_str()));
    let mut out = Vec::new();
    let err = |path: &Path| {
        let path = path.to_path_buf();
        move |source| OutputError::Write { path, source }
    };
    for (i, (rec, slug)) in summary.runs.iter().zip(&slugs).enumerate() {
        use crate::line::config::RightEndKind::Periodic;
        if rec.profiles.is_empty() || super::files::profile_rows(rec) > VTU_MAX_CELLS {
            continue;
        }
        let straight = || -> Snapshots {
            match rec.profiles.iter().map(line_boundaries).collect() {
                Some(boundaries) => Snapshots::Rectilinear(boundaries),
                None => Snapshots::Unstructured(|p| line_grid(p, false)),
            }
        };
        let mut snapshots = match scenario.runs.get(i).map(|s| &s.config) {
            Some(ModelConfig::Line(cfg)) if cfg.right_end == Periodic => {
                Snapshots::Unstructured(|p| line_grid(p, true))
            }
            Some(ModelConfig::Proliferating(cfg)) if cfg.line.right_end == Periodic => {
                Snapshots::Unstructured(|p| line_grid(p, true))
            }
            Some(ModelConfig::Line(_) | ModelConfig::Proliferating(_)) => straight(),
            Some(ModelConfig::Sheet(..)) => {
                Snapshots::Unstructured(crate::sheet::vtk::profile_grid)
            }
            _ => continue,
        };
        let mut entries = Vec::new();
        for (k, p) in rec.profiles.iter().enumerate() {
            let name = match &snapshots {
                Snapshots::Rectilinear(..) => format!("{slug}_{k:04}.vtr"),
                Snapshots::Unstructured(..) => format!("{slug}_{k:04}.vtu"),
            };
            let path = dir.join(&name);
            match &mut snapshots {
                Snapshots::Rectilinear(boundaries) => {
                    let x = std::mem::take(&mut boundaries[k]);
                    let cell_data = line_fields(p, x.len() - 1);
                    write_vtr(&path, p.t, &Rectilinear { x, cell_data })
                }
                Snapshots::Unstructured(grid) => write_vtu(&path, p.t, &grid(p)),
            }
            .map_err(err(&path))?;
            out.push(path);
            entries.push((p.t, name));
        }
        let path = dir.join(format!("{slug}.pvd"));
        write_pvd(&path, &entries).map_err(err(&path))?;
        out.push(path);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn inflate(z: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        flate2::read::ZlibDecoder::new(z)
            .read_to_end(&mut out)
            .expect("a valid zlib stream");
        out
    }

    /// Bytes that deflate cannot shrink (a 64-bit LCG's high bytes).
    fn noise(n: usize) -> Vec<u8> {
        let mut s = 0x2545_f491_4f6c_dd1d_u64;
        (0..n)
            .map(|_| {
                s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                (s >> 56) as u8
            })
            .collect()
    }

    #[test]
    fn stored_streams_inflate_to_their_bytes_at_every_block_boundary() {
        for n in [0, 1, 65_534, 65_535, 65_536, 3 * 65_535, 200_001] {
            let raw = noise(n);
            let z = stored(&raw);
            assert_eq!(inflate(&z), raw, "{n} bytes");
            // header, one 5-byte header per block (one empty block for no bytes), Adler-32
            assert_eq!(
                z.len(),
                2 + 5 * n.div_ceil(65_535).max(1) + n + 4,
                "{n} bytes"
            );
        }
    }

    #[test]
    fn incompressible_arrays_are_stored_and_regular_ones_deflated() {
        let noisy = noise(800_000);
        // stored: the stream is the bytes plus 5 per 65 535-byte block and 6 of framing
        assert_eq!(zlib(&noisy).unwrap().len(), 800_000 + 5 * 13 + 6);
        let indices: Vec<u8> = (0..100_000i32).flat_map(i32::to_le_bytes).collect();
        assert!(zlib(&indices).unwrap().len() < indices.len() / 2);
        for raw in [noisy, indices] {
            let text = encode(&raw).unwrap();
            let b = base64::engine::general_purpose::STANDARD;
            // the UInt64 header [1 block, size, size, packed size] is 32 bytes: 44 base64 chars
            let header = b.decode(&text[..44]).unwrap();
            let packed = b.decode(&text[44..]).unwrap();
            assert_eq!(
                u64::from_le_bytes(header[24..32].try_into().unwrap()),
                packed.len() as u64
            );
            assert_eq!(inflate(&packed), raw);
        }
    }

    #[test]
    fn point_indices_are_int32_while_they_fit() {
        let g = Grid {
            points: vec![[0.0; 3], [1.0, 0.0, 0.0]],
            connectivity: vec![0, 1],
            offsets: vec![2],
            types: vec![VTK_LINE],
            cell_data: vec![],
        };
        let s = vtu_string(0.0, &g).unwrap();
        assert!(s.contains("type=\"Int32\" Name=\"connectivity\""));
        let big = Grid {
            connectivity: vec![0, i64::from(i32::MAX) + 1],
            ..g
        };
        let s = vtu_string(0.0, &big).unwrap();
        assert!(s.contains("type=\"Int64\" Name=\"connectivity\""));
    }
}
