//! Per-run arrays as a numpy `.npz` archive (`run_<label>.npz`, read with `numpy.load`), the
//! layout `numpy.savez` writes: a zip of `.npy` members, stored uncompressed.
//!
//! Members (all float64 unless noted):
//! * `series/<name>` — every series column by name (`series/t`, `series/length`, …), length T;
//! * `profiles/t` — the profile times, length P; `profiles/cells` (int64) — cells (nodes) per
//!   profile; `profiles/<field>` (`X`, `x`, `stretch`, `pressure`, extra fields) — stacked
//!   P × cells when every profile has the same size, else concatenated in time order (split
//!   with `numpy.split(a, numpy.cumsum(cells)[:-1])`, e.g. a proliferating line); a field a
//!   profile lacks makes that member absent rather than padded;
//! * `divisions/t`, `divisions/x`, `divisions/x_over_length`, `divisions/parent` and
//!   `divisions/cells_after` (int64) — the division events, when there are any — and
//!   `divisions/age`, the dividing cells' ages, when the model follows individual cells, and
//!   `divisions/cell`, `divisions/daughter_1`, `divisions/daughter_2` (int64), their
//!   identities, when it traces their lineage;
//! * `reference/series/t`, `reference/series/max_pressure`, `reference/series/min_stretch`,
//!   `reference/profiles/{t, X, stretch, pressure}` and `reference/equilibrium/{t, X, x}` —
//!   the analytic reference the run carries ([`crate::observe::AnalyticReference`]; its label
//!   is in `summary.json`), profiles stacked times × points, each part only when present.
//!
//! `.npy` serialisation is npyz's; the zip container is the `zip` crate's (no compression, so
//! no compression backend is built).

use crate::observe::RunRecord;
use npyz::WriterBuilder as _;
use std::collections::BTreeMap;
use std::io::{self, Seek, Write};
use std::path::Path;

/// One member: its shape and data.
pub(crate) enum Member {
    F64(Vec<u64>, Vec<f64>),
    I64(Vec<u64>, Vec<i64>),
}

/// The members of a run's archive, by name (without `.npy`).
pub(crate) fn members(rec: &RunRecord) -> BTreeMap<String, Member> {
    let mut m = BTreeMap::new();
    for (k, v) in super::files::series_columns(rec) {
        m.insert(
            format!("series/{k}"),
            Member::F64(vec![v.len() as u64], v.clone()),
        );
    }
    let p = &rec.profiles;
    if !p.is_empty() {
        let times: Vec<f64> = p.iter().map(|q| q.t).collect();
        let cells: Vec<i64> = p.iter().map(|q| q.x_ref.len() as i64).collect();
        let rect = cells.windows(2).all(|w| w[0] == w[1]);
        m.insert(
            "profiles/t".into(),
            Member::F64(vec![times.len() as u64], times),
        );
        let mut fields: Vec<&str> = vec!["X", "x", "stretch", "pressure"];
        let mut extra: Vec<&str> = p
            .iter()
            .flat_map(|q| q.extra.keys().map(String::as_str))
            .collect();
        extra.sort_unstable();
        extra.dedup();
        fields.extend(extra);
        for f in fields {
            let cols: Option<Vec<&Vec<f64>>> = p
                .iter()
                .map(|q| match f {
                    "X" => Some(&q.x_ref),
                    "x" => Some(&q.x),
                    "stretch" => Some(&q.stretch),
                    "pressure" => Some(&q.pressure),
                    k => q.extra.get(k),
                })
                .collect();
            let Some(cols) = cols else { continue };
            // a field of another length than the profile's cells (e.g. per-boundary) is kept
            // concatenated
            let same = cols.iter().zip(&cells).all(|(c, n)| c.len() as i64 == *n);
            let data: Vec<f64> = cols.iter().flat_map(|c| c.iter().copied()).collect();
            let shape = if rect && same {
                vec![p.len() as u64, cells[0] as u64]
            } else {
                vec![data.len() as u64]
            };
            let name = super::files::profile_field_name(rec, f);
            m.insert(format!("profiles/{name}"), Member::F64(shape, data));
        }
        m.insert(
            "profiles/cells".into(),
            Member::I64(vec![cells.len() as u64], cells),
        );
    }
    if !rec.divisions.is_empty() {
        use crate::events::log::{division_columns, DivisionColumn};
        let n = vec![rec.divisions.len() as u64];
        for (name, column) in division_columns(&rec.divisions) {
            let member = match column {
                DivisionColumn::F64(v) => Member::F64(n.clone(), v),
                DivisionColumn::I64(v) => Member::I64(n.clone(), v),
            };
            m.insert(format!("divisions/{name}"), member);
        }
    }
    if let Some(r) = &rec.reference {
        let vec = |v: &[f64]| Member::F64(vec![v.len() as u64], v.to_vec());
        if !r.series.t.is_empty() {
            m.insert("reference/series/t".into(), vec(&r.series.t));
            m.insert(
                "reference/series/max_pressure".into(),
                vec(&r.series.max_pressure),
            );
            m.insert(
                "reference/series/min_stretch".into(),
                vec(&r.series.min_stretch),
            );
        }
        // every profile of one reference has the same points (one configuration)
        let stack = |rows: Vec<&Vec<f64>>| {
            let data: Vec<f64> = rows.iter().flat_map(|c| c.iter().copied()).collect();
            let width = rows.first().map_or(0, |c| c.len());
            if rows.iter().all(|c| c.len() == width) {
                Member::F64(vec![rows.len() as u64, width as u64], data)
            } else {
                Member::F64(vec![data.len() as u64], data)
            }
        };
        let p = &r.profiles;
        if !p.is_empty() {
            let t: Vec<f64> = p.iter().map(|q| q.t).collect();
            m.insert("reference/profiles/t".into(), vec(&t));
            m.insert(
                "reference/profiles/X".into(),
                stack(p.iter().map(|q| &q.x_ref).collect()),
            );
            m.insert(
                "reference/profiles/stretch".into(),
                stack(p.iter().map(|q| &q.stretch).collect()),
            );
            m.insert(
                "reference/profiles/pressure".into(),
                stack(p.iter().map(|q| &q.pressure).collect()),
            );
        }
        let e = &r.equilibrium;
        if !e.is_empty() {
            let t: Vec<f64> = e.iter().map(|q| q.t).collect();
            m.insert("reference/equilibrium/t".into(), vec(&t));
            m.insert(
                "reference/equilibrium/X".into(),
                stack(e.iter().map(|q| &q.x_ref).collect()),
            );
            m.insert(
                "reference/equilibrium/x".into(),
                stack(e.iter().map(|q| &q.x).collect()),
            );
        }
    }
    m
}

/// Writes the archive of `rec` to `w`.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::npz::write_npz;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// rec.series.t = vec![0.0, 1.0];
/// let mut bytes = std::io::Cursor::new(Vec::new());
/// write_npz(&rec, &mut bytes).unwrap();
/// let zip = bytes.into_inner();
/// assert_eq!(&zip[..2], b"PK"); // a zip of .npy members, as numpy.savez writes
/// assert!(zip.windows(12).any(|w| w == b"series/t.npy"));
/// ```
pub fn write_npz<W: Write + Seek>(rec: &RunRecord, w: W) -> io::Result<()> {
    let mut zip = zip::ZipWriter::new(w);
    for (name, member) in members(rec) {
        let bytes = match &member {
            Member::F64(_, v) => 8 * v.len(),
            Member::I64(_, v) => 8 * v.len(),
        };
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored)
            .large_file(bytes as u64 > u32::MAX as u64 / 2);
        zip.start_file(format!("{name}.npy"), opts)
            .map_err(io::Error::other)?;
        // npyz writes one element at a time; straight into the zip writer each 8 bytes paid
        // the zip's per-call bookkeeping and checksum (most of the write phase at 10⁶ cells):
        // a buffer hands the zip writer blocks instead
        let mut buf = io::BufWriter::with_capacity(1 << 16, &mut zip);
        match member {
            Member::F64(shape, v) => {
                let mut a = npyz::WriteOptions::<f64>::new()
                    .default_dtype()
                    .shape(&shape)
                    .writer(&mut buf)
                    .begin_nd()?;
                a.extend(v)?;
                a.finish()?;
            }
            Member::I64(shape, v) => {
                let mut a = npyz::WriteOptions::<i64>::new()
                    .default_dtype()
                    .shape(&shape)
                    .writer(&mut buf)
                    .begin_nd()?;
                a.extend(v)?;
                a.finish()?;
            }
        }
        buf.flush()?;
    }
    zip.finish().map_err(io::Error::other)?;
    Ok(())
}

/// Writes `rec`'s archive to `path` atomically.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::npz::{member_names, write_npz_file};
/// let rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// let path = std::env::temp_dir().join(format!("celltissue_doc_{}.npz", std::process::id()));
/// write_npz_file(&path, &rec).unwrap();
/// assert!(path.exists() && member_names(&rec).contains(&"series/t".to_string()));
/// std::fs::remove_file(&path).unwrap();
/// ```
pub fn write_npz_file(path: &Path, rec: &RunRecord) -> io::Result<()> {
    super::atomic::with_temp_file(path, |tmp| {
        let f = std::fs::File::create(tmp)?;
        let mut w = io::BufWriter::new(f);
        write_npz(rec, &mut w)?;
        w.flush()
    })
}

/// Member names of an archive written by [`write_npz`] for `rec` (without `.npy`).
///
/// ```
/// use celltissue::observe::*;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![],
///     reference: None, accuracy_check: None };
/// rec.series.t = vec![0.0, 1.0];
/// let names = celltissue::output::npz::member_names(&rec);
/// assert!(names.contains(&"series/t".to_string()));
/// ```
pub fn member_names(rec: &RunRecord) -> Vec<String> {
    members(rec).into_keys().collect()
}
