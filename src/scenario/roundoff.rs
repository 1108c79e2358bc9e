//! The solver tolerances against what a line's positions resolve, checked before a run.
//!
//! The error test measures each cell's stretch as a difference of two stored boundary
//! positions (docs/model.md §8.1), and a difference of two doubles of size `|X|` is known only
//! to about `ε·|X|`. A line whose far cells are short against its length can ask, at a small
//! `rtol + atol`, for stretches finer than that: the test then measures rounding noise, the
//! steps shrink without end, and the solver stops at the first step
//! ([`integrators::ErrorKind::TooMuchAccuracy`], past
//! [`integrators::solver::ROUNDOFF_LIMIT`]). [`check_line`] rejects such a scenario at
//! `validate` with the tightest tolerance that would run. It sees the initial state only: a
//! line that compresses a cell far, or divides into many more cells, can still reach the limit
//! later, and the solver then says when and where.
//!
//! ```
//! use celltissue::scenario::roundoff::check_line;
//! // 4 000 unit cells: rtol 1e-6 resolves every stretch with room to spare
//! assert!(check_line([1.0; 4000], 1e-6, 1e-8).is_ok());
//! // rtol 1e-15 asks for stretches to 1e-15, below the 1.8e-12 that positions near 4 000 give
//! let e = check_line([1.0; 4000], 1e-15, 1e-17).unwrap_err();
//! assert_eq!(e.key_name(), Some("solver.rtol"));
//! ```

use integrators::solver::ROUNDOFF_LIMIT;

use super::error::ScenarioError;

/// Where a line at rest comes closest to round-off: the ratio, the cell (from 1) and the
/// reference position of the boundary that closes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// `ε·(X_i + X_{i−1}) / (L_i·(rtol + atol))`: round-off of the cell's length over its
    /// stretch tolerance.
    pub ratio: f64,
    /// The cell, counted from 1.
    pub cell: usize,
    /// `X_i`, the reference position of the boundary that closes the cell.
    pub x: f64,
}

/// The largest round-off ratio of a line at rest whose cells have reference lengths `lengths`
/// (in order, from a wall at 0): for the boundary at `X_i` that closes cell `i`,
/// `ε·(X_i + X_{i−1}) / (L_i·(rtol + atol))` (its stretch row in the error test, positions
/// carrying `atol·L_i`), over the boundaries between two cells (the end boundaries are not
/// unknowns of every end condition). A uniform line is passed as `repeat_n(L, N)`: no
/// N-vector.
///
/// ```
/// use celltissue::scenario::roundoff::line_ratio;
/// // cells of length 1, 1, 1e-6, 1: the short third cell, between positions 2 and 2 + 1e-6
/// let c = line_ratio([1.0, 1.0, 1e-6, 1.0], 1e-6, 0.0);
/// assert_eq!(c.cell, 3);
/// assert!((c.ratio - f64::EPSILON * 4.000001 / 1e-12).abs() < 1e-9);
/// ```
pub fn line_ratio(lengths: impl IntoIterator<Item = f64>, rtol: f64, atol: f64) -> Closest {
    let mut worst = Closest {
        ratio: 0.0,
        cell: 0,
        x: 0.0,
    };
    // the candidate of the latest cell, kept only once a cell follows it
    let mut pending: Option<Closest> = None;
    let mut left = 0.0;
    for (i, l) in lengths.into_iter().enumerate() {
        if let Some(c) = pending.take() {
            if c.ratio > worst.ratio {
                worst = c;
            }
        }
        let right = left + l;
        pending = Some(Closest {
            ratio: f64::EPSILON * (left + right) / (l * (rtol + atol)),
            cell: i + 1,
            x: right,
        });
        left = right;
    }
    worst
}

/// Rejects a line (cells of reference lengths `lengths`, `cells` of them) whose stretch
/// tolerance `rtol + atol` at rest is within [`ROUNDOFF_LIMIT`] of the round-off of its
/// positions, naming `solver.rtol`, the cell and the tightest tolerance that would run.
///
/// ```
/// use celltissue::scenario::roundoff::check_line;
/// // 10⁶ unit cells: rtol 1e-8 runs, rtol 1e-10 would test the far cells' rounding noise
/// let cells = || std::iter::repeat_n(1.0, 1_000_000);
/// assert!(check_line(cells(), 1e-8, 1e-10).is_ok());
/// let e = check_line(cells(), 1e-10, 1e-12).unwrap_err();
/// assert!(e.to_string().contains("rtol + atol ≥ 1.8e-9"), "{e}");
/// ```
pub fn check_line(
    lengths: impl IntoIterator<Item = f64>,
    rtol: f64,
    atol: f64,
) -> Result<(), ScenarioError> {
    check_line_for(lengths, rtol, atol, Asker::Run)
}

/// Who asks for a tolerance: the run itself, or the accuracy check's run at a tenth of it
/// (`solver.accuracy_check`, [`super::accuracy_check::tightened`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Asker {
    /// The run, at `solver.rtol` and `solver.atol`.
    Run,
    /// The accuracy check's tighter run.
    Check,
}

/// [`check_line`] for `asker`: the check's error names `solver.accuracy_check` and the
/// run's tolerances that would let its run go.
fn check_line_for(
    lengths: impl IntoIterator<Item = f64>,
    rtol: f64,
    atol: f64,
    asker: Asker,
) -> Result<(), ScenarioError> {
    let c = line_ratio(lengths, rtol, atol);
    if c.ratio <= ROUNDOFF_LIMIT {
        return Ok(());
    }
    let tol = rtol + atol;
    let needed = tol * c.ratio / ROUNDOFF_LIMIT;
    let (key, lead, would) = match asker {
        Asker::Run => (
            "solver.rtol",
            format!("= {rtol:e} (with atol = {atol:e}) asks"),
            "would run".to_string(),
        ),
        Asker::Check => (
            "solver.accuracy_check",
            format!("= true runs each run again at rtol = {rtol:e}, atol = {atol:e}, which ask"),
            format!(
                "would run, i.e. the run's rtol + atol ≥ {:.1e} (or leave the check out)",
                needed * super::accuracy_check::FACTOR
            ),
        ),
    };
    Err(ScenarioError::key(
        key,
        format!(
            "{lead} for stretches finer than the positions resolve: cell {} ends at X = {:.6e}, \
             where a difference of two positions is known only to {:.1e} of the cell's length \
             against the stretch tolerance rtol + atol = {tol:.1e}; rtol + atol ≥ {needed:.1e} \
             {would}",
            c.cell,
            c.x,
            c.ratio * tol,
        ),
    ))
}

/// [`check_line`] for every line model of a `[model]` section (a line, or a growing line that
/// divides): the discrete cells, and the continuum's `nodes` equal segments; for a sheet, its
/// longer direction (cells, or the continuum's grid). The shear column (whose unknowns are
/// displacements, zero at rest) and registered modes are left to the solver's own check.
///
/// ```
/// use celltissue::scenario::model::parse_model;
/// use celltissue::scenario::roundoff::check_section;
/// use celltissue::scenario::schema::SolverSection;
/// let model: toml::Table = toml::from_str("kind = \"line\"\ncells = 4000\nnodes = 40")?;
/// let section = parse_model(&model)?;
/// let tight: SolverSection = toml::from_str("rtol = 1e-13\natol = 1e-15")?;
/// // the 4 000 cells cannot be resolved to 1e-13 (the 40 continuum segments could)
/// let e = check_section(&section, &tight.validate()?).unwrap_err();
/// assert!(e.to_string().contains("cell 3999"), "{e}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check_section(
    section: &super::model::ModelSection,
    solver: &crate::settings::SolveSettings,
) -> Result<(), ScenarioError> {
    check_section_for(section, solver, Asker::Run)
}

/// [`check_section`] for `asker` at `solver`'s tolerances: with [`Asker::Check`], `solver`
/// is the check's run and the error names `solver.accuracy_check`.
///
/// ```
/// use celltissue::scenario::accuracy_check::tightened;
/// use celltissue::scenario::model::parse_model;
/// use celltissue::scenario::roundoff::{check_section_for, Asker};
/// use celltissue::scenario::schema::SolverSection;
/// let model: toml::Table = toml::from_str("kind = \"line\"\ncells = 4000")?;
/// let section = parse_model(&model)?;
/// let run: SolverSection = toml::from_str("rtol = 1e-11\natol = 1e-13")?;
/// let run = run.validate()?;
/// assert!(check_section_for(&section, &run, Asker::Run).is_ok());
/// // the check's run at rtol 1e-12 would test the far cells' rounding
/// let e = check_section_for(&section, &tightened(&run), Asker::Check).unwrap_err();
/// assert_eq!(e.key_name(), Some("solver.accuracy_check"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check_section_for(
    section: &super::model::ModelSection,
    solver: &crate::settings::SolveSettings,
    asker: Asker,
) -> Result<(), ScenarioError> {
    use super::model::ModelConfig;
    use crate::observe::ModelKind;
    let (rtol, atol) = (solver.rtol, solver.atol);
    // `check_line` for this asker
    let check = |lengths: &mut dyn Iterator<Item = f64>, rtol, atol| {
        check_line_for(lengths, rtol, atol, asker)
    };
    let line = match &section.config {
        ModelConfig::Line(c) => &**c,
        ModelConfig::Proliferating(p) => &p.line,
        ModelConfig::Sheet(c, _) => {
            // faces at multiples of the cell size in each direction, tested through their
            // cells' stretches as a line's boundaries are: the longer direction decides
            for model in &section.models {
                let (n, m) = match model {
                    ModelKind::Discrete => (c.cells_x, c.cells_y),
                    ModelKind::Continuum => section
                        .grid
                        .unwrap_or((2 * c.cells_x.min(1 << 40), 2 * c.cells_y.min(1 << 40))),
                };
                check(&mut std::iter::repeat_n(1.0, n.max(m)), rtol, atol)?;
            }
            return Ok(());
        }
        _ => return Ok(()),
    };
    for model in &section.models {
        match (model, &line.ref_lengths) {
            (ModelKind::Discrete, Some(v)) => check(&mut v.iter().copied(), rtol, atol)?,
            (ModelKind::Discrete, None) => check(
                &mut std::iter::repeat_n(line.cell_length, line.cells),
                rtol,
                atol,
            )?,
            (ModelKind::Continuum, _) => {
                let n = section.nodes.unwrap_or(line.cells).max(1);
                check(
                    &mut std::iter::repeat_n(line.l0() / n as f64, n),
                    rtol,
                    atol,
                )?
            }
        }
    }
    Ok(())
}
