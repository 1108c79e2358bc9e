//! The time-stepping schemes: BDF, ESDIRK, Radau IIA, Dormand–Prince.
//!
//! Each implements [`Method`]; [`build`] (or [`MethodKind::build`]) returns a fresh one by kind.
//!
//! ```
//! use integrators::{methods, MethodKind};
//! let m = methods::build(MethodKind::Bdf);
//! assert_eq!(m.name(), "bdf");
//! ```

use crate::method::{Method, MethodKind};

pub mod bdf;
pub mod dopri;
pub mod esdirk;
pub mod radau;

/// A fresh method object of the given kind.
pub fn build(kind: MethodKind) -> Box<dyn Method> {
    match kind {
        MethodKind::Bdf => Box::new(bdf::Bdf::new()),
        MethodKind::Esdirk => Box::new(esdirk::Esdirk::new()),
        MethodKind::Radau => Box::new(radau::Radau5::new()),
        MethodKind::Dopri => Box::new(dopri::Dopri5::new()),
    }
}
