//! Adapters onto the residual form: explicit ODEs `ẏ = f(t, y)` and mass-matrix systems
//! `M(t, y)·ẏ = f(t, y)`.
//!
//! * [`OdeProblem`] + [`Ode`]: `F(t, y, ẏ) = ẏ − f(t, y)`. The iteration matrix is
//!   `c·I − ∂f/∂y`; if the problem gives `∂f/∂y` ([`OdeProblem::jacobian`]) it is used directly,
//!   otherwise the driver builds it by coloured finite differences from the declared pattern.
//! * [`MassProblem`] + [`Mass`]: `F(t, y, ẏ) = M(t, y)·ẏ − f(t, y)`. Rows of `M` that are zero
//!   make the corresponding components algebraic (declare them with
//!   [`MassProblem::algebraic`]). With a constant mass matrix and `∂f/∂y` given, the iteration
//!   matrix `c·M − ∂f/∂y` is assembled exactly; otherwise finite differences are used.
//!
//! Per-component absolute tolerances, patterns and events pass straight through, by
//! [`forward_problem!`](crate::forward_problem) — the one forwarding mechanism of every wrapper
//! problem (these adapters, and celltissue's cell-array adapter and wrappers).

use crate::linalg::Matrix;
use crate::pattern::Pattern;
use crate::problem::{EventAction, JacobianSink, Problem, ResidualError};

/// Writes, inside an `impl` block, methods of [`Problem`] that just call the same method on a
/// field: `forward_problem!(field: method, method, …)`. Each name is one of `dim`, `pattern`,
/// `residual`, `atol`, `algebraic`, `num_events`, `events`, `handle_event`,
/// `restart_derivative`, `map_history`, `set_threads`, with [`Problem`]'s signature; `residual<S: Bound>` writes instead a
/// residual generic over a scalar `S` taking `&self`, and `jacobian(&self)` a Jacobian taking
/// `&self` (the shapes of celltissue's `CellArray`, whose other methods share [`Problem`]'s
/// signatures). The field may be a tuple index (`0`). `atol` forwards the error map
/// ([`Problem::error_map`]) too: the two describe one tolerance contract.
///
/// A wrapper writes by hand only what it changes, and lists the rest:
///
/// ```
/// use integrators::{Problem, ResidualError};
/// /// Counts residual evaluations of any problem.
/// struct Counted<P> { inner: P, calls: usize }
/// impl<P: Problem> Problem for Counted<P> {
///     fn residual(&mut self, t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> {
///         self.calls += 1;
///         self.inner.residual(t, y, yp, r)
///     }
///     integrators::forward_problem!(inner: dim, pattern, atol, algebraic, num_events, events,
///         handle_event, restart_derivative);
/// }
/// ```
///
/// (A blanket "delegating" trait with default forwarding would not do: a wrapper could then
/// not override single methods without specialization, and the signatures are shared with a
/// trait of another crate.)
#[macro_export]
macro_rules! forward_problem {
    ($f:tt : $($rest:tt)*) => {
        $crate::forward_problem!(@list $f; $($rest)*);
    };
    (@list $f:tt; ) => {};
    (@list $f:tt; residual<$s:ident : $bound:path> $(, $($rest:tt)*)?) => {
        fn residual<$s: $bound>(
            &self,
            t: f64,
            y: &[$s],
            yp: &[$s],
            r: &mut [$s],
        ) -> Result<(), $crate::ResidualError> {
            self.$f.residual(t, y, yp, r)
        }
        $crate::forward_problem!(@list $f; $($($rest)*)?);
    };
    (@list $f:tt; jacobian(&self) $(, $($rest:tt)*)?) => {
        fn jacobian(
            &self,
            t: f64,
            y: &[f64],
            yp: &[f64],
            c: f64,
            jac: &mut $crate::JacobianSink,
        ) -> Result<bool, $crate::ResidualError> {
            self.$f.jacobian(t, y, yp, c, jac)
        }
        $crate::forward_problem!(@list $f; $($($rest)*)?);
    };
    (@list $f:tt; $m:ident $(, $($rest:tt)*)?) => {
        $crate::forward_problem!(@one $f $m);
        $crate::forward_problem!(@list $f; $($($rest)*)?);
    };
    (@one $f:tt dim) => {
        fn dim(&self) -> usize {
            self.$f.dim()
        }
    };
    (@one $f:tt pattern) => {
        fn pattern(&self) -> $crate::Pattern {
            self.$f.pattern()
        }
    };
    (@one $f:tt residual) => {
        fn residual(
            &mut self,
            t: f64,
            y: &[f64],
            yp: &[f64],
            r: &mut [f64],
        ) -> Result<(), $crate::ResidualError> {
            self.$f.residual(t, y, yp, r)
        }
    };
    (@one $f:tt atol) => {
        fn atol(&self) -> Option<Vec<f64>> {
            self.$f.atol()
        }
        // the tolerances travel together: `atol` also forwards the error map
        fn error_map(&self) -> Option<$crate::ErrorMap> {
            self.$f.error_map()
        }
    };
    (@one $f:tt algebraic) => {
        fn algebraic(&self) -> Vec<bool> {
            self.$f.algebraic()
        }
        // what the outputs read travels with which components are algebraic
        fn outputs_read_rates(&self) -> bool {
            self.$f.outputs_read_rates()
        }
    };
    (@one $f:tt num_events) => {
        fn num_events(&self) -> usize {
            self.$f.num_events()
        }
    };
    (@one $f:tt events) => {
        fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
            self.$f.events(t, y, g)
        }
    };
    (@one $f:tt handle_event) => {
        fn handle_event(
            &mut self,
            t: f64,
            fired: &[usize],
            y: &mut Vec<f64>,
            yp: &[f64],
        ) -> Result<$crate::EventAction, $crate::ResidualError> {
            self.$f.handle_event(t, fired, y, yp)
        }
    };
    (@one $f:tt restart_derivative) => {
        fn restart_derivative(&mut self, t: f64, y: &[f64], yp: &mut [f64]) {
            self.$f.restart_derivative(t, y, yp)
        }
    };
    (@one $f:tt map_history) => {
        fn map_history(&self, t: f64, old: &[f64], derivative: bool, new: &mut [f64]) -> bool {
            self.$f.map_history(t, old, derivative, new)
        }
    };
    (@one $f:tt map_jacobian) => {
        fn map_jacobian(
            &self,
            t: f64,
            y: &[f64],
            yp: &[f64],
            jy: &mut $crate::linalg::Matrix,
            jyp: &mut $crate::linalg::Matrix,
        ) -> Result<bool, $crate::ResidualError> {
            self.$f.map_jacobian(t, y, yp, jy, jyp)
        }
    };
    (@one $f:tt set_threads) => {
        fn set_threads(&mut self, threads: usize) {
            self.$f.set_threads(threads)
        }
    };
}

/// An explicit ODE `ẏ = f(t, y)`. Wrap it in [`Ode`] to solve it.
///
/// ```
/// use integrators::adapters::{Ode, OdeProblem};
/// use integrators::{MethodKind, Options, ResidualError, Solver};
/// /// ẏ = -2y
/// struct Decay;
/// impl OdeProblem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
///         f[0] = -2.0 * y[0];
///         Ok(())
///     }
/// }
/// let sol = Solver::new(MethodKind::Bdf, Options { rtol: 1e-8, atol: 1e-10, ..Default::default() })
///     .solve(&mut Ode(Decay), 0.0, &[1.0], &[1.0])
///     .unwrap();
/// assert!((sol.y[0][0] - (-2.0f64).exp()).abs() < 1e-6);
/// ```
pub trait OdeProblem {
    /// Number of unknowns.
    fn dim(&self) -> usize;

    /// Evaluates `f = f(t, y)`.
    fn rhs(&mut self, t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError>;

    /// Adds `∂f/∂y` at `(t, y)` into `jac` (zeroed, shaped by [`pattern`](OdeProblem::pattern)).
    /// Return `Ok(false)` (the default) if not provided.
    fn jacobian(&mut self, _t: f64, _y: &[f64], _jac: &mut Matrix) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Structure of `∂f/∂y` (the diagonal is always included). Default dense.
    fn pattern(&self) -> Pattern {
        Pattern::Dense
    }

    /// Per-component absolute tolerances, or `None` for [`crate::Options::atol`].
    fn atol(&self) -> Option<Vec<f64>> {
        None
    }

    /// How the error tests measure the components (see [`Problem::error_map`]); default
    /// `None`, each on its own.
    fn error_map(&self) -> Option<crate::ErrorMap> {
        None
    }

    /// Number of event functions (may change after a resize).
    fn num_events(&self) -> usize {
        0
    }

    /// Event functions `g_i(t, y)`.
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Event handler; see [`Problem::handle_event`].
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        Ok(EventAction::Stop)
    }
}

/// Residual-form wrapper of an [`OdeProblem`]: `F = ẏ − f(t, y)`. The wrapped problem is
/// public (`ode.0`) so that callers and observers can read model state.
///
/// ```
/// use integrators::adapters::{Ode, OdeProblem};
/// use integrators::{Problem, ResidualError};
/// struct Decay;
/// impl OdeProblem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
///         f[0] = -2.0 * y[0];
///         Ok(())
///     }
/// }
/// // the residual form F = ẏ − f(t, y): zero on the solution
/// let mut p = Ode(Decay);
/// let mut r = [0.0];
/// p.residual(0.0, &[1.0], &[-2.0], &mut r).unwrap();
/// assert_eq!(r, [0.0]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Ode<P>(pub P);

/// Multiplies every stored value of `m` by `s`.
fn scale_matrix(m: &mut Matrix, s: f64) {
    match m {
        Matrix::Dense(d) => d.data.iter_mut().for_each(|v| *v *= s),
        Matrix::Banded(b) => b.data.iter_mut().for_each(|v| *v *= s),
        Matrix::Sparse(sp) => sp.values.iter_mut().for_each(|v| *v *= s),
    }
}

impl<P: OdeProblem> Problem for Ode<P> {
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        // f is written into r, then r = ẏ − f
        self.0.rhs(t, y, r)?;
        for (ri, &ypi) in r.iter_mut().zip(yp) {
            *ri = ypi - *ri;
        }
        Ok(())
    }

    fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        if !self.0.jacobian(t, y, jac)? {
            return Ok(false);
        }
        scale_matrix(jac, -1.0);
        for i in 0..self.0.dim() {
            jac.add(i, i, c);
        }
        Ok(true)
    }

    crate::forward_problem!(0: dim, pattern, atol, num_events, events, handle_event);
}

/// A mass-matrix system `M(t, y)·ẏ = f(t, y)`. Wrap it in [`Mass`] to solve it.
///
/// ```
/// use integrators::adapters::{Mass, MassProblem};
/// use integrators::{MethodKind, Options, ResidualError, Solver};
/// /// 2·ẏ0 = -y0 (differential), 0 = y1 - y0 (algebraic)
/// struct Dae;
/// impl MassProblem for Dae {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
///         f[0] = -y[0];
///         f[1] = y[1] - y[0];
///         Ok(())
///     }
///     fn mass_times(&mut self, _t: f64, _y: &[f64], v: &[f64], out: &mut [f64])
///         -> Result<(), ResidualError> {
///         out[0] = 2.0 * v[0];
///         out[1] = 0.0;
///         Ok(())
///     }
///     fn algebraic(&self) -> Vec<bool> { vec![false, true] }
/// }
/// let sol = Solver::new(MethodKind::Bdf, Options { rtol: 1e-8, atol: 1e-10, ..Default::default() })
///     .solve(&mut Mass::new(Dae), 0.0, &[1.0, 1.0], &[2.0])
///     .unwrap();
/// assert!((sol.y[0][0] - (-1.0f64).exp()).abs() < 1e-6);
/// assert!((sol.y[0][1] - sol.y[0][0]).abs() < 1e-9);
/// ```
pub trait MassProblem {
    /// Number of unknowns.
    fn dim(&self) -> usize;

    /// Evaluates `f = f(t, y)`.
    fn rhs(&mut self, t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError>;

    /// Evaluates `out = M(t, y)·v`.
    fn mass_times(
        &mut self,
        t: f64,
        y: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) -> Result<(), ResidualError>;

    /// Whether `M` is constant (independent of `t` and `y`). Only then is the exact iteration
    /// matrix assembled from [`mass_matrix`](MassProblem::mass_matrix) and
    /// [`jacobian`](MassProblem::jacobian); a state-dependent `M` adds `∂(M ẏ)/∂y`, which is left
    /// to finite differences. Default `false`.
    fn mass_is_constant(&self) -> bool {
        false
    }

    /// Adds `M` into `m` (zeroed, shaped by the pattern). `Ok(false)` (default): not provided.
    fn mass_matrix(&mut self, _t: f64, _y: &[f64], _m: &mut Matrix) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Adds `∂f/∂y` into `jac`. `Ok(false)` (default): not provided.
    fn jacobian(&mut self, _t: f64, _y: &[f64], _jac: &mut Matrix) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Structure of `c·M − ∂f/∂y`. Default dense.
    fn pattern(&self) -> Pattern {
        Pattern::Dense
    }

    /// Components with a zero row in `M` (algebraic). Default none.
    fn algebraic(&self) -> Vec<bool> {
        vec![false; self.dim()]
    }

    /// Whether the outputs read `ẏ` beyond the state ([`Problem::outputs_read_rates`]).
    /// Default false.
    fn outputs_read_rates(&self) -> bool {
        false
    }

    /// Per-component absolute tolerances, or `None` for [`crate::Options::atol`].
    fn atol(&self) -> Option<Vec<f64>> {
        None
    }

    /// How the error tests measure the components (see [`Problem::error_map`]); default
    /// `None`, each on its own.
    fn error_map(&self) -> Option<crate::ErrorMap> {
        None
    }

    /// Number of event functions (may change after a resize).
    fn num_events(&self) -> usize {
        0
    }

    /// Event functions `g_i(t, y)`.
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Event handler; see [`Problem::handle_event`].
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        Ok(EventAction::Stop)
    }
}

/// Residual-form wrapper of a [`MassProblem`]: `F = M(t, y)·ẏ − f(t, y)`.
///
/// ```
/// use integrators::adapters::{Mass, MassProblem};
/// use integrators::{MethodKind, Options, ResidualError, Solver};
/// /// ẏ₁ = −y₁ with the algebraic row 0 = y₂ − y₁ (M = diag(1, 0)).
/// struct Dae;
/// impl MassProblem for Dae {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
///         f[0] = -y[0];
///         f[1] = y[1] - y[0];
///         Ok(())
///     }
///     fn mass_times(&mut self, _t: f64, _y: &[f64], v: &[f64], out: &mut [f64]) -> Result<(), ResidualError> {
///         out[0] = v[0];
///         out[1] = 0.0;
///         Ok(())
///     }
///     fn algebraic(&self) -> Vec<bool> { vec![false, true] }
/// }
/// let sol = Solver::new(MethodKind::Radau, Options { rtol: 1e-8, atol: 1e-10, ..Default::default() })
///     .solve(&mut Mass::new(Dae), 0.0, &[1.0, 1.0], &[1.0])
///     .unwrap();
/// assert!((sol.y[0][1] - (-1.0f64).exp()).abs() < 1e-6); // y₂ follows y₁
/// ```
#[derive(Clone, Debug, Default)]
pub struct Mass<P> {
    /// The wrapped problem.
    pub inner: P,
    f: Vec<f64>,
    scratch: Option<(Pattern, Matrix)>,
}

impl<P: MassProblem> Mass<P> {
    /// Wraps `inner`.
    ///
    /// ```
    /// use integrators::adapters::{Mass, MassProblem};
    /// use integrators::{MethodKind, Options, ResidualError, Solver};
    /// /// ẏ₁ = −y₁ with the algebraic row 0 = y₂ − y₁ (M = diag(1, 0)).
    /// struct Dae;
    /// impl MassProblem for Dae {
    ///     fn dim(&self) -> usize { 2 }
    ///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
    ///         f[0] = -y[0];
    ///         f[1] = y[1] - y[0];
    ///         Ok(())
    ///     }
    ///     fn mass_times(&mut self, _t: f64, _y: &[f64], v: &[f64], out: &mut [f64]) -> Result<(), ResidualError> {
    ///         out[0] = v[0];
    ///         out[1] = 0.0;
    ///         Ok(())
    ///     }
    ///     fn algebraic(&self) -> Vec<bool> { vec![false, true] }
    /// }
    /// let m = Mass::new(Dae);
    /// assert_eq!(m.inner.dim(), 2);
    /// ```
    pub fn new(inner: P) -> Self {
        Self {
            inner,
            f: Vec::new(),
            scratch: None,
        }
    }
}

impl<P: MassProblem> Problem for Mass<P> {
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        self.f.resize(r.len(), 0.0);
        self.inner.rhs(t, y, &mut self.f)?;
        self.inner.mass_times(t, y, yp, r)?;
        for (ri, fi) in r.iter_mut().zip(&self.f) {
            *ri -= fi;
        }
        Ok(())
    }

    fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        if !self.inner.mass_is_constant() {
            return Ok(false);
        }
        let n = self.inner.dim();
        let pattern = self.inner.pattern();
        let fresh = match &self.scratch {
            Some((p, m)) => m.n() != n || *p != pattern,
            None => true,
        };
        if fresh {
            let m = Matrix::zeros(n, &pattern);
            self.scratch = Some((pattern, m));
        }
        let mm = &mut self.scratch.as_mut().expect("allocated").1;
        mm.set_zero();
        if !self.inner.mass_matrix(t, y, mm)? {
            return Ok(false);
        }
        if !self.inner.jacobian(t, y, jac)? {
            return Ok(false);
        }
        // jac = c·M − ∂f/∂y
        jac.axpby(-1.0, c, mm);
        Ok(true)
    }

    crate::forward_problem!(inner: dim, pattern, algebraic, atol, num_events, events, handle_event);
}
