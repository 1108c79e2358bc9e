//! Array data and provenance: every run's `.npz` holds its series by name, its
//! profiles stacked times × cells and its divisions, bit for bit the values of the record;
//! `summary.json` carries provenance and no copy of the profiles; lines get binary (zlib +
//! base64) rectilinear `.vtr` snapshots and rings `.vtu`, each with a `.pvd`, that decode to the
//! profile values and carry their time.

use base64::Engine as _;
use celltissue::observe::{RunRecord, Summary};
use celltissue::output;
use celltissue::scenario::{execute, load_str};
use std::io::Read as _;
use std::path::{Path, PathBuf};

const LINE: &str = r#"
name = "arrays"
[output]
series = { start = 0, stop = 2, count = 11 }
profiles = [0, 1, 2]
[model]
kind = "line"
models = ["discrete", "continuum"]
cells = 12
nodes = 12
K = 1.0
"#;

const RING: &str = r#"
name = "ring"
[output]
series = [0, 1, 2]
profiles = [1, 2]
[model]
kind = "line"
models = ["discrete"]
cells = 16
right_end = "periodic"
active = { beta = -1.0, omega = 0.0625 }
K = 0.01
"#;

fn run(name: &str, text: &str) -> (PathBuf, Summary) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let s = load_str(text, Path::new("s.toml"), &[]).unwrap();
    let summary = execute::run_all(&s, execute::run_spec, |_| {});
    let opts = output::WriteOptions {
        provenance: Some(output::provenance::Provenance::collect(&s.table, 1)),
        no_plots: true,
        ..Default::default()
    };
    output::write_all_with(&dir, &s, &summary, &opts).unwrap();
    (dir, summary)
}

/// The members of an `.npz` as (shape, f64 data) (int64 members converted).
fn read_npz(path: &Path) -> Vec<(String, Vec<u64>, Vec<f64>)> {
    let f = std::fs::File::open(path).unwrap();
    let mut zip = zip::ZipArchive::new(f).unwrap();
    let mut out = Vec::new();
    for i in 0..zip.len() {
        let mut m = zip.by_index(i).unwrap();
        let name = m.name().trim_end_matches(".npy").to_string();
        let mut bytes = Vec::new();
        m.read_to_end(&mut bytes).unwrap();
        let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
        let shape = npy.shape().to_vec();
        let data: Vec<f64> = if [
            "profiles/cells",
            "divisions/parent",
            "divisions/cells_after",
        ]
        .contains(&name.as_str())
        {
            npy.into_vec::<i64>()
                .unwrap()
                .into_iter()
                .map(|v| v as f64)
                .collect()
        } else {
            npy.into_vec::<f64>().unwrap()
        };
        out.push((name, shape, data));
    }
    out
}

fn member<'a>(
    m: &'a [(String, Vec<u64>, Vec<f64>)],
    name: &str,
) -> &'a (String, Vec<u64>, Vec<f64>) {
    m.iter()
        .find(|x| x.0 == name)
        .unwrap_or_else(|| panic!("{name} missing"))
}

fn check_npz(dir: &Path, rec: &RunRecord, arrays: &str) {
    let m = read_npz(&dir.join(arrays));
    assert_eq!(member(&m, "series/t").2, rec.series.t);
    assert_eq!(member(&m, "series/max_pressure").2, rec.series.max_pressure);
    for (k, v) in &rec.series.extra {
        assert_eq!(&member(&m, &format!("series/{k}")).2, v, "series/{k}");
    }
    let p = &rec.profiles;
    let n = p[0].stretch.len() as u64;
    let (_, shape, data) = member(&m, "profiles/stretch");
    assert_eq!(shape, &vec![p.len() as u64, n]);
    let stacked: Vec<f64> = p.iter().flat_map(|q| q.stretch.iter().copied()).collect();
    assert_eq!(data, &stacked);
    assert_eq!(
        member(&m, "profiles/t").2,
        p.iter().map(|q| q.t).collect::<Vec<_>>()
    );
    let x: Vec<f64> = p.iter().flat_map(|q| q.x_ref.iter().copied()).collect();
    assert_eq!(member(&m, "profiles/X").2, x);
}

#[test]
fn npz_holds_series_and_profiles_and_summary_does_not_repeat_them() {
    let (dir, summary) = run("arrays_line", LINE);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let prov = &v["provenance"];
    assert_eq!(prov["version"], env!("CARGO_PKG_VERSION"));
    for key in ["date", "command_line", "threads", "available_parallelism"] {
        assert!(prov.get(key).is_some(), "provenance.{key}");
    }
    for (r, rec) in v["runs"].as_array().unwrap().iter().zip(&summary.runs) {
        assert!(r.get("profiles").is_none());
        assert_eq!(r["profile_times"], serde_json::json!([0.0, 1.0, 2.0]));
        // counters are integers
        for (k, c) in r["stats"].as_object().unwrap() {
            if k != "wall_seconds" {
                assert!(c.is_u64(), "stats.{k} = {c}");
            }
        }
        check_npz(&dir, rec, r["arrays"].as_str().unwrap());
    }
}

/// The bytes of one `format="binary"` zlib-compressed array of a `.vtu` or `.vtr`, by name.
fn vtu_bytes(text: &str, name: &str) -> Vec<u8> {
    // the snapshot's time is field data, which states its length
    let time = if name == "TIME" {
        " NumberOfTuples=\"1\""
    } else {
        ""
    };
    let key = format!("Name=\"{name}\"{time} format=\"binary\">");
    let start = text.find(&key).unwrap_or_else(|| panic!("{name}")) + key.len();
    let body = &text[start..start + text[start..].find('<').unwrap()];
    let b = base64::engine::general_purpose::STANDARD;
    // header: [blocks = 1, block size, last size, compressed size] as UInt64 = 32 bytes → 44 chars
    let header = b.decode(&body[..44]).unwrap();
    let raw_len = u64::from_le_bytes(header[8..16].try_into().unwrap()) as usize;
    let packed = b.decode(&body[44..]).unwrap();
    let mut raw = Vec::new();
    flate2::read::ZlibDecoder::new(&packed[..])
        .read_to_end(&mut raw)
        .unwrap();
    assert_eq!(raw.len(), raw_len);
    raw
}

/// Decodes one Float64 array of a `.vtu` or `.vtr` by name.
fn vtu_array(text: &str, name: &str) -> Vec<f64> {
    vtu_bytes(text, name)
        .chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn rings_get_vtu_and_lines_vtr_snapshots_with_a_pvd() {
    let (dir, summary) = run("arrays_ring", RING);
    let rec = &summary.runs[0];
    let pvd = std::fs::read_to_string(dir.join("discrete.pvd")).unwrap();
    assert!(pvd.contains("discrete_0000.vtu") && pvd.contains("discrete_0001.vtu"));
    let text = std::fs::read_to_string(dir.join("discrete_0001.vtu")).unwrap();
    assert!(!text.contains("format=\"ascii\""));
    assert_eq!(vtu_array(&text, "stretch"), rec.profiles[1].stretch);
    assert_eq!(vtu_array(&text, "pressure"), rec.profiles[1].pressure);
    assert_eq!(vtu_array(&text, "TIME"), [rec.profiles[1].t]);
    // the ring's cells lie on a circle whose circumference is the sum of the cell lengths
    let key = "NumberOfComponents=\"3\" format=\"binary\">";
    let i = text.find(key).unwrap();
    let fake = format!(
        "Name=\"points\" format=\"binary\">{}",
        &text[i + key.len()..]
    );
    let pts = vtu_array(&fake, "points");
    let radii: Vec<f64> = pts.chunks(3).map(|p| p[0].hypot(p[1])).collect();
    let r0 = radii[0];
    assert!(
        radii.iter().all(|r| (r - r0).abs() < 1e-9 * r0),
        "{radii:?}"
    );
    // a straight line is a rectilinear grid: its cells' boundaries as the x coordinates
    let (lines, summary) = run("arrays_line_vtu", LINE);
    for (r, rec) in summary.runs.iter().enumerate() {
        let label = ["discrete", "continuum"][r];
        let pvd = std::fs::read_to_string(lines.join(format!("{label}.pvd"))).unwrap();
        assert!(pvd.contains(&format!("{label}_0002.vtr")), "{pvd}");
        let text = std::fs::read_to_string(lines.join(format!("{label}_0002.vtr"))).unwrap();
        let p = &rec.profiles[2];
        assert!(text.contains("<Piece Extent=\"0 12 0 0 0 0\">"), "{label}");
        assert_eq!(vtu_array(&text, "TIME"), [p.t]);
        assert_eq!(vtu_array(&text, "stretch"), p.stretch, "{label}");
        assert_eq!(vtu_array(&text, "pressure"), p.pressure, "{label}");
        let ends = vtr_segment_ends(&text);
        for (j, (&(a, b), &x)) in ends.iter().zip(&p.x).enumerate() {
            assert!((0.5 * (a + b) - x).abs() < 1e-12, "{label} cell {j}");
        }
    }
}

/// The x coordinates of each cell's two ends of a `.vtr` (consecutive boundaries), in cell
/// order.
fn vtr_segment_ends(text: &str) -> Vec<(f64, f64)> {
    assert_eq!(vtu_array(text, "y_coordinates"), [0.0]);
    assert_eq!(vtu_array(text, "z_coordinates"), [0.0]);
    vtu_array(text, "x_coordinates")
        .windows(2)
        .map(|w| (w[0], w[1]))
        .collect()
}

#[test]
fn growing_and_dividing_cells_tile_their_line_in_the_vtr() {
    // cells that grow (g ≠ 1) and divide (daughters of their own reference length): each
    // drawn segment is the cell's current length about its centre, so the segments meet end
    // to end from the wall at 0 to the line's length (drawn from the elastic stretch times the
    // reference spacing, a growing cell was 1/g of its length, with gaps between the cells)
    let dividing = r#"
name = "tiles"
[output]
series = [0, 2, 4]
profiles = [2, 4]
[model]
kind = "line"
models = ["discrete"]
cells = 4
K = 0.01
right_end = "free"
growth = { law = "tanh", sigma0 = 0.1, gm = 1 }
division = { rule = "area", ratio = 2 }
"#;
    let (dir, summary) = run("arrays_tiles", dividing);
    let rec = &summary.runs[0];
    assert!(
        rec.profiles.last().unwrap().x.len() > 4,
        "the cells divided"
    );
    for (k, p) in rec.profiles.iter().enumerate() {
        let text = std::fs::read_to_string(dir.join(format!("discrete_{k:04}.vtr"))).unwrap();
        let ends = vtr_segment_ends(&text);
        let length = rec.series.length[k + 1]; // series [0, 2, 4], profiles [2, 4]
        assert_eq!(ends.len(), p.x.len());
        // N cells between N + 1 boundaries
        assert!(text.contains(&format!("WholeExtent=\"0 {} 0 0 0 0\"", p.x.len())));
        assert!(ends[0].0.abs() < 1e-12, "t = {}: {:?}", p.t, ends[0]);
        assert!((ends.last().unwrap().1 - length).abs() < 1e-9 * length);
        // each segment (between one cell's left end and the next one's) is the cell's total
        // stretch times its own reference length: the recorded `length`, and more than its
        // elastic stretch alone gives where g > 1
        let lengths = &p.extra["length"];
        for (j, &(a, b)) in ends.iter().enumerate() {
            assert!(((b - a) - lengths[j]).abs() < 1e-12 * length, "cell {j}");
        }
        assert!(p.extra["g"].iter().any(|&g| g > 1.1));
    }
}
