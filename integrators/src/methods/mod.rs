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
pub(crate) mod one_step;
pub mod radau;

/// A fresh method object of the given kind.
///
/// ```
/// use integrators::{methods, MethodKind};
/// for kind in [MethodKind::Bdf, MethodKind::Esdirk, MethodKind::Radau, MethodKind::Dopri] {
///     assert_eq!(methods::build(kind).name(), kind.name());
/// }
/// ```
pub fn build(kind: MethodKind) -> Box<dyn Method> {
    match kind {
        MethodKind::Bdf => Box::new(bdf::Bdf::new()),
        MethodKind::Esdirk => Box::new(esdirk::Esdirk::new()),
        MethodKind::Radau => Box::new(radau::Radau5::new()),
        MethodKind::Dopri => Box::new(dopri::Dopri5::new()),
    }
}

/// Writes, inside `impl Method for X`, the accessors every method answers from its fields
/// `t`, `t_prev`, `y`, `yp` (vectors) and `h` (the step to try next): [`Method::t`],
/// [`Method::t_prev`], [`Method::y`], [`Method::yp`], [`Method::h_next`]. With `one_step`, also
/// [`Method::step`] as the shared step loop of [`one_step`] (the type implements
/// `one_step::OneStep`).
macro_rules! method_accessors {
    (one_step) => {
        fn step(
            &mut self,
            sys: &mut $crate::system::System<'_>,
            t_stop: f64,
        ) -> Result<usize, $crate::error::SolverError> {
            $crate::methods::one_step::step(self, sys, t_stop)
        }
        $crate::methods::method_accessors!();
    };
    () => {
        fn t(&self) -> f64 {
            self.t
        }
        fn t_prev(&self) -> f64 {
            self.t_prev
        }
        fn y(&self) -> &[f64] {
            &self.y
        }
        fn yp(&self) -> &[f64] {
            &self.yp
        }
        fn h_next(&self) -> f64 {
            self.h
        }
    };
}
pub(crate) use method_accessors;

/// Shared precondition of every one-step method's `step`: the method was started and `t_stop`
/// lies after the current time.
pub(crate) fn check_step_request(
    started: bool,
    t: f64,
    t_stop: f64,
) -> Result<(), crate::error::SolverError> {
    use crate::error::{ErrorKind, SolverError};
    if !started {
        return Err(SolverError::new(
            ErrorKind::InvalidInput("step called before start".into()),
            t,
            None,
        ));
    }
    if t_stop.is_nan() || t_stop <= t {
        return Err(SolverError::new(
            ErrorKind::InvalidInput(format!(
                "t_stop = {t_stop} must be after the current time {t}"
            )),
            t,
            None,
        ));
    }
    Ok(())
}
