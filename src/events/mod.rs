//! Cell division as integrator events (thesis §3.1.8, §3.3.2; docs/model.md §2.8, §5.5).
//!
//! * [`division`] — the [`DivisionRule`] trait (a rule sees a [`CellView`]: growth, age, and
//!   on request length, width, area, stress, pressure, position, neighbours) and rules:
//!   [`SurfaceToVolume`] (thesis Ch. 5), [`AreaDoubling`] (default:
//!   `A/A₀ = g g₂` reaches 2), [`AgeRule`] (fixed cycle time) and [`RandomThreshold`] (per-cell
//!   threshold drawn at birth from a seeded [`SplitMix64`]); [`DivisionConfig`] is the
//!   scenario's `division = { rule = … }` table;
//! * [`rules`] — the registry of rules by name (built-ins, and [`rules::register`] for a
//!   program's own);
//! * [`reindex`] — `Line::split_cell` / `Line::split_cells`: two daughters of reference
//!   length `L₀g/2` with `g = 1` and the parent's material parameters, a boundary at the
//!   midpoint; all `k` cells that fire at one time in one O(N + k) pass;
//! * [`dividing`] — [`Dividing`], the growing line with one event function per cell; the fired
//!   cells are split together and the driver resizes. By default
//!   ([`Dividing::carry_history`]) the event is a mapped resize
//!   ([`integrators::Problem::map_history`]: the interpolated `ẏ` carried onto the new layout —
//!   a new boundary at its parent's midpoint velocity, a daughter's `ġ` its parent's — with no
//!   consistent initialisation) and BDF goes on at order 1 with a step-doubled first step
//!   ([`integrators::Method::resume`]): one Jacobian per division. Otherwise the method
//!   restarts from a consistent `ẏ` ([`crate::array::CellArray::restart_derivative`] replaces
//!   it for an inviscid line by the pre-event velocities, whose resting new boundary and
//!   noise-amplified velocities (`∝ μ/(K L₀)`) made every restart reject steps);
//! * [`log`] — [`DivisionLog`]: time, parent, `x_d`, `x_d/l`, `N` after, the parent's age
//!   and identities; CSV; `N(t)`, median `x_d/l`;
//! * [`lineage`] — [`Lineage`]: each cell's identity and the initial cell it descends from,
//!   through every division of a discrete line;
//! * `plots` — the division scatter and log–log `l(t)`, `N(t)` figures (Fig. 3.3);
//! * [`run`] — [`run_proliferation`]: a scenario run (discrete with division, or the
//!   proliferating continuum of [`crate::proliferation`]) to a [`crate::observe::RunRecord`]
//!   with `"cells"` series and `"divisions"`.
//!
//! # Validation (docs/model.md §5.5; N₀ = 100, σ₀ = 0.1, free end, BDF rtol 1e-8)
//!
//! `tests/division_thesis.rs`: K = 1e-5, m = 0: first division 2.008588 (Ref 2.0086, the
//! free-end cell), all originals divided by 2.594794 (Ref 2.5948, last at the wall),
//! N(2.5, 3, 5, 6) = 166, 200, 248, 288 (Ref identical); m = 1: 2.012098 / 2.872323
//! (Ref 2.0121 / 2.8723); K = 1e-2: first 2.582356 (Ref 2.5824), 4 divisions by t = 6 (Ref 4),
//! median `x_d/l` = 0.979 (a proliferating rim). Every division conserves the boundaries and
//! `l` exactly, `Σ L₀g` to 3e-16, the daughters' `α`, `σ_el`, `p_el` to ≤ 1.2e-13.

pub mod dividing;
pub mod division;
pub mod lineage;
pub mod log;
pub mod merge;
#[cfg(feature = "plots")]
pub(crate) mod plots;
pub mod reindex;
pub mod rules;
pub mod run;

pub use dividing::{Dividing, InvariantReport};
pub use division::{
    AgeRule, AreaDoubling, CellGridConfig, CellView, DivisionConfig, DivisionError, DivisionRule,
    RandomThreshold, SplitMix64, SurfaceToVolume, DEFAULT_MAX_CELLS,
};
pub use lineage::Lineage;
pub use log::DivisionLog;
pub use reindex::{Ahead, Split};
pub use rules::RuleSpec;
pub use run::{run_proliferation, ProliferationConfig, ProliferationError};

/// Errors of the division machinery (become fatal solver errors inside an event handler).
///
/// ```
/// use celltissue::events::EventError;
/// let e = EventError::NoSuchCell { cell: 12, cells: 10 };
/// assert_eq!(e.to_string(), "no cell 12: the line has 10 cells (1-based)");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EventError {
    /// The cell index is out of range.
    #[error("no cell {cell}: the line has {cells} cells (1-based)")]
    NoSuchCell {
        /// Requested cell.
        cell: usize,
        /// Number of cells.
        cells: usize,
    },
    /// The state vector does not match the layout.
    #[error("state has length {got}, expected {expected}")]
    StateLength {
        /// Given length.
        got: usize,
        /// Expected length.
        expected: usize,
    },
    /// The configuration cannot divide.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The parent cell is degenerate.
    #[error("cell {cell} cannot divide: {reason}")]
    Degenerate {
        /// The cell.
        cell: usize,
        /// Why.
        reason: String,
    },
}
