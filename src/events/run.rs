//! [`run_proliferation`]: one run of a growing line with division — the discrete
//! [`Dividing`] line, or the proliferating continuum ([`DensityContinuum`], or [`CellGrid`]
//! with `division.cell_grid`) — from a [`ProliferationConfig`] (a [`LineConfig`] plus a
//! `division` table) to a [`RunRecord`] with the `"cells"` series (`N` at each output time)
//! and the `"divisions"` list.

use super::dividing::Dividing;
use super::division::DivisionConfig;
use crate::energy::StrainEnergy;
use crate::line::config::RightEndKind;
use crate::line::run::run_model;
use crate::line::{LineConfig, OutputTimes, SolveSettings};
use crate::observe::{ModelKind, RunRecord, RunStats, Series};
use crate::proliferation::{CellGrid, DensityContinuum};
use serde::Serialize;

/// An invalid proliferating line; [`ProliferationError::key`] is the innermost scenario key
/// (under `model`).
///
/// ```
/// use celltissue::events::{ProliferationConfig, ProliferationError};
/// let t: toml::Table = toml::from_str("cells = 10\nright_end = \"free\"").unwrap();
/// let e = ProliferationConfig::from_table(&t).and_then(|c| c.validate().map(|_| c)).unwrap_err();
/// assert!(matches!(e, ProliferationError::NoGrowth));
/// assert!(e.to_string().contains("division needs a growth law"));
/// ```
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProliferationError {
    /// The line's keys do not parse.
    #[error("invalid line configuration: {0}")]
    LineTable(toml::de::Error),
    /// The line's configuration is invalid.
    #[error(transparent)]
    Line(#[from] crate::line::LineError),
    /// The division rule is invalid.
    #[error(transparent)]
    Division(#[from] super::division::DivisionError),
    /// Division without growth.
    #[error("invalid `growth`: division needs a growth law (add growth = {{ sigma0 = 0.1 }})")]
    NoGrowth,
    /// The proliferating continuum on a ring.
    #[error("invalid `right_end` = \"periodic\": the proliferating continuum has no ring; run models = [\"discrete\"]")]
    Ring,
}

impl ProliferationError {
    /// The innermost key the error is about, relative to the model table (`division.ratio`,
    /// `growth`, `mu.width`); `None` when no single key is at fault.
    ///
    /// ```
    /// use celltissue::events::ProliferationConfig;
    /// let t: toml::Table = toml::from_str("cells = 10\ngrowth = { sigma0 = 0.1 }\n\
    ///     division = { rule = \"age\", period = -1 }").unwrap();
    /// let e = ProliferationConfig::from_table(&t).unwrap_err();
    /// assert_eq!(e.key().as_deref(), Some("division.period"));
    /// ```
    pub fn key(&self) -> Option<String> {
        match self {
            ProliferationError::LineTable(_) => None,
            ProliferationError::Line(e) => e.key().map(str::to_string),
            ProliferationError::Division(e) if e.key().is_empty() => Some("division".into()),
            ProliferationError::Division(e) => Some(format!("division.{}", e.key())),
            ProliferationError::NoGrowth => Some("growth".into()),
            ProliferationError::Ring => Some("right_end".into()),
        }
    }
}

/// A proliferating line: the line's configuration (must grow, right end not periodic) and the
/// division rule.
///
/// ```
/// use celltissue::events::ProliferationConfig;
/// let t: toml::Table = toml::from_str(r#"
///     cells = 100
///     right_end = "free"
///     K = 1e-5
///     growth = { sigma0 = 0.1 }
///     division = { rule = "area" }
/// "#).unwrap();
/// let cfg = ProliferationConfig::from_table(&t).unwrap();
/// assert!(cfg.validate().is_ok());
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProliferationConfig {
    /// The line.
    #[serde(flatten)]
    pub line: LineConfig,
    /// The division rule.
    pub division: DivisionConfig,
}

impl ProliferationConfig {
    /// Parses a `[model]`-style table: the `division` key is the rule (default: area
    /// doubling), every other key belongs to [`LineConfig`]. Errors name the key.
    ///
    /// ```
    /// use celltissue::events::run::ProliferationConfig;
    /// let t: toml::Table = toml::from_str("cells = 10\nK = 1e-3\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }")?;
    /// let cfg = ProliferationConfig::from_table(&t)?;
    /// assert_eq!((cfg.line.cells, cfg.division.area_ratio()), (10, Some(2.0))); // the default rule
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_table(table: &toml::Table) -> Result<Self, ProliferationError> {
        let mut rest = table.clone();
        let division = match rest.remove("division") {
            None => DivisionConfig::default(),
            Some(v) => DivisionConfig::from_value(v)?,
        };
        let line: LineConfig = toml::Value::Table(rest)
            .try_into()
            .map_err(ProliferationError::LineTable)?;
        Ok(Self { line, division })
    }

    /// Validates the line and the rule; division needs growth.
    ///
    /// ```
    /// use celltissue::events::run::ProliferationConfig;
    /// let t: toml::Table = toml::from_str("cells = 10\nright_end = \"free\"")?;
    /// // division needs growth
    /// assert!(ProliferationConfig::from_table(&t)?.validate().is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn validate(&self) -> Result<(), ProliferationError> {
        self.line.validate()?;
        self.division.validate()?;
        if self.line.growth.is_none() {
            return Err(ProliferationError::NoGrowth);
        }
        Ok(())
    }

    /// What the proliferating continuum needs besides [`Self::validate`]: a line, not a ring.
    /// Cells with a Maxwell branch are supported by both continua: each segment carries one
    /// viscous stretch, which a division copies to both halves, a density division leaves as
    /// it is and a merge averages by grown length ([`crate::line::Line::merge_cells`]).
    ///
    /// ```
    /// use celltissue::events::run::ProliferationConfig;
    /// let t: toml::Table = toml::from_str("cells = 10\nK = 1.0\nright_end = \"periodic\"\ngrowth = { sigma0 = 0.1 }")?;
    /// // the proliferating continuum is a line, not a ring
    /// assert!(ProliferationConfig::from_table(&t)?.validate_continuum().is_err());
    /// let sls = "cells = 10\nK = 1e-5\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }\n\
    ///     viscosity = { model = \"standard_linear_solid\", mu_m = 1, eta_m = 2 }\n";
    /// // cells with a branch divide in both continua, and the grid merges them
    /// let merging = format!("{sls}division = {{ rule = \"area\", cell_grid = {{ merge_below = 1e-3 }} }}");
    /// assert!(ProliferationConfig::from_table(&toml::from_str(&merging)?)?.validate_continuum().is_ok());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn validate_continuum(&self) -> Result<(), ProliferationError> {
        if self.line.right_end == RightEndKind::Periodic {
            return Err(ProliferationError::Ring);
        }
        Ok(())
    }
}

/// Runs one proliferating line (`model`: discrete with division, or the proliferating
/// continuum on `nodes` segments — the cell-number grid with any rule, the density continuum
/// with the area rule) and records series, profiles and
/// divisions. Invalid configuration: a record with `error` naming the key.
///
/// ```
/// use celltissue::events::{run_proliferation, ProliferationConfig};
/// use celltissue::line::{OutputTimes, SolveSettings};
/// use celltissue::observe::ModelKind;
/// let t: toml::Table = toml::from_str("cells = 10\nK = 1e-5\nright_end = \"free\"\n\
///     growth = { sigma0 = 0.1 }\ndivision = { rule = \"area\" }").unwrap();
/// let cfg = ProliferationConfig::from_table(&t)?;
/// let times = OutputTimes { series: vec![1.0, 3.0], profiles: vec![] };
/// let rec = run_proliferation(&cfg, ModelKind::Discrete, None, &SolveSettings::default(), &times);
/// assert!(rec.error.is_none());
/// assert!(rec.divisions.len() >= 10); // every cell doubles by t ≈ 2
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_proliferation(
    cfg: &ProliferationConfig,
    model: ModelKind,
    nodes: Option<usize>,
    solver: &SolveSettings,
    times: &OutputTimes,
) -> RunRecord {
    let mut parameters = serde_json::to_value(cfg).unwrap_or(serde_json::Value::Null);
    if let (serde_json::Value::Object(m), Some(n)) = (&mut parameters, nodes) {
        m.insert("nodes".into(), n.into());
    }
    let n0 = cfg.line.n_cells();
    let label = match model {
        ModelKind::Discrete => format!("discrete N0={n0} with division"),
        ModelKind::Continuum => format!("proliferating continuum n={}", nodes.unwrap_or(n0)),
    };
    let mut rec = RunRecord {
        label,
        model,
        parameters,
        series: Series::default(),
        profiles: Vec::new(),
        stats: RunStats::default(),
        divisions: Vec::new(),
        error: None,
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    };
    if let Err(e) = cfg.validate() {
        rec.error = Some(e.to_string());
        return rec;
    }
    if let Err(e) = times.check() {
        rec.error = Some(e.to_string());
        return rec;
    }
    with_law(
        cfg,
        cfg.line.law.clone(),
        model,
        nodes,
        solver,
        times,
        &mut rec,
    );
    note_cap(&mut rec, cfg.division.max_cells);
    rec
}

/// A dividing run that reached its `max_cells` cap divides no more: from then on its N(t) and
/// l(t) are the cap's, not the model's. Noted in the record (`summary.json`, Python's
/// `Run.notes`) and warned of.
fn note_cap(rec: &mut RunRecord, cap: Option<usize>) {
    let Some(cap) = cap else { return };
    let Some(d) = rec.divisions.iter().find(|d| d.cells_after >= cap) else {
        return;
    };
    let note = format!(
        "the division cap max_cells = {cap} was reached at t = {}: no cell divided after it, \
         so N(t) and l(t) from then on are the cap's, not the model's; raise \
         model.division.max_cells (up to 10⁸) to follow the growth",
        integrators::error::short_number(d.t)
    );
    log::warn!("{}: {note}", rec.label);
    rec.notes.push(note);
}

fn with_law<E: StrainEnergy + Clone>(
    cfg: &ProliferationConfig,
    energy: E,
    model: ModelKind,
    nodes: Option<usize>,
    solver: &SolveSettings,
    times: &OutputTimes,
    rec: &mut RunRecord,
) {
    let params = cfg.line.params(solver.atol);
    let n0 = cfg.line.n_cells();
    match model {
        ModelKind::Discrete => {
            let built = crate::line::build::discrete(energy, &params)
                .map_err(|e| e.to_string())
                .and_then(|line| {
                    Dividing::new(line, cfg.division.build(), cfg.division.seed())
                        .map_err(|e| e.to_string())
                });
            match built {
                Ok(mut d) => {
                    d.max_cells = cfg.division.max_cells;
                    d.batch_within = cfg.division.batch_within;
                    let prob = run_model(d, solver, times, rec);
                    rec.divisions = prob.array.log.records;
                }
                Err(e) => rec.error = Some(e),
            }
        }
        ModelKind::Continuum => {
            if let Err(e) = cfg.validate_continuum() {
                rec.error = Some(e.to_string());
                return;
            }
            let n = nodes.unwrap_or(n0);
            if let Some(grid) = &cfg.division.cell_grid {
                let built = crate::line::build::cell_groups(energy, &params, n)
                    .map_err(|e| e.to_string())
                    .and_then(|line| {
                        CellGrid::with_cell_lengths(line, &params.ref_lengths, cfg.division.build())
                            .map_err(|e| e.to_string())
                    });
                match built {
                    Ok(mut g) => {
                        g.coarsen = grid.coarsening();
                        if grid.merge_stress_within.is_some() && g.stress_tolerance().is_none() {
                            // the tolerance is a fraction of G(0)/G′(0)
                            let slope = g.dividing.line.growth().map_or(0.0, |l| l.rate(0.0).1);
                            rec.error = Some(format!(
                                "division.cell_grid.merge_stress_within needs a growth law \
                                 whose rate rises with stress at zero stress (G′(0) > 0); \
                                 this one has G′(0) = {slope}"
                            ));
                            return;
                        }
                        g.max_cells = cfg.division.max_cells;
                        let prob = run_model(g, solver, times, rec);
                        // N(t) comes from the snapshots' cell counts, not the segments
                        rec.divisions = prob.array.dividing.log.records;
                    }
                    Err(e) => rec.error = Some(e),
                }
                return;
            }
            let Some(ratio) = cfg.division.area_ratio() else {
                rec.error = Some(
                    "invalid `division.rule`: the density continuum supports only \"area\"; \
                     the cell-number grid (`division.cell_grid`) takes any rule"
                        .into(),
                );
                return;
            };
            let built = crate::line::build::continuum(energy, &params, n)
                .map_err(|e| e.to_string())
                .and_then(|line| {
                    let cells = crate::line::build::segment_cells(&params, n);
                    DensityContinuum::with_initial_cells(line, cells, ratio)
                        .map_err(|e| e.to_string())
                });
            match built {
                Ok(mut d) => {
                    d.max_cells = cfg.division.max_cells.map(|m| m as f64);
                    // N(t) = ∫ρ dX comes from the snapshots' cell counts
                    let prob = run_model(d, solver, times, rec);
                    rec.divisions = prob.array.log.records;
                }
                Err(e) => rec.error = Some(e),
            }
        }
    }
}
