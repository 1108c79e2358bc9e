//! Scenario files: the TOML schema (`[solver]`, `[output]`, `[model]`, `[sweep]`, `[plots]`),
//! `--set dotted.key=value` overrides, sweep expansion and validation with errors that name the
//! key and its valid range. Every key is documented in `models/README.md`.
//!
//! A scenario reads top to bottom as what it runs:
//!
//! ```toml
//! name = "fig2_5"
//! description = "eta = 0, K sweep, exponential ramp"
//! figure = "2.5"
//! [solver]
//! method = "bdf"
//! [output]
//! series = { start = 1e-3, stop = 1000, count = 120, spacing = "log", zero = true }
//! profiles = [0, 1, 10, 1000]
//! [model]
//! kind = "line"
//! models = ["discrete", "continuum"]
//! nodes = 101
//! cells = 100
//! [sweep]
//! parameter = "K"
//! values = [1e-5, 1e-2, 1, 10]
//! ```
//!
//! [`load()`] turns it into a [`Scenario`] whose [`RunSpec`]s are all validated before anything
//! runs; [`execute`] runs them.

pub mod accuracy_check;
pub mod bundled;
pub mod error;
pub mod execute;
pub mod growth_stress;
pub mod impulse;
pub mod limits;
pub mod load;
pub mod model;
pub mod overrides;
pub mod parallel;
pub mod roundoff;
pub mod schema;
pub mod sweep;
pub mod times;

pub use error::ScenarioError;
pub use load::{
    format_number, load, load_str, load_str_with, load_with, resolve, RunSpec, Scenario, SweepInfo,
    SweepPoint,
};
pub use model::ModelConfig;
pub use schema::{PlotSettings, ProfileAxis, Scale};
