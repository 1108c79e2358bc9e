//! # integrators — stiff time integration for residual-form DAEs with structured Jacobians
//!
//! This crate knows nothing about cells. It integrates index-1 differential–algebraic systems
//! written in implicit (residual) form
//!
//! ```text
//!     F(t, y, ẏ) = 0,        y(t0) = y0,
//! ```
//!
//! the form used by DASSL/IDA. Explicit ODEs `ẏ = f(t, y)` and mass-matrix systems
//! `M(t, y) ẏ = f(t, y)` are adapters onto it ([`adapters`]).
//!
//! How the pieces fit (problem, method, state and driver are separate things):
//!
//! * [`Problem`] — the user's system: residual, optional Jacobian or exact directional
//!   derivatives (e.g. by forward-mode AD), a declared Jacobian [`Pattern`] (dense, banded or
//!   sparse), per-component tolerances, algebraic flags and event functions. A problem may
//!   **resize** itself in an event (cell division adds unknowns).
//! * [`System`] — the shared machinery every method uses: counted residual calls, the iteration
//!   matrix `∂F/∂y + c·∂F/∂ẏ` assembled by pattern (user Jacobian, coloured directional
//!   derivatives, or coloured finite differences: bandwidth+1 calls for banded, one call per
//!   colour for sparse, never N calls), and its factorisation by pattern ([`linalg`]).
//! * [`Method`] — one time-stepping scheme (BDF, ESDIRK, Radau IIA, Dormand–Prince) behind one
//!   trait, chosen by [`MethodKind`] (also from a string: `"bdf"`, `"esdirk"`, `"radau"`,
//!   `"dopri"`).
//! * [`Solver`] — the driver: consistent initialisation, output at requested times via dense
//!   output, event location and actions (stop / modify / resize), a stop time, statistics, and
//!   typed errors that carry the partial solution.
//!
//! ```
//! use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
//! /// ẏ = −y in residual form.
//! struct Decay;
//! impl Problem for Decay {
//!     fn dim(&self) -> usize { 1 }
//!     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
//!         -> Result<(), ResidualError> { r[0] = yp[0] + y[0]; Ok(()) }
//! }
//! let opts = Options { rtol: 1e-8, atol: 1e-10, ..Options::default() };
//! let sol = Solver::new(MethodKind::Bdf, opts).solve(&mut Decay, 0.0, &[1.0], &[1.0, 2.0])?;
//! assert!((sol.y[1][0] - (-2.0f64).exp()).abs() < 1e-6);
//! # Ok::<(), integrators::SolveFailure>(())
//! ```
#![warn(missing_docs)]

pub mod adapters;
pub mod error;
pub mod error_map;
mod initial_step;
pub mod interrupt;
pub mod jacobian;
pub mod linalg;
pub mod method;
pub mod methods;
pub mod observer;
pub mod options;
pub mod pattern;
pub mod problem;
pub mod solver;
mod split_pool;
pub mod stats;
pub mod system;

pub use error::{ErrorKind, RecoverableCause, SolveFailure, SolverError};
pub use error_map::{ErrorMap, ErrorMapError, Row};
pub use method::{CustomMethod, Method, MethodChoice, MethodKind, StabilityLimit};
pub use observer::Observer;
pub use options::{
    BdfOptions, ErrorNorm, IterativeSettings, LinearSolverChoice, Options, OptionsError,
    Parallelism,
};
pub use pattern::{Pattern, SparsityPattern};
pub use problem::{EventAction, JacobianSink, Problem, ResidualError};
pub use solver::{EventRecord, Solution, Solver};
pub use stats::Stats;
pub use system::System;
