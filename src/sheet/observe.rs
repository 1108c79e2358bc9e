//! Chapter 4 observables (docs/model.md §6) and their [`RunRecord`](crate::observe::RunRecord)
//! series/profile keys.
//!
//! Sheet: `max p`, mean `p`, mean height `H`, `mean λ₃ / mean λ₂`, and the shared-boundary
//! mismatch `W_err = |W_{j+1/2,k} − W_s|` with the overlap
//! `W_s = min(y_b(j,k), y_b(j+1,k)) − max(y_b(j,k−1), y_b(j+1,k−1))` ((4.76)–(4.77), overlap
//! corrected), mean and max over the interior x-faces. Shear: `x_e`, `T_k`, `θ_k`, spread
//! `max tan θ − min tan θ`, mean `θ` and the top displacement `x_{e,M}`.

use super::shear::ShearFields;
use super::uniaxial::{SheetCell, UniaxialSheet};
use crate::energy::StrainEnergy;
use crate::observe::Profile;
use crate::runner::SeriesRow;

/// Series key: mean cell pressure.
pub const MEAN_PRESSURE: &str = "mean_pressure";
/// Series key: mean cell height `H = β₀λ₃`.
pub const MEAN_HEIGHT: &str = "mean_height";
/// Series key: `mean λ₃ / mean α₂` (`mean λ₃ / mean λ₂` without growth).
pub const MEAN_STRETCH_Z_OVER_Y: &str = "mean_stretch_z_over_y";
/// Series key: mean shared-boundary mismatch `W_err`.
pub const BOUNDARY_MISMATCH_MEAN: &str = "boundary_mismatch_mean";
/// Series key: max shared-boundary mismatch `W_err`.
pub const BOUNDARY_MISMATCH_MAX: &str = "boundary_mismatch_max";
/// Series key: x-position of the shear column's top edge.
pub const TOP_DISPLACEMENT: &str = "top_displacement";
/// Series key: `max tan θ − min tan θ` over the column.
pub const SHEAR_SPREAD: &str = "shear_spread";
/// Series key: mean shear angle θ (radians).
pub const MEAN_SHEAR_ANGLE: &str = "mean_shear_angle";
/// Series key: max over cells of the transverse elastic stretch α₂ (λ₂ without growth).
pub const MAX_STRETCH_Y: &str = "max_stretch_y";
/// Series key: min over cells of the transverse elastic stretch α₂ (λ₂ without growth).
pub const MIN_STRETCH_Y: &str = "min_stretch_y";
/// Series key: mean position of the side `y = w` (growing sheets only).
pub const MEAN_WIDTH: &str = "mean_width";

/// Scalar observables of one sheet snapshot.
///
/// ```
/// use celltissue::sheet::observe::sheet_observables;
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let y = sheet.initial_state();
/// let o = sheet_observables(&sheet, 0.0, &y, &sheet.cells(0.0, &y, &vec![0.0; y.len()]));
/// // the undeformed 10 × 10 sheet: length l₀ = 10, unit stretches, height β₀ = 1
/// assert_eq!((o.length, o.stretch_x, o.stretch_y), (10.0, [1.0; 2], [1.0; 2]));
/// assert!((o.mean_height - 1.0).abs() < 1e-15);
/// assert_eq!(o.width, None); // reported for growing sheets only
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SheetObservables {
    /// Time.
    pub t: f64,
    /// Length: the mean position of the side `x = l` (`l(t)` when prescribed).
    pub length: f64,
    /// Width: the mean position of the side `y = w`, for a growing sheet.
    pub width: Option<f64>,
    /// Max / min / mean pressure.
    pub pressure: [f64; 3],
    /// Max / min elastic stretch `α₁ = λ₁/g₁` ([`SheetCell::elastic_stretch`]; `λ₁` without
    /// growth), as a growing line's `stretch` is its elastic stretch.
    pub stretch_x: [f64; 2],
    /// Max / min elastic stretch `α₂ = λ₂/g₂` (`λ₂` without growth).
    pub stretch_y: [f64; 2],
    /// Mean height `H`.
    pub mean_height: f64,
    /// `mean λ₃ / mean α₂` (`mean λ₃ / mean λ₂` without growth; `λ₃` is elastic).
    pub stretch_z_over_y: f64,
    /// Mean and max `W_err` over interior x-faces (0 for a single column).
    pub mismatch: [f64; 2],
}

/// `W_err` (mean, max) over the interior x-faces of the sheet at state `y`.
///
/// ```
/// use celltissue::sheet::observe::boundary_mismatch;
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let mut y = sheet.initial_state();
/// assert_eq!(boundary_mismatch(&sheet, &y), [0.0, 0.0]);
/// y[sheet.iy(1, 1)] += 0.1; // raise one face of column 1: its cells no longer match column 2's
/// assert!(boundary_mismatch(&sheet, &y)[1] > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn boundary_mismatch<E: StrainEnergy>(sheet: &UniaxialSheet<E>, y: &[f64]) -> [f64; 2] {
    let (n, m) = sheet.grid();
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    for j in 1..n {
        for k in 1..=m {
            let (a0, a1) = (sheet.yb(y, j, k - 1), sheet.yb(y, j, k));
            let (b0, b1) = (sheet.yb(y, j + 1, k - 1), sheet.yb(y, j + 1, k));
            let w = 0.5 * ((a1 - a0) + (b1 - b0));
            let ws = a1.min(b1) - a0.max(b0);
            let e = (w - ws).abs();
            sum += e;
            max = max.max(e);
            count += 1;
        }
    }
    if count == 0 {
        [0.0, 0.0]
    } else {
        [sum / count as f64, max]
    }
}

/// Observables from the per-cell fields (and the state, for `W_err`).
///
/// ```
/// use celltissue::sheet::observe::sheet_observables;
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let y = sheet.initial_state();
/// let o = sheet_observables(&sheet, 0.0, &y, &sheet.cells(0.0, &y, &vec![0.0; y.len()]));
/// // at rest: unit stretches, p = μ, no mismatch
/// assert_eq!((o.length, o.stretch_x, o.mismatch), (10.0, [1.0, 1.0], [0.0, 0.0]));
/// assert!((o.pressure[2] - 1.0).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sheet_observables<E: StrainEnergy>(
    sheet: &UniaxialSheet<E>,
    t: f64,
    y: &[f64],
    cells: &[SheetCell],
) -> SheetObservables {
    let nc = cells.len() as f64;
    let mut o = SheetObservables {
        t,
        length: sheet.right_edge(t, y),
        width: sheet.growth().map(|_| {
            let (n, m) = sheet.grid();
            (1..=n).map(|j| sheet.yb(y, j, m)).sum::<f64>() / n as f64
        }),
        pressure: [f64::NEG_INFINITY, f64::INFINITY, 0.0],
        stretch_x: [f64::NEG_INFINITY, f64::INFINITY],
        stretch_y: [f64::NEG_INFINITY, f64::INFINITY],
        ..Default::default()
    };
    let (mut l2s, mut l3s) = (0.0, 0.0);
    for c in cells {
        let [a1, a2] = c.elastic_stretch();
        o.pressure[0] = o.pressure[0].max(c.pressure);
        o.pressure[1] = o.pressure[1].min(c.pressure);
        o.pressure[2] += c.pressure / nc;
        o.stretch_x[0] = o.stretch_x[0].max(a1);
        o.stretch_x[1] = o.stretch_x[1].min(a1);
        o.stretch_y[0] = o.stretch_y[0].max(a2);
        o.stretch_y[1] = o.stretch_y[1].min(a2);
        o.mean_height += c.height / nc;
        l2s += a2;
        l3s += c.stretch[2];
    }
    o.stretch_z_over_y = l3s / l2s;
    o.mismatch = boundary_mismatch(sheet, y);
    o
}

/// One sheet state's series values: `length` and the pressure and `α₁` extremes, extra keys
/// [`MEAN_PRESSURE`], [`MEAN_HEIGHT`], [`MEAN_STRETCH_Z_OVER_Y`], [`BOUNDARY_MISMATCH_MEAN`],
/// [`BOUNDARY_MISMATCH_MAX`], [`MAX_STRETCH_Y`], [`MIN_STRETCH_Y`] and, for a growing sheet,
/// [`MEAN_WIDTH`].
///
/// ```
/// use celltissue::observe::Series;
/// use celltissue::sheet::observe::{sheet_series_row, SheetObservables, MEAN_HEIGHT};
/// let mut s = Series::default();
/// s.push_row(1.0, &sheet_series_row(&SheetObservables { t: 1.0, mean_height: 0.9, ..Default::default() }));
/// assert_eq!((s.t[0], s.extra[MEAN_HEIGHT][0]), (1.0, 0.9));
/// assert!(!s.extra.contains_key("mean_width")); // only a growing sheet has a width series
/// ```
pub fn sheet_series_row(o: &SheetObservables) -> SeriesRow {
    let mut extra = vec![
        (MEAN_PRESSURE, o.pressure[2]),
        (MEAN_HEIGHT, o.mean_height),
        (MEAN_STRETCH_Z_OVER_Y, o.stretch_z_over_y),
        (BOUNDARY_MISMATCH_MEAN, o.mismatch[0]),
        (BOUNDARY_MISMATCH_MAX, o.mismatch[1]),
        (MAX_STRETCH_Y, o.stretch_y[0]),
        (MIN_STRETCH_Y, o.stretch_y[1]),
    ];
    if let Some(w) = o.width {
        extra.push((MEAN_WIDTH, w));
    }
    SeriesRow {
        length: o.length,
        max_pressure: o.pressure[0],
        min_pressure: o.pressure[1],
        max_stretch: o.stretch_x[0],
        min_stretch: o.stretch_x[1],
        extra: extra.into_iter().map(|(k, v)| (k.to_string(), v)).collect(),
    }
}

/// The per-cell columns every sheet profile has besides `X`, `x`, `stretch` and `pressure`
/// ([`sheet_profile`] writes them, [`sheet_cells`] reads them back).
const PROFILE_KEYS: [&str; 14] = [
    "Y",
    "y",
    "stretch_y",
    "stretch_z",
    "height",
    "sigma11",
    "sigma22",
    "kappa",
    "column",
    "row",
    "x_left",
    "x_right",
    "y_bottom",
    "y_top",
];

/// The optional per-cell columns of a sheet profile.
///
/// ```
/// use celltissue::sheet::observe::SheetColumns;
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// // an elastic sheet without growth: no viscous or growth stretches to write
/// assert_eq!(SheetColumns::of(&sheet), SheetColumns { viscous: false, growth: false });
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SheetColumns {
    /// `viscous_x`, `viscous_y`: the Maxwell branch's viscous stretches.
    pub viscous: bool,
    /// `growth_x`, `growth_y`: the growth stretches, and `lambda`, `lambda_y`: the total
    /// stretches (`stretch`, `stretch_y` are then the elastic ones).
    pub growth: bool,
}

impl SheetColumns {
    /// The columns a sheet has.
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// use celltissue::sheet::observe::SheetColumns;
    /// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
    /// let p = SheetParams { branch: Some(MaxwellBranch::maxwell(1.0, 1.0)?), ..Default::default() };
    /// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let c = SheetColumns::of(&sheet);
    /// assert!(c.viscous && !c.growth);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of<E: StrainEnergy>(sheet: &UniaxialSheet<E>) -> Self {
        Self {
            viscous: sheet.branch().is_some(),
            growth: sheet.growth().is_some(),
        }
    }
}

/// A per-cell sheet [`Profile`]: `X`/`x` are reference/current centre x, `stretch` is the
/// elastic stretch `α₁ = λ₁/g₁` (`λ₁` without growth, [`SheetCell::elastic_stretch`]), as a
/// growing line's is; `extra` holds `Y`, `y`, `stretch_y` (α₂), `stretch_z` (λ₃), `height`,
/// `sigma11`, `sigma22`, `kappa`, `column` (j), `row` (k), the cell's extent `x_left`,
/// `x_right`, `y_bottom`, `y_top` (what [`sheet_cells`] rebuilds the cells from), and the
/// optional [`SheetColumns`]: the viscous stretches `viscous_x` (a₁), `viscous_y` (a₂), and the
/// growth stretches `growth_x` (g₁), `growth_y` (g₂) with the total stretches `lambda` (λ₁),
/// `lambda_y` (λ₂). Cells are listed column by column.
///
/// ```
/// use celltissue::sheet::observe::{sheet_profile, SheetColumns};
/// use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
/// let sheet = UniaxialSheet::discrete(celltissue::NeoHookean::new(1.0)?, &SheetParams::default())?;
/// let y = sheet.initial_state();
/// let p = sheet_profile(0.0, &sheet.cells(0.0, &y, &vec![0.0; y.len()]), SheetColumns::of(&sheet));
/// assert_eq!(p.stretch.len(), 100);
/// assert_eq!(p.extra["x_right"][0], 1.0);
/// assert!(!p.extra.contains_key("growth_x"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sheet_profile(t: f64, cells: &[SheetCell], columns: SheetColumns) -> Profile {
    let mut p = Profile {
        t,
        ..Default::default()
    };
    let keys = PROFILE_KEYS;
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(cells.len()); keys.len()];
    for c in cells {
        let [a1, a2] = c.elastic_stretch();
        p.x_ref.push(c.reference[0]);
        p.x.push(0.5 * (c.x[0] + c.x[1]));
        p.stretch.push(a1);
        p.pressure.push(c.pressure);
        let v = [
            c.reference[1],
            0.5 * (c.y[0] + c.y[1]),
            a2,
            c.stretch[2],
            c.height,
            c.s11,
            c.s22,
            c.kappa,
            c.j as f64,
            c.k as f64,
            c.x[0],
            c.x[1],
            c.y[0],
            c.y[1],
        ];
        for (col, x) in cols.iter_mut().zip(v) {
            col.push(x);
        }
    }
    for (k, col) in keys.iter().zip(cols) {
        p.extra.insert(k.to_string(), col);
    }
    if columns.viscous {
        for (i, key) in ["viscous_x", "viscous_y"].into_iter().enumerate() {
            let col = cells.iter().map(|c| c.viscous[i]).collect();
            p.extra.insert(key.to_string(), col);
        }
    }
    if columns.growth {
        for (i, key) in ["growth_x", "growth_y"].into_iter().enumerate() {
            let col = cells.iter().map(|c| c.growth[i]).collect();
            p.extra.insert(key.to_string(), col);
        }
        for (i, key) in ["lambda", "lambda_y"].into_iter().enumerate() {
            let col = cells.iter().map(|c| c.stretch[i]).collect();
            p.extra.insert(key.to_string(), col);
        }
    }
    p
}

/// The cells of a sheet profile ([`sheet_profile`]), for writers that draw them (VTK, PNG):
/// extents, stretches, height, pressure, stresses, `κ` and indices. Empty if the profile is
/// not a sheet's.
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::sheet::observe::sheet_cells;
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, SheetConfig};
/// use celltissue::SolveSettings;
/// let cfg = SheetConfig { cells_x: 3, cells_y: 2, ..Default::default() };
/// let out = OutputTimes { series: vec![1.0], profiles: vec![1.0] };
/// let rec = run_sheet(&cfg, &cfg.law, ModelKind::Discrete, None, &SolveSettings::default(), &out)?;
/// let cells = sheet_cells(&rec.profiles[0]);
/// assert_eq!(cells.len(), 6);
/// assert!(cells.iter().all(|c| c.x[1] > c.x[0] && c.y[1] > c.y[0]));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sheet_cells(p: &Profile) -> Vec<SheetCell> {
    let col = |k: &str| p.extra.get(k).map(Vec::as_slice).unwrap_or(&[]);
    let keys = PROFILE_KEYS;
    let n = keys
        .iter()
        .map(|k| col(k).len())
        .chain([p.x_ref.len(), p.stretch.len(), p.pressure.len()])
        .min()
        .unwrap_or(0);
    (0..n)
        .map(|i| {
            let at = |k: &str| col(k)[i];
            let growth =
                [col("growth_x"), col("growth_y")].map(|c| c.get(i).copied().unwrap_or(1.0));
            SheetCell {
                j: at("column") as usize,
                k: at("row") as usize,
                x: [at("x_left"), at("x_right")],
                y: [at("y_bottom"), at("y_top")],
                reference: [p.x_ref[i], at("Y")],
                // the total stretches (a growing sheet's `stretch` columns are elastic)
                stretch: [
                    col("lambda").get(i).copied().unwrap_or(p.stretch[i]),
                    col("lambda_y").get(i).copied().unwrap_or(at("stretch_y")),
                    at("stretch_z"),
                ],
                height: at("height"),
                pressure: p.pressure[i],
                s11: at("sigma11"),
                s22: at("sigma22"),
                kappa: at("kappa"),
                viscous: [col("viscous_x"), col("viscous_y")]
                    .map(|c| c.get(i).copied().unwrap_or(1.0)),
                growth,
            }
        })
        .collect()
}

/// Scalar observables of one shear snapshot.
///
/// ```
/// use celltissue::sheet::observe::shear_observables;
/// use celltissue::sheet::shear::{ShearColumn, ShearParams};
/// let p = ShearParams { cells: 4, ..Default::default() };
/// let col = ShearColumn::discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
/// // the steady state of F_A = β₀μ: every cell sheared by tan θ = 1, the top edge at x = 4
/// let o = shear_observables(0.0, &col.fields(&[1.0, 2.0, 3.0, 4.0], &[0.0; 4]));
/// assert_eq!((o.top, o.spread, o.tan_theta), (4.0, 0.0, [1.0, 1.0]));
/// assert!((o.mean_theta - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
/// assert!((o.pressure[0] - 1.0).abs() < 1e-12); // neo-Hookean: p = μ
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShearObservables {
    /// Time.
    pub t: f64,
    /// Top displacement `x_{e,M}`.
    pub top: f64,
    /// `max tan θ − min tan θ`.
    pub spread: f64,
    /// Mean `θ` (radians).
    pub mean_theta: f64,
    /// Max / min `tan θ`.
    pub tan_theta: [f64; 2],
    /// Max / min pressure.
    pub pressure: [f64; 2],
}

/// Shear observables from the per-cell fields.
///
/// ```
/// use celltissue::sheet::observe::shear_observables;
/// use celltissue::sheet::shear::ShearFields;
/// let f = ShearFields { tan_theta: vec![0.5, 1.0], theta: vec![0.4, 0.8], x_edge: vec![0.0, 0.5, 1.5],
///                       pressure: vec![1.0, 1.0], ..Default::default() };
/// let o = shear_observables(2.0, &f);
/// assert_eq!((o.top, o.spread, o.tan_theta), (1.5, 0.5, [1.0, 0.5]));
/// ```
pub fn shear_observables(t: f64, f: &ShearFields) -> ShearObservables {
    let mx = f
        .tan_theta
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max);
    let mn = f.tan_theta.iter().cloned().fold(f64::INFINITY, f64::min);
    ShearObservables {
        t,
        top: *f.x_edge.last().unwrap_or(&0.0),
        spread: mx - mn,
        mean_theta: f.theta.iter().sum::<f64>() / f.theta.len().max(1) as f64,
        tan_theta: [mx, mn],
        pressure: [
            f.pressure.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            f.pressure.iter().cloned().fold(f64::INFINITY, f64::min),
        ],
    }
}

/// One shear-column state's series values: `length` is the top displacement,
/// `max/min_stretch` are `max/min tan θ`; extra keys [`TOP_DISPLACEMENT`], [`SHEAR_SPREAD`],
/// [`MEAN_SHEAR_ANGLE`].
///
/// ```
/// use celltissue::sheet::observe::{shear_series_row, ShearObservables, SHEAR_SPREAD};
/// let o = ShearObservables { top: 2.0, spread: 0.1, tan_theta: [0.3, 0.2], ..Default::default() };
/// let row = shear_series_row(&o);
/// assert_eq!((row.length, row.max_stretch, row.min_stretch), (2.0, 0.3, 0.2));
/// assert!(row.extra.contains(&(SHEAR_SPREAD.to_string(), 0.1)));
/// ```
pub fn shear_series_row(o: &ShearObservables) -> SeriesRow {
    SeriesRow {
        length: o.top,
        max_pressure: o.pressure[0],
        min_pressure: o.pressure[1],
        max_stretch: o.tan_theta[0],
        min_stretch: o.tan_theta[1],
        extra: [
            (TOP_DISPLACEMENT, o.top),
            (SHEAR_SPREAD, o.spread),
            (MEAN_SHEAR_ANGLE, o.mean_theta),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect(),
    }
}

/// A per-cell shear [`Profile`] against height: `X` is the reference centre height `y`, `x` the
/// centre position `x_c`, `stretch` is `tan θ`; extra: `theta`, `tau` (σ₁₂), `x_edge` (top edge
/// of each cell).
///
/// ```
/// use celltissue::sheet::observe::shear_profile;
/// use celltissue::sheet::shear::ShearFields;
/// let f = ShearFields { y_ref: vec![0.5, 1.5], x_centre: vec![0.1, 0.3], tan_theta: vec![0.2, 0.2],
///                       theta: vec![0.197, 0.197], tau: vec![0.2, 0.2], pressure: vec![1.0, 1.0],
///                       x_edge: vec![0.0, 0.2, 0.4] };
/// let p = shear_profile(3.0, &f);
/// assert_eq!((p.x_ref.clone(), p.stretch.clone()), (vec![0.5, 1.5], vec![0.2, 0.2]));
/// assert_eq!(p.extra["x_edge"], [0.2, 0.4]); // each cell's top edge
/// ```
pub fn shear_profile(t: f64, f: &ShearFields) -> Profile {
    let mut p = Profile {
        t,
        x_ref: f.y_ref.clone(),
        x: f.x_centre.clone(),
        stretch: f.tan_theta.clone(),
        pressure: f.pressure.clone(),
        ..Default::default()
    };
    p.extra.insert("theta".into(), f.theta.clone());
    p.extra.insert("tau".into(), f.tau.clone());
    p.extra.insert("x_edge".into(), f.x_edge[1..].to_vec());
    p
}
