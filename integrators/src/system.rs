//! [`System`]: the machinery shared by every method — counted residual calls, the iteration
//! matrix `J = ∂F/∂y + c·∂F/∂ẏ` built by pattern (user Jacobian → exact coloured directional
//! derivatives → coloured finite differences), its factorisation, error weights and norms, and
//! consistent initialisation.
//!
//! The signatures here are the contract between the driver, the methods and the linear
//! algebra; the Jacobian construction itself lives in [`crate::jacobian`].

use crate::error::{ErrorKind, RecoverableCause, SolverError};
use crate::error_map::ErrorMap;
use crate::jacobian::{self, Columns};
use crate::linalg::{LinearSolver, Matrix};
use crate::options::ErrorNorm;
use crate::options::Options;
use crate::pattern::Pattern;
use crate::problem::{Problem, ResidualError};
use crate::stats::Stats;

/// Why a step attempt failed in a way the method may recover from by reducing the step.
///
/// ```
/// use integrators::system::StepFailure;
/// use integrators::{ErrorKind, SolverError};
/// // a failure the method cannot recover from carries the solver's error
/// let f = StepFailure::Fatal(SolverError::new(ErrorKind::NonFinite, 1.0, None));
/// assert!(matches!(f, StepFailure::Fatal(ref e) if e.t == 1.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum StepFailure {
    /// Residual reported `ResidualError::Recoverable`, a non-finite value appeared, or a
    /// factorisation was singular: retry with a smaller step.
    Recoverable {
        /// Cause, for the final error if retries run out.
        reason: RecoverableCause,
        /// Component responsible, if known.
        component: Option<usize>,
    },
    /// Unrecoverable: abort with this error.
    Fatal(SolverError),
}

/// Problem plus shared workspaces and counters, handed to a [`crate::Method`] on every call.
///
/// ```
/// use integrators::{Problem, ResidualError};
/// /// ẏ = −y in residual form.
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
///         r[0] = yp[0] + y[0];
///         Ok(())
///     }
/// }
/// use integrators::system::SystemCache;
/// use integrators::{Options, Stats, System};
/// let (mut p, opts, mut stats) = (Decay, Options::default(), Stats::default());
/// let mut cache = SystemCache::default();
/// cache.rebuild(&p, &opts).unwrap();
/// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
/// let mut r = [0.0];
/// sys.residual(0.0, &[1.0], &[-1.0], &mut r).unwrap(); // counted in the statistics
/// assert_eq!((r[0], sys.dim(), sys.stats.residual_calls), (0.0, 1, 1));
/// ```
pub struct System<'a> {
    /// The user's problem.
    pub problem: &'a mut dyn Problem,
    /// Options.
    pub opts: &'a Options,
    /// Work counters.
    pub stats: &'a mut Stats,
    /// Cached per-dimension data (pattern, colouring, atol, algebraic mask).
    pub(crate) cache: &'a mut SystemCache,
}

/// Per-dimension data cached by the driver; rebuilt after a resize by [`SystemCache::rebuild`].
///
/// ```
/// use integrators::{Problem, ResidualError};
/// /// ẏ = −y in residual form.
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
///         r[0] = yp[0] + y[0];
///         Ok(())
///     }
/// }
/// use integrators::system::SystemCache;
/// use integrators::Options;
/// let mut cache = SystemCache::default();
/// cache.rebuild(&Decay, &Options::default()).unwrap();
/// assert_eq!(cache.colour_count(), 1); // one Jacobian colour for one unknown
/// ```
#[derive(Default)]
pub struct SystemCache {
    pub(crate) n: usize,
    pub(crate) pattern: Option<Pattern>,
    pub(crate) ncolours: usize,
    pub(crate) atol: Vec<f64>,
    pub(crate) algebraic: Vec<bool>,
    /// [`Problem::outputs_read_rates`], read with the algebraic flags.
    pub(crate) outputs_read_rates: bool,
    /// Columns of each colour (`colour_cols[k]` = the columns `j` with `colour[j] == k`).
    pub(crate) colour_cols: Vec<Vec<usize>>,
    /// Work vectors of the Jacobian assembly (kept across calls: a large line would otherwise
    /// allocate and page-fault four fresh `n`-vectors per Jacobian).
    pub(crate) jac_work: [Vec<f64>; 4],
    /// Buffers one phase of a solve hands to the next (see [`Spares`]). Dropped by
    /// [`rebuild`](SystemCache::rebuild).
    pub(crate) spares: Spares,
    /// Set once [`Problem::jacobian`] has returned `Ok(false)`: later Jacobians skip it (and
    /// the zero fill of the matrix it would have written, a whole pass over a large band).
    /// Cleared by [`rebuild`](SystemCache::rebuild).
    pub(crate) no_user_jacobian: bool,
    /// Rejected step attempts not yet passed to the observer (drained by the driver after
    /// every step; see [`System::reject_step`]).
    pub(crate) rejected: Vec<crate::observer::RejectedStep>,
    /// The problem's [`ErrorMap`] (empty: the identity).
    pub(crate) map: ErrorMap,
    /// With a map: [`ErrorMap::effective_atol`] of `atol` (anchors include `rtol·size`);
    /// empty otherwise.
    pub(crate) eatol: Vec<f64>,
    /// The last [`System::roundoff_ratio`] the driver measured (0 before it has): the weighted
    /// size of one rounding unit of the tested quantities. A Newton correction no larger
    /// cannot be resolved in the state ([`System::below_roundoff`]).
    pub(crate) roundoff: f64,
}

/// Buffers a finished phase of a solve leaves for the next one (consistent initialisation →
/// the starting-step estimate → the method's Newton matrices, solver and vectors), all of the
/// current dimension and pattern. A large problem otherwise faults in fresh pages for every
/// phase: at 10⁶ unknowns each vector is 2 048 page faults, and a start used to touch ≈ 50 of
/// them. Taken buffers hold stale values: [`System::take_vec`] and [`System::take_matrix`]
/// say what their callers must overwrite.
#[derive(Default)]
pub(crate) struct Spares {
    vecs: Vec<Vec<f64>>,
    matrices: Vec<Matrix>,
    /// Banded solvers only: a sparse LU's symbolic analysis is counted in the statistics,
    /// and reusing it would change them.
    solvers: Vec<LinearSolver>,
}

impl SystemCache {
    /// Re-reads dimension, pattern, colouring, tolerances and algebraic flags from the problem
    /// (at the start and after every resize). Errors if the problem's declared sizes disagree.
    ///
    /// ```
    /// use integrators::system::SystemCache;
    /// use integrators::{Options, Problem, ResidualError};
    /// /// Declares 3 unknowns but 2 tolerances: rebuild refuses it.
    /// struct Bad;
    /// impl Problem for Bad {
    ///     fn dim(&self) -> usize { 3 }
    ///     fn residual(&mut self, _: f64, _: &[f64], _: &[f64], _: &mut [f64]) -> Result<(), ResidualError> { Ok(()) }
    ///     fn atol(&self) -> Option<Vec<f64>> { Some(vec![1e-8; 2]) }
    /// }
    /// assert!(SystemCache::default().rebuild(&Bad, &Options::default()).is_err());
    /// ```
    pub fn rebuild(&mut self, problem: &dyn Problem, opts: &Options) -> Result<(), ErrorKind> {
        let n = problem.dim();
        let pattern = problem.pattern();
        if let Pattern::Sparse(p) = &pattern {
            if p.n() != n {
                return Err(ErrorKind::InvalidInput(format!(
                    "sparse pattern is {}×{} but dim() = {n}",
                    p.n(),
                    p.n()
                )));
            }
        }
        let atol = match problem.atol() {
            Some(a) => {
                if a.len() != n {
                    return Err(ErrorKind::InvalidInput(format!(
                        "atol() has length {} but dim() = {n}",
                        a.len()
                    )));
                }
                // (a branch-free sweep first: this runs at every division of a dividing line)
                let valid = |x: f64| x > 0.0 && x.is_finite();
                if !a.iter().fold(true, |ok, &x| ok & valid(x)) {
                    let i = a.iter().position(|&x| !valid(x)).unwrap_or_default();
                    return Err(ErrorKind::InvalidInput(format!(
                        "atol()[{i}] = {} must be positive and finite",
                        a[i]
                    )));
                }
                a
            }
            None => {
                if !(opts.atol > 0.0 && opts.atol.is_finite()) {
                    return Err(ErrorKind::InvalidInput(format!(
                        "atol = {} must be positive and finite",
                        opts.atol
                    )));
                }
                vec![opts.atol; n]
            }
        };
        let mut map = problem.error_map().unwrap_or_default();
        if !map.is_empty() {
            map.check_len(n)?;
        }
        let algebraic = problem.algebraic();
        if algebraic.len() != n {
            return Err(ErrorKind::InvalidInput(format!(
                "algebraic() has length {} but dim() = {n}",
                algebraic.len()
            )));
        }
        let colour_cols = match pattern {
            // column j has colour j mod w: each group is a stride, built at its exact size
            // (no per-column colour vector, no regrowth of ten-million-entry lists)
            Pattern::Banded { lower, upper } if n > 0 => {
                let w = (lower + upper + 1).min(n);
                (0..w).map(|k| (k..n).step_by(w).collect()).collect()
            }
            _ => {
                let (colour, ncolours) = pattern.colouring(n);
                let mut groups = vec![Vec::new(); ncolours];
                for (j, &k) in colour.iter().enumerate() {
                    groups[k].push(j);
                }
                groups
            }
        };
        let ncolours = colour_cols.len();
        self.n = n;
        let old_pattern = self.pattern.replace(pattern);
        self.ncolours = ncolours;
        self.eatol = if map.is_empty() {
            Vec::new()
        } else {
            map.effective_atol(&atol, opts.rtol)
        };
        self.map = map;
        self.atol = atol;
        self.algebraic = algebraic;
        self.outputs_read_rates = problem.outputs_read_rates();
        self.colour_cols = colour_cols;
        // Spares survive a resize that keeps a band (a dividing line): vectors are resized
        // when taken, band matrices and solvers grow in place here; anything else is dropped.
        // Their contents are stale either way, as every spare's is.
        let same_band = matches!(
            (&old_pattern, &self.pattern),
            (Some(a @ Pattern::Banded { .. }), Some(b)) if a == b
        );
        let spares = std::mem::take(&mut self.spares);
        if same_band {
            self.spares.vecs = spares.vecs;
            self.spares.matrices = spares
                .matrices
                .into_iter()
                .filter_map(|mut m| m.grow(n).then_some(m))
                .collect();
            self.spares.solvers = spares
                .solvers
                .into_iter()
                .filter_map(|mut l| l.grow(n).then_some(l))
                .collect();
        }
        self.no_user_jacobian = false;
        Ok(())
    }

    /// Number of colours of the current pattern (= residual calls per finite-difference
    /// Jacobian when the base residual is supplied).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    ///
    /// assert_eq!(cache.colour_count(), 1);
    /// ```
    pub fn colour_count(&self) -> usize {
        self.ncolours
    }
}

impl<'a> System<'a> {
    /// Bundles the pieces (the driver calls this).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.dim(), 1);
    /// ```
    pub fn new(
        problem: &'a mut dyn Problem,
        opts: &'a Options,
        stats: &'a mut Stats,
        cache: &'a mut SystemCache,
    ) -> Self {
        Self {
            problem,
            opts,
            stats,
            cache,
        }
    }

    /// How this solve may split its vector passes ([`Options::parallel`]).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.parallel(), integrators::Parallelism::Serial);
    /// ```
    pub fn parallel(&self) -> crate::Parallelism {
        self.opts.parallel
    }

    /// The default problem size from which passes are split
    /// ([`crate::Parallelism::DEFAULT_MIN_LEN`]; a solve's own is in [`Options::parallel`]).
    pub const PARALLEL_MIN: usize = crate::Parallelism::DEFAULT_MIN_LEN;

    /// Problem dimension (as cached at the last rebuild).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.dim(), 1);
    /// ```
    pub fn dim(&self) -> usize {
        self.cache.n
    }

    /// Declared pattern.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(*sys.pattern(), integrators::Pattern::Dense);
    /// ```
    pub fn pattern(&self) -> &Pattern {
        self.cache
            .pattern
            .as_ref()
            .expect("SystemCache::rebuild not called")
    }

    /// Absolute tolerances per component.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.atol(), [1e-8]); // the scalar atol, per component
    /// ```
    pub fn atol(&self) -> &[f64] {
        &self.cache.atol
    }

    /// The problem's error map (empty: the identity; see [`crate::error_map`]).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert!(sys.error_map().is_empty()); // no map: the identity
    /// ```
    pub fn error_map(&self) -> &ErrorMap {
        &self.cache.map
    }

    /// Re-weighs the error map's end rows that reach a prescribed position
    /// ([`ErrorMap::with_end_at`]) at the state `y` a step starts from at `t`; nothing for a
    /// map without such rows. The solver calls it before each step, so that the last cell
    /// before a prescribed end is held to its own stretch.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// sys.refresh_end_weights(0.0, &[1.0]); // no map: nothing to do
    /// assert!(!sys.error_map().has_positions());
    /// ```
    pub fn refresh_end_weights(&mut self, t: f64, y: &[f64]) {
        if self.cache.map.has_positions() {
            self.cache.map.refresh_ends(t, y, self.opts.rtol);
        }
    }

    /// The tolerances the weights add to `rtol·|…|`: [`atol`](Self::atol), with an anchor's
    /// `rtol·size` included when the problem has an error map.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.weight_atol(), [1e-8]);
    /// ```
    pub fn weight_atol(&self) -> &[f64] {
        if self.cache.map.is_empty() {
            &self.cache.atol
        } else {
            &self.cache.eatol
        }
    }

    /// Newton weights at `y`: [`error_weights`](Self::error_weights) without the suppression
    /// of algebraic components (algebraic unknowns must converge too).
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let mut w = [0.0];
    /// sys.newton_weights(&[2.0], &mut w);
    /// assert!((w[0] - 1.0 / (1e-6 * 2.0 + 1e-8)).abs() < 1e-3);
    /// ```
    pub fn newton_weights(&self, y: &[f64], w: &mut [f64]) {
        assert!(
            y.len() == self.dim() && w.len() == self.dim(),
            "newton_weights: dimension mismatch"
        );
        let rtol = self.opts.rtol;
        if self.cache.map.is_empty() {
            for ((wi, yi), ai) in w.iter_mut().zip(y).zip(&self.cache.atol) {
                *wi = 1.0 / (rtol * yi.abs() + ai);
            }
        } else {
            self.cache.map.weights(y, &self.cache.eatol, rtol, 0, w);
        }
    }

    /// How close the tolerances come to the round-off of the tested quantities at `y`:
    /// [`ErrorMap::roundoff_ratio`] through the problem's map, `ε·|y_i|·w_i` without one; the
    /// largest ratio and its component.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-15, atol: 1e-20, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// // rtol 1e-15 is within a factor 5 of the resolution ε ≈ 2.2e-16 of a double
    /// let (ratio, i) = sys.roundoff_ratio(&[3.0]);
    /// assert!((ratio - f64::EPSILON / 1e-15).abs() < 1e-6 && i == 0);
    /// ```
    pub fn roundoff_ratio(&self, y: &[f64]) -> (f64, usize) {
        let rtol = self.opts.rtol;
        if self.cache.map.is_empty() {
            let mut worst = (0.0, 0);
            for (i, (yi, ai)) in y.iter().zip(&self.cache.atol).enumerate() {
                let r = f64::EPSILON * yi.abs() / (rtol * yi.abs() + ai);
                if r > worst.0 {
                    worst = (r, i);
                }
            }
            worst
        } else {
            self.cache.map.roundoff_ratio(y, &self.cache.eatol, rtol)
        }
    }

    /// Whether a Newton correction of weighted norm `delnrm` is within the rounding of the
    /// state: no larger than the round-off ratio the driver last measured
    /// ([`roundoff_ratio`](Self::roundoff_ratio), before the first step and every
    /// [`crate::solver::ROUNDOFF_CHECK_EVERY`] steps). Adding such a correction changes the
    /// state by about an ulp or not at all, so the next correction is as large and a
    /// contraction test reads rounding as divergence; a method accepts its iterate there
    /// instead of failing the step. The tight tolerance of a purely algebraic line (K = 0,
    /// η = 0, rtol 1e-10) failed every first step after a restart that way: its second
    /// correction was bitwise its first.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options::default(), Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// // before the driver has measured the round-off, nothing counts as below it
    /// assert!(!sys.below_roundoff(1e-300));
    /// ```
    pub fn below_roundoff(&self, delnrm: f64) -> bool {
        delnrm <= self.cache.roundoff
    }

    /// The norm ([`Options::norm`]) of the weighted error vector `v` through the problem's
    /// error map: `ErrorNorm::of(v, w)` without a map, the norm of the weighted cell-level
    /// quantities with one. The local-error and Newton tests of every method use it.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.norm(&[0.5], &[2.0]), 1.0); // RMS of v·w
    /// ```
    pub fn norm(&self, v: &[f64], w: &[f64]) -> f64 {
        self.norm_with(self.opts.norm, v, w)
    }

    /// [`norm`](Self::norm) with a given kind of norm.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.norm_with(integrators::ErrorNorm::Max, &[-0.5], &[2.0]), 1.0);
    /// ```
    pub fn norm_with(&self, norm: ErrorNorm, v: &[f64], w: &[f64]) -> f64 {
        self.cache.map.norm(v, w, norm)
    }

    /// The component with the largest weighted (cell-level) error, for failure reports.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.worst(&[3.0], &[1.0]), Some(0));
    /// ```
    pub fn worst(&self, v: &[f64], w: &[f64]) -> Option<usize> {
        self.cache.map.worst(v, w)
    }

    /// Algebraic-component flags.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.algebraic(), [false]);
    /// ```
    pub fn algebraic(&self) -> &[bool] {
        &self.cache.algebraic
    }

    /// Counted residual evaluation; non-finite output becomes a recoverable failure naming the
    /// component.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let mut r = [0.0];
    /// sys.residual(0.0, &[1.0], &[-1.0], &mut r).unwrap();
    /// assert_eq!((r[0], sys.stats.residual_calls), (0.0, 1)); // counted
    /// ```
    pub fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), StepFailure> {
        self.stats.residual_calls += 1;
        self.problem
            .residual(t, y, yp, r)
            .map_err(|e| self.residual_failure(e, t))?;
        if let Some(i) = crate::linalg::first_non_finite(r) {
            return Err(StepFailure::Recoverable {
                reason: RecoverableCause::NonFiniteResidual {
                    component: i,
                    value: r[i],
                },
                component: Some(i),
            });
        }
        Ok(())
    }

    /// Maps a [`ResidualError`] at time `t` to a [`StepFailure`].
    pub(crate) fn residual_failure(&self, e: ResidualError, t: f64) -> StepFailure {
        match e {
            ResidualError::Recoverable { reason, component } => StepFailure::Recoverable {
                reason: RecoverableCause::Rejected(reason),
                component,
            },
            ResidualError::Fatal(msg) => {
                StepFailure::Fatal(SolverError::new(ErrorKind::Residual(msg), t, None))
            }
        }
    }

    /// Counts a rejected step attempt (from `t` with size `h`) and hands it to the solve's
    /// [`crate::observer::Observer`] once the method's step returns. A [`crate::Method`]
    /// calls this for every attempt it retries.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// sys.reject_step(0.0, 0.1, integrators::observer::RejectCause::ErrorTest, Some(0));
    /// assert_eq!(sys.stats.rejected_steps, 1);
    /// ```
    pub fn reject_step(
        &mut self,
        t: f64,
        h: f64,
        cause: crate::observer::RejectCause,
        component: Option<usize>,
    ) {
        self.stats.rejected_steps += 1;
        self.cache.rejected.push(crate::observer::RejectedStep {
            t,
            h,
            cause,
            component,
        });
    }

    /// A zeroed matrix shaped by the current pattern.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.new_matrix().n(), 1);
    /// ```
    pub fn new_matrix(&self) -> Matrix {
        Matrix::zeros(self.dim(), self.pattern())
    }

    /// A linear solver for the current pattern (symbolic analysis happens at first factor),
    /// direct or iterative as [`Options::linear_solver`] says.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// assert_eq!(sys.new_linear_solver().krylov_counters().solves, 0);
    /// ```
    pub fn new_linear_solver(&self) -> LinearSolver {
        let mut lin =
            LinearSolver::with_choice(self.dim(), self.pattern(), self.opts.linear_solver);
        lin.set_parallelism(self.parallel());
        lin
    }

    /// A vector of length [`dim`](Self::dim) from the spares (see [`Spares`]) or freshly
    /// zeroed; a spare holds stale values, so the caller must write every entry before
    /// reading it. Hand it back with [`give_vec`](Self::give_vec) when done.
    pub(crate) fn take_vec(&mut self) -> Vec<f64> {
        let n = self.dim();
        match self.cache.spares.vecs.pop() {
            Some(mut v) => {
                v.resize(n, 0.0);
                v
            }
            None => vec![0.0; n],
        }
    }

    /// Returns a vector to the spares (one of another length too: [`take_vec`](Self::take_vec)
    /// resizes it, keeping its allocation across a resize of the problem).
    pub(crate) fn give_vec(&mut self, v: Vec<f64>) {
        if v.capacity() > 0 {
            self.cache.spares.vecs.push(v);
        }
    }

    /// A matrix of the current pattern from the spares, or [`new_matrix`](Self::new_matrix).
    /// A spare's structural entries are stale (its other storage slots are zero, as in a new
    /// one): fill it with [`jacobian`](Self::jacobian) or zero it before use.
    pub(crate) fn take_matrix(&mut self) -> Matrix {
        self.cache
            .spares
            .matrices
            .pop()
            .unwrap_or_else(|| self.new_matrix())
    }

    /// Returns a matrix to the spares.
    pub(crate) fn give_matrix(&mut self, m: Matrix) {
        if m.n() == self.dim() {
            self.cache.spares.matrices.push(m);
        }
    }

    /// A linear solver from the spares (a banded one, factorisation stale), or
    /// [`new_linear_solver`](Self::new_linear_solver).
    pub(crate) fn take_solver(&mut self) -> LinearSolver {
        self.cache
            .spares
            .solvers
            .pop()
            .unwrap_or_else(|| self.new_linear_solver())
    }

    /// Returns a linear solver to the spares if the pattern is banded (see [`Spares`]).
    pub(crate) fn give_solver(&mut self, lu: LinearSolver) {
        if matches!(self.pattern(), Pattern::Banded { .. }) {
            self.cache.spares.solvers.push(lu);
        }
    }

    /// Evaluates `J = ∂F/∂y + c·∂F/∂ẏ` at `(t, y, ẏ)` into `jac` (zeroed first): the problem's
    /// own Jacobian if it provides one, else exact coloured directional derivatives, else
    /// coloured finite differences. Counted as one Jacobian evaluation.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// // the iteration matrix ∂F/∂y + c·∂F/∂ẏ = 1 + c
    /// let mut j = sys.new_matrix();
    /// sys.jacobian(0.0, &[1.0], &[-1.0], 10.0, &mut j).unwrap();
    /// assert!((j.get(0, 0) - 11.0).abs() < 1e-6);
    /// assert_eq!(sys.stats.jacobian_evals, 1);
    /// ```
    pub fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut Matrix,
    ) -> Result<(), StepFailure> {
        self.stats.jacobian_evals += 1;
        jacobian::assemble(self, t, y, yp, Columns::Iteration { c }, None, jac)
    }

    /// Both halves of the iteration matrix at `(t, y, ẏ)`: `∂F/∂y` into `jy` and `∂F/∂ẏ` into
    /// `jyp`, for a method that refactorises `∂F/∂y + α·∂F/∂ẏ` as `α` changes (BDF), `alpha`
    /// the coefficient it needs now. A differential column whose `∂F/∂ẏ` is lost to rounding
    /// in `J(1) − J(0)` (below about 2⁻⁴⁰ of its `∂F/∂y`) is read from `(J(C) − J(0))/C` with
    /// `C` a large power of two, as in the consistent initialisation, when `alpha` exceeds 2³⁰
    /// (below, such a column changes the Newton matrix by less than 2⁻¹⁰). Counted as the
    /// matrix evaluations it took: two, or more when such columns were restored.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// /// K·ẏ + y = 0 with K far below the unit stiffness: J(1) − J(0) = (1 + K) − 1 = 0.
    /// struct FaintDrag;
    /// impl Problem for FaintDrag {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    ///         r[0] = 1e-20 * yp[0] + y[0];
    ///         Ok(())
    ///     }
    /// }
    /// # let (mut p, opts, mut stats) = (FaintDrag, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let (mut jy, mut jyp) = (sys.new_matrix(), sys.new_matrix());
    /// sys.jacobian_pair(0.0, &[1.0], &[0.0], 1e12, &mut jy, &mut jyp).unwrap();
    /// assert_eq!(jy.get(0, 0), 1.0);
    /// assert!((jyp.get(0, 0) / 1e-20 - 1.0).abs() < 1e-6);
    /// assert_eq!(sys.stats.jacobian_evals, 3); // J(0), J(1) and one J(C)
    /// ```
    pub fn jacobian_pair(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        alpha: f64,
        jy: &mut Matrix,
        jyp: &mut Matrix,
    ) -> Result<(), StepFailure> {
        jacobian::pair(self, t, y, yp, alpha, jy, jyp)
    }

    /// As [`jacobian`](System::jacobian), for a caller that already holds `r0 = F(t, y, ẏ)`:
    /// finite differences then cost exactly one residual call per colour
    /// ([`SystemCache::colour_count`]; bandwidth+1 for banded) instead of one more.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let mut j = sys.new_matrix();
    /// sys.jacobian_with_residual(0.0, &[1.0], &[-1.0], 10.0, &[0.0], &mut j).unwrap();
    /// assert!((j.get(0, 0) - 11.0).abs() < 1e-6);
    /// ```
    pub fn jacobian_with_residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        r0: &[f64],
        jac: &mut Matrix,
    ) -> Result<(), StepFailure> {
        self.stats.jacobian_evals += 1;
        jacobian::assemble(self, t, y, yp, Columns::Iteration { c }, Some(r0), jac)
    }

    /// Counted factorisation; a zero pivot is a recoverable failure.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let (mut j, mut lu) = (sys.new_matrix(), sys.new_linear_solver());
    /// j.add(0, 0, 4.0);
    /// sys.factor(&mut lu, &j).unwrap();
    /// assert_eq!(sys.stats.factorizations, 1);
    /// assert!(sys.factor(&mut lu, &sys.new_matrix()).is_err()); // singular: recoverable, not a panic
    /// ```
    pub fn factor(&mut self, solver: &mut LinearSolver, m: &Matrix) -> Result<(), StepFailure> {
        self.stats.factorizations += 1;
        let res = solver.factor(m);
        if solver.last_factor_was_symbolic() {
            self.stats.symbolic_factorizations += 1;
        }
        res.map_err(|column| factor_failure(column, &[m]))
    }

    /// Counted factorisation of `a + beta·b` (see [`LinearSolver::factor_combination`]: banded
    /// matrices skip the scratch matrix); a zero pivot is a recoverable failure.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let (mut a, mut b, mut s) = (sys.new_matrix(), sys.new_matrix(), sys.new_matrix());
    /// a.add(0, 0, 1.0);
    /// b.add(0, 0, 1.0);
    /// let mut lu = sys.new_linear_solver();
    /// sys.factor_combination(&mut lu, &a, 3.0, &b, &mut s).unwrap(); // 1 + 3·1
    /// let mut x = [8.0];
    /// sys.solve(&lu, &mut x);
    /// assert_eq!(x, [2.0]);
    /// ```
    pub fn factor_combination(
        &mut self,
        solver: &mut LinearSolver,
        a: &Matrix,
        beta: f64,
        b: &Matrix,
        scratch: &mut Matrix,
    ) -> Result<(), StepFailure> {
        self.stats.factorizations += 1;
        let res = solver.factor_combination(a, beta, b, scratch);
        if solver.last_factor_was_symbolic() {
            self.stats.symbolic_factorizations += 1;
        }
        res.map_err(|column| factor_failure(column, &[a, b]))
    }

    /// Counted in-place solve with the last factorisation.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let (mut j, mut lu) = (sys.new_matrix(), sys.new_linear_solver());
    /// j.add(0, 0, 4.0);
    /// sys.factor(&mut lu, &j).unwrap();
    /// let mut b = [2.0];
    /// sys.solve(&lu, &mut b);
    /// assert_eq!((b[0], sys.stats.linear_solves), (0.5, 1));
    /// ```
    pub fn solve(&mut self, solver: &LinearSolver, b: &mut [f64]) {
        self.stats.linear_solves += 1;
        let before = solver.krylov_counters();
        solver.solve_in_place(b);
        self.count_krylov(solver, before);
    }

    fn count_krylov(&mut self, solver: &LinearSolver, before: crate::linalg::KrylovCounters) {
        let after = solver.krylov_counters();
        self.stats.krylov_iterations += after.iterations - before.iterations;
        self.stats.krylov_failures += after.failures - before.failures;
    }

    /// Counted in-place solve that also maps every solution component (see
    /// [`LinearSolver::solve_in_place_map`]: the banded tridiagonal solver fuses the map into
    /// its backward sweep), with the caller's Newton tolerance for an iterative solver.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// use integrators::linalg::SolutionMap;
    /// struct Plus(f64);
    /// impl SolutionMap for Plus { fn map(&mut self, _: usize, x: f64) -> f64 { x + self.0 } }
    /// let (mut j, mut lu) = (sys.new_matrix(), sys.new_linear_solver());
    /// j.add(0, 0, 4.0);
    /// sys.factor(&mut lu, &j).unwrap();
    /// let mut b = [2.0];
    /// sys.solve_map(&lu, &mut b, None, Plus(1.0)); // the solution 0.5, stored plus 1
    /// assert_eq!(b, [1.5]);
    /// ```
    pub fn solve_map<M: crate::linalg::SolutionMap + Send>(
        &mut self,
        solver: &LinearSolver,
        b: &mut [f64],
        tol: Option<&crate::linalg::LinearTolerance<'_>>,
        map: M,
    ) -> M {
        self.stats.linear_solves += 1;
        let before = solver.krylov_counters();
        let map = solver.solve_in_place_map(b, tol, map);
        self.count_krylov(solver, before);
        map
    }

    /// Error weights `w_i = 1/(rtol·|y_i| + atol_i)` — or, with an error map, the weights of
    /// the cell-level quantities (`1/(rtol·|y_i − y_p| + atol_i)` for a difference row, see
    /// [`crate::error_map`]) — zero for algebraic components when `opts.suppress_algebraic`.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// let mut w = [0.0];
    /// sys.error_weights(&[0.0], &mut w);
    /// assert!((w[0] - 1e8).abs() < 1e-3); // 1/(rtol·|y| + atol) at y = 0
    /// ```
    pub fn error_weights(&self, y: &[f64], w: &mut [f64]) {
        self.newton_weights(y, w);
        if self.opts.suppress_algebraic {
            for (wi, &alg) in w.iter_mut().zip(&self.cache.algebraic) {
                if alg {
                    *wi = 0.0;
                }
            }
        }
    }

    /// Weighted RMS norm `sqrt(mean((v_i·w_i)²))`. Finite whenever every `v_i·w_i` is: when
    /// the squares overflow (terms beyond about 1e154, as the initial rates of a drag far
    /// below the stiffness), the sum is taken over the terms divided by the largest.
    ///
    /// ```
    /// use integrators::System;
    /// assert!((System::wrms(&[3.0, 4.0], &[1.0, 1.0]) - 12.5f64.sqrt()).abs() < 1e-15);
    /// assert!((System::wrms(&[3e200, 4e200], &[1.0, 1.0]) / (12.5f64.sqrt() * 1e200) - 1.0).abs() < 1e-15);
    /// assert!(System::wrms(&[1.0, f64::NAN], &[1.0, 1.0]).is_nan());
    /// ```
    pub fn wrms(v: &[f64], w: &[f64]) -> f64 {
        assert_eq!(v.len(), w.len(), "wrms: length mismatch");
        if v.is_empty() {
            return 0.0;
        }
        let s: f64 = v.iter().zip(w).map(|(a, b)| (a * b) * (a * b)).sum();
        let n = v.len() as f64;
        if s.is_finite() || v.iter().zip(w).any(|(a, b)| !(a * b).is_finite()) {
            return (s / n).sqrt();
        }
        let big = v
            .iter()
            .zip(w)
            .fold(0.0f64, |m, (a, b)| m.max((a * b).abs()));
        let s: f64 = v
            .iter()
            .zip(w)
            .map(|(a, b)| (a * b / big) * (a * b / big))
            .sum();
        big * (s / n).sqrt()
    }

    /// Index of the component with the largest `|v_i·w_i|` (for error messages).
    ///
    /// ```
    /// use integrators::System;
    /// assert_eq!(System::worst_component(&[1.0, -5.0, 2.0], &[1.0; 3]), Some(1));
    /// assert_eq!(System::worst_component(&[1.0, f64::NAN], &[1.0; 2]), Some(1)); // a NaN first
    /// ```
    pub fn worst_component(v: &[f64], w: &[f64]) -> Option<usize> {
        assert_eq!(v.len(), w.len(), "worst_component: length mismatch");
        if let Some(i) = v.iter().zip(w).position(|(a, b)| (a * b).is_nan()) {
            return Some(i);
        }
        let mut best: Option<(usize, f64)> = None;
        for (i, (a, b)) in v.iter().zip(w).enumerate() {
            let x = (a * b).abs();
            if best.is_none_or(|(_, bx)| x > bx) {
                best = Some((i, x));
            }
        }
        best.map(|(i, _)| i)
    }

    /// An output's `ẏ` solved from its state, for a problem without algebraic components whose
    /// outputs read rates ([`Problem::outputs_read_rates`]): simplified Newton on
    /// `F(t, y, ẏ) = 0` from the given (interpolated) `ẏ`, converged as
    /// [`consistent_init`](Self::consistent_init) is (weighted RMS update ≤ 10⁻³), with
    /// `∂F/∂ẏ` factorised once and kept in `lu` across outputs. That matrix changes with the
    /// state only slowly, so a residual and a solve per iteration, about three, replace a
    /// Jacobian and a factorisation per output (3.7 ms against 10 ms per output at 10⁵
    /// cells); it is
    /// refreshed when missing, of another size, or slow to converge (rate above ½). `Err(())`,
    /// with `yp` as given, when even a fresh matrix does not converge.
    ///
    /// A rate is weighted by `rtol·|ẏᵢ| + atolᵢ/h`, with `h` the last step (> 0; otherwise
    /// `atolᵢ`): the absolute part is the rate that moves the component by its `atol` over a
    /// step, so the test reads the same on any time scale. With `atolᵢ` alone (a position's
    /// tolerance as a rate's), a boundary at rest on times of 2⁻³³² was held to a rate of
    /// 10⁻¹⁰ against a rounding of its solved rate near 10⁸⁴, and the solve fell back to the
    /// interpolated `ẏ` (a viscous line's pressure then erred 12 times more than at unit time).
    pub(crate) fn rates_from_state(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &mut [f64],
        lu: &mut Option<(usize, LinearSolver)>,
        h: f64,
    ) -> Result<(), ()> {
        let n = self.dim();
        let (mut r, mut w, mut start) = (self.take_vec(), self.take_vec(), self.take_vec());
        let per_step = if h > 0.0 && h.is_finite() {
            1.0 / h
        } else {
            1.0
        };
        for ((wi, &u), &a) in w.iter_mut().zip(yp.iter()).zip(&self.cache.atol) {
            *wi = 1.0 / (self.opts.rtol * u.abs() + a * per_step);
        }
        start.copy_from_slice(yp);
        let outcome = self.rates_iterations(t, y, yp, lu, n, &mut r, &w, &start);
        if outcome.is_err() {
            yp.copy_from_slice(&start);
        }
        self.give_vec(r);
        self.give_vec(w);
        self.give_vec(start);
        outcome
    }

    /// [`rates_from_state`](Self::rates_from_state) with its scratch.
    #[allow(clippy::too_many_arguments)]
    fn rates_iterations(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &mut [f64],
        lu: &mut Option<(usize, LinearSolver)>,
        n: usize,
        r: &mut [f64],
        w: &[f64],
        start: &[f64],
    ) -> Result<(), ()> {
        let mut fresh = false;
        loop {
            if lu.as_ref().is_none_or(|(m, _)| *m != n) {
                self.residual(t, y, yp, r).map_err(|_| ())?;
                let (mut jac, mut solver) = (self.take_matrix(), self.take_solver());
                let algebraic = vec![false; n];
                self.stats.jacobian_evals += 1;
                let built = jacobian::assemble(
                    self,
                    t,
                    y,
                    yp,
                    Columns::Init {
                        algebraic: &algebraic,
                    },
                    Some(r),
                    &mut jac,
                )
                .and_then(|_| self.factor(&mut solver, &jac));
                self.give_matrix(jac);
                if built.is_err() {
                    self.give_solver(solver);
                    return Err(());
                }
                *lu = Some((n, solver));
                fresh = true;
            }
            let solver = &lu.as_ref().expect("built above").1;
            let mut last = f64::INFINITY;
            for _ in 0..4 {
                self.residual(t, y, yp, r).map_err(|_| ())?;
                self.solve(solver, r);
                let norm = Self::wrms(r, w);
                for (v, d) in yp.iter_mut().zip(r.iter()) {
                    *v -= d;
                }
                if norm <= INIT_TOL {
                    return Ok(());
                }
                if !norm.is_finite() || (last.is_finite() && norm > 0.5 * last) {
                    break;
                }
                last = norm;
            }
            if fresh {
                return Err(());
            }
            // a stale matrix that did not converge: a fresh one, from the interpolated ẏ
            yp.copy_from_slice(start);
            *lu = None;
        }
    }

    /// Consistent initialisation at `t`: given `y`, solves `F(t, y, ẏ) = 0` for `ẏ` of the
    /// differential components and for the algebraic components of `y` (IDA's YA_YDP), by
    /// damped Newton with the pattern's factorisation. `yp` holds the initial guess on entry.
    ///
    /// ```
    /// # use integrators::system::SystemCache;
    /// # use integrators::{Options, Problem, ResidualError, Stats, System};
    /// # /// ẏ = −y in residual form, one unknown.
    /// # struct Decay;
    /// # impl Problem for Decay {
    /// #     fn dim(&self) -> usize { 1 }
    /// #     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    /// #         r[0] = yp[0] + y[0];
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let (mut p, opts, mut stats) = (Decay, Options { rtol: 1e-6, atol: 1e-8, ..Default::default() }, Stats::default());
    /// # let mut cache = SystemCache::default();
    /// # cache.rebuild(&p, &opts).unwrap();
    /// let mut sys = System::new(&mut p, &opts, &mut stats, &mut cache);
    /// // ẏ from F(t, y, ẏ) = 0 at y = 2: ẏ = −2
    /// let (mut y, mut yp) = ([2.0], [0.0]);
    /// sys.consistent_init(0.0, &mut y, &mut yp).unwrap();
    /// assert!((yp[0] + 2.0).abs() < 1e-10);
    /// ```
    pub fn consistent_init(
        &mut self,
        t: f64,
        y: &mut [f64],
        yp: &mut [f64],
    ) -> Result<(), SolverError> {
        let n = self.dim();
        assert!(
            y.len() == n && yp.len() == n,
            "consistent_init: dimension mismatch"
        );
        if n == 0 {
            return Ok(());
        }
        let mut jac = self.take_matrix();
        let mut lu = self.take_solver();
        let mut vecs: [Vec<f64>; 8] = std::array::from_fn(|_| self.take_vec());
        let res = self.consistent_init_with(t, y, yp, &mut jac, &mut lu, &mut vecs);
        self.give_matrix(jac);
        self.give_solver(lu);
        for v in vecs {
            self.give_vec(v);
        }
        res
    }

    /// [`consistent_init`](Self::consistent_init) with its scratch.
    fn consistent_init_with(
        &mut self,
        t: f64,
        y: &mut [f64],
        yp: &mut [f64],
        jac: &mut Matrix,
        lu: &mut LinearSolver,
        vecs: &mut [Vec<f64>; 8],
    ) -> Result<(), SolverError> {
        let [r, delta, w, w_new, y_new, yp_new, r_new, d_new] = vecs;
        let algebraic = self.cache.algebraic.clone();
        let init_err = |why: String, component: Option<usize>| {
            SolverError::new(ErrorKind::Initialisation(why), t, component)
        };
        let to_error = |f: StepFailure, what: &str| match f {
            StepFailure::Recoverable { reason, component } => {
                init_err(format!("{what}: {reason}"), component)
            }
            StepFailure::Fatal(e) => e,
        };
        let rtol = self.opts.rtol;
        let weights = |y: &[f64], yp: &[f64], atol: &[f64], w: &mut [f64]| {
            for i in 0..w.len() {
                let u = if algebraic[i] { y[i] } else { yp[i] };
                w[i] = 1.0 / (rtol * u.abs() + atol[i]);
            }
        };
        self.residual(t, y, yp, r)
            .map_err(|f| to_error(f, "residual at the initial state"))?;
        let mut last_norm = f64::INFINITY;
        for _ in 0..INIT_MAX_ITERS {
            self.stats.jacobian_evals += 1;
            jacobian::assemble(
                self,
                t,
                y,
                yp,
                Columns::Init {
                    algebraic: &algebraic,
                },
                Some(&r[..]),
                jac,
            )
            .map_err(|f| to_error(f, "Jacobian at the initial state"))?;
            self.factor(lu, jac).map_err(|f| {
                let what = match &f {
                    StepFailure::Recoverable {
                        reason: RecoverableCause::NonFiniteMatrix { .. },
                        ..
                    } => "∂F/∂(ẏ differential, y algebraic) overflowed",
                    _ => {
                        "∂F/∂(ẏ differential, y algebraic) is singular (index > 1, or a \
                         component flagged differential whose ẏ does not appear in F)"
                    }
                };
                to_error(f, what)
            })?;
            delta.copy_from_slice(r);
            self.solve(lu, delta);
            weights(y, yp, &self.cache.atol, w);
            let dnorm = Self::wrms(delta, w);
            if !dnorm.is_finite() {
                return Err(init_err(
                    "non-finite Newton update".into(),
                    Self::worst_component(delta, w),
                ));
            }
            if dnorm <= INIT_TOL {
                apply(&algebraic, y, yp, delta, 1.0);
                return Ok(());
            }
            // damped step: merit = ‖M⁻¹·F‖ with the current factorisation
            let mut lambda = 1.0;
            loop {
                y_new.copy_from_slice(y);
                yp_new.copy_from_slice(yp);
                apply(&algebraic, y_new, yp_new, delta, lambda);
                let accepted = match self.residual(t, y_new, yp_new, r_new) {
                    Ok(()) => {
                        d_new.copy_from_slice(r_new);
                        self.solve(lu, d_new);
                        // convergence is judged with the trial point's weights, descent with the
                        // current iterate's (those of `dnorm`)
                        let nnorm = Self::wrms(d_new, w);
                        weights(y_new, yp_new, &self.cache.atol, w_new);
                        if Self::wrms(d_new, w_new) <= INIT_TOL {
                            y.copy_from_slice(y_new);
                            yp.copy_from_slice(yp_new);
                            apply(&algebraic, y, yp, d_new, 1.0);
                            return Ok(());
                        }
                        nnorm.is_finite() && nnorm <= (1.0 - 1e-4 * lambda) * dnorm
                    }
                    Err(StepFailure::Recoverable { .. }) => false,
                    Err(StepFailure::Fatal(e)) => return Err(e),
                };
                if accepted {
                    break;
                }
                lambda *= 0.5;
                if lambda < INIT_MIN_DAMPING {
                    if dnorm <= 1.0 {
                        // No step along the update lowers it, yet it is already within the
                        // tolerance: the residual is at its rounding floor (a viscous line's ẏ
                        // near rest at rtol 1e-10 stopped at 1.9e-3 against INIT_TOL).
                        return Ok(());
                    }
                    return Err(init_err(
                        format!(
                            "damped Newton could not reduce the residual (weighted update \
                             norm {dnorm:.3e})"
                        ),
                        worst_abs(r),
                    ));
                }
            }
            y.copy_from_slice(y_new);
            yp.copy_from_slice(yp_new);
            std::mem::swap(r, r_new);
            last_norm = dnorm;
        }
        Err(init_err(
            format!(
                "Newton did not converge in {INIT_MAX_ITERS} iterations (last weighted update \
                 norm {last_norm:.3e})"
            ),
            worst_abs(r),
        ))
    }
}

/// Newton iterations allowed in [`System::consistent_init`].
const INIT_MAX_ITERS: usize = 20;
/// Convergence: weighted RMS norm of the Newton update of the unknowns.
const INIT_TOL: f64 = 1e-3;
/// Smallest damping factor of the line search.
const INIT_MIN_DAMPING: f64 = 1.0 / 1024.0;

/// `u -= λ·δ` where `u_i` is `y_i` (algebraic) or `ẏ_i` (differential).
fn apply(algebraic: &[bool], y: &mut [f64], yp: &mut [f64], delta: &[f64], lambda: f64) {
    for i in 0..delta.len() {
        if algebraic[i] {
            y[i] -= lambda * delta[i];
        } else {
            yp[i] -= lambda * delta[i];
        }
    }
}

/// Component with the largest `|r_i|` (NaN first).
fn worst_abs(r: &[f64]) -> Option<usize> {
    let ones = vec![1.0; r.len()];
    System::worst_component(r, &ones)
}

#[cfg(test)]
mod tests;

/// The recoverable failure of a factorisation that stopped at `column`: a non-finite entry of
/// one of the factorised `matrices` if there is one (the problem's derivatives overflowed, and
/// its row names the equation), a zero pivot otherwise.
fn factor_failure(column: usize, matrices: &[&Matrix]) -> StepFailure {
    match matrices.iter().find_map(|m| m.first_non_finite()) {
        Some((row, column, value)) => StepFailure::Recoverable {
            reason: RecoverableCause::NonFiniteMatrix { row, column, value },
            component: Some(row),
        },
        None => StepFailure::Recoverable {
            reason: RecoverableCause::SingularMatrix { column },
            component: Some(column),
        },
    }
}
