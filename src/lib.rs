//! # celltissue — discrete-to-continuum mechanics of cells in tissues
//!
//! Soft tissue as arrays of incompressible hyperelastic cells (Kelvin–Voigt viscosity, substrate
//! drag `K·κ`, `κ = (A/A₀)^m`), and the continuum PDEs that the same cell laws upscale to. The
//! canonical equations are in `docs/model.md`; module docs cite its sections.
//!
//! Data flow: scenario file → validated scenario → (cell array, cell laws, boundary conditions)
//! → discrete or continuum builder → [`integrators`] problem → integrator → observers → writers.
#![warn(missing_docs)]

pub mod array;
pub mod boundary;
pub mod cell;
#[cfg(feature = "cli")]
pub mod cli;
pub mod drive;
pub mod energy;
pub mod events;
pub mod line;
pub mod modes;
pub mod observe;
pub mod output;
pub mod proliferation;
pub mod registry;
pub mod runner;
pub mod scalar;
pub mod scenario;
pub mod settings;
pub mod sheet;
pub mod substrate;

pub use array::{ArrayProblem, CellArray};
pub use energy::{
    AnyEnergy, EnergyError, Gent, Hgo, LawVisitor, LineResponse, MooneyRivlin, NeoHookean, Ogden,
    Scaled, ShearResponse, SheetResponse, StrainEnergy,
};
pub use scalar::Scalar;
pub use settings::SolveSettings;

/// The time integrators (crate `celltissue-integrators`), so an outside crate needs only
/// `celltissue` in its `Cargo.toml`.
pub use integrators;
pub use integrators::{
    ErrorNorm, Method, MethodChoice, MethodKind, Options, OptionsError, Parallelism, Problem,
    Solver,
};
/// Forward-mode AD numbers (crate `num-dual`): strain energies and growth laws are written
/// generically over [`Scalar`], which `f64` and [`num_dual::Dual64`] implement.
pub use num_dual;
/// Serialisation (crate `serde`): a registered strain energy derives `Serialize` and
/// `Deserialize` (with `#[serde(crate = "celltissue::serde")]` when `serde` is not a direct
/// dependency).
pub use serde;

/// Time-stepping methods by name: register a method of one's own ([`method::register`]) and scenarios
/// select it with `solver.method = "<name>"` (see `docs/guide-method.md`).
pub mod method {
    pub use integrators::method::{
        register, registered, CustomMethod, Method, MethodChoice, MethodError, MethodKind,
    };
}

pub use cell::{GrowthLaw, GrowthRate};
pub use events::{CellView, DivisionRule};

/// The extension guides in `docs/`: their code blocks are compiled and run as doctests.
#[cfg(doctest)]
mod guides {
    #[doc = include_str!("../docs/guide-method.md")]
    struct Method;
    #[doc = include_str!("../docs/guide-growth-law.md")]
    struct GrowthLaw;
    #[doc = include_str!("../docs/guide-division-rule.md")]
    struct DivisionRule;
}
