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

/// A fresh method object of the given kind.
pub fn build(kind: MethodKind) -> Box<dyn Method> {
    match kind {
        MethodKind::Bdf => Box::new(bdf::Bdf::new()),
        // ESDIRK, Radau IIA and Dormand–Prince are wired in once their modules are committed.
        other => unimplemented!("method `{other}` not yet wired"),
    }
}
