//! The line of cells (thesis Ch. 2 and the growth part of Ch. 3; docs/model.md §2–§3), discrete and
//! continuum, from a [`crate::StrainEnergy`] to a [`crate::observe::RunRecord`]:
//!
//! * [`array`](mod@array) — [`Line`], the residual (docs/model.md §2.9) as a [`crate::CellArray`];
//! * [`build`] — discrete and conservative-continuum builders from one [`LineParams`];
//! * [`thesis_scheme`] — the thesis's non-conservative finite-difference scheme (reproduction
//!   mode, Table 2.1);
//! * [`analytic`] — analytic reference solutions (uniform K = 0, linear theory, quasi-static)
//!   used as plot overlays;
//! * [`static_solve`] — static equilibrium by a bracketing solve for the uniform stress, and a
//!   Newton solve of the static problem;
//! * [`observe`] — per-cell snapshots and the observables of docs/model.md §6;
//! * [`config`] — the serde scenario section [`LineConfig`] with validation;
//! * [`run`] — [`run_line`]: config → problem → integrator → `RunRecord`.

pub mod analytic;
pub mod array;
pub mod build;
pub mod config;
pub(crate) mod homogenise;
pub mod observe;
pub mod run;
pub mod static_solve;
pub mod thesis_scheme;

pub use array::{CellEval, Cells, FieldsMut, Layout, Line};
pub use build::{continuum, discrete, LineParams};
pub use config::LineConfig;
pub use run::{run_line, OutputTimes, SolveSettings};

/// Errors building or configuring a line. Messages name the key and its valid range.
///
/// ```
/// use celltissue::line::LineConfig;
/// let e = LineConfig { cells: 0, ..Default::default() }.validate().unwrap_err();
/// assert_eq!(e.key(), Some("cells"));
/// assert!(e.to_string().starts_with("invalid `cells` = 0"));
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LineError {
    /// A parameter is out of range.
    #[error("invalid `{key}` = {value}: must be {range}")]
    Invalid {
        /// The scenario key.
        key: String,
        /// The offending value.
        value: String,
        /// The valid range.
        range: String,
    },
    /// A field description is invalid (the error names the innermost key).
    #[error("invalid field: {0}")]
    Field(#[from] crate::cell::FieldError),
    /// The cell-centre drag form is singular on a ring (docs/model.md §2.5).
    #[error("invalid `drag_form` = \"centre\" with `right_end` = \"periodic\": the cell-centre form is singular on a ring (zig-zag null mode); use drag_form = \"boundary\"")]
    CentreFormPeriodic,
    /// A combination with no well-posed dynamics.
    #[error("invalid combination: {0}")]
    Combination(String),
    /// A configuration key that conflicts with others (`key` is the one to change).
    #[error("invalid combination: {message}")]
    Conflict {
        /// The scenario key the message starts from.
        key: &'static str,
        /// What conflicts and how to fix it.
        message: String,
    },
}

impl LineError {
    /// The innermost scenario key the error is about (`mu.width`, `drag_form`, `K`), or
    /// `None` when no single key is at fault.
    ///
    /// ```
    /// use celltissue::line::LineError;
    /// assert_eq!(LineError::invalid("cells", 0, ">= 1").key(), Some("cells"));
    /// assert_eq!(LineError::Combination("no static state".into()).key(), None);
    /// ```
    pub fn key(&self) -> Option<&str> {
        match self {
            LineError::Invalid { key, .. } => Some(key),
            LineError::Field(e) => Some(&e.key),
            LineError::CentreFormPeriodic => Some("drag_form"),
            LineError::Conflict { key, .. } => Some(key),
            LineError::Combination(_) => None,
        }
    }

    /// An [`LineError::Invalid`] from displayable parts.
    ///
    /// ```
    /// let e = celltissue::line::LineError::invalid("cells", 0, "an integer >= 1");
    /// assert_eq!(e.to_string(), "invalid `cells` = 0: must be an integer >= 1");
    /// ```
    pub fn invalid(key: &str, value: impl std::fmt::Display, range: &str) -> Self {
        LineError::Invalid {
            key: key.to_string(),
            value: value.to_string(),
            range: range.to_string(),
        }
    }
}
