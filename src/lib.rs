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
pub mod energy;
pub mod events;
pub mod line;
pub mod observe;
pub mod output;
pub mod proliferation;
pub mod scalar;
pub mod scenario;
pub mod sheet;
pub mod substrate;

pub use array::{ArrayProblem, CellArray};
pub use energy::{
    AnyEnergy, EnergyError, Gent, Hgo, LineResponse, MooneyRivlin, NeoHookean, Ogden, Scaled,
    ShearResponse, SheetResponse, StrainEnergy,
};
pub use scalar::Scalar;
