//! [`SolveSettings`]: the one integrator setting every run takes — line, ring, proliferating
//! line, sheet, shear column and registered modes alike — and the scenario's validated
//! `[solver]` table. It turns into the integrators' [`Options`] with
//! [`SolveSettings::options`]; the scenario echo and `summary.json` serialise it by name.
//!
//! Tolerances follow the cell-unit accuracy contract (docs/model.md §8.1): `rtol` bounds the
//! relative error of every cell's stretch (and pressure), `atol` is in cell units (a model
//! scales it by its local reference cell size).

use integrators::{
    ErrorNorm, LinearSolverChoice, MethodChoice, MethodKind, Options, OptionsError, Parallelism,
};
use serde::Serialize;

/// Method, tolerances, error norm, linear solver and threads of a run.
///
/// ```
/// use celltissue::SolveSettings;
/// let s = SolveSettings { rtol: 1e-8, atol: 1e-10, ..Default::default() };
/// let o = s.options().unwrap();
/// assert_eq!((o.rtol, o.atol, o.norm), (1e-8, 1e-10, integrators::ErrorNorm::Max));
/// // a bad value is named
/// let bad = SolveSettings { threads: 3, ..s };
/// assert!(bad.options().unwrap_err().to_string().contains("3"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolveSettings {
    /// Method (built-in or registered); serialised by name.
    #[serde(serialize_with = "method_name")]
    pub method: MethodChoice,
    /// Relative tolerance, in (0, 1).
    pub rtol: f64,
    /// Absolute tolerance in cell units, > 0.
    pub atol: f64,
    /// Error norm of the local error and Newton tests (default [`ErrorNorm::Max`]: a line's
    /// dynamics concentrate at its ends, where the RMS norm would dilute the local error by
    /// `√N`; see [`ErrorNorm`]).
    #[serde(serialize_with = "norm_name")]
    pub norm: ErrorNorm,
    /// Linear solver of the Newton iterations (the iterative one serves sheet models only).
    #[serde(serialize_with = "linear_solver_fields")]
    pub linear_solver: LinearSolverChoice,
    /// Threads the solve may use, 1 or 2 (default 1; anything else fails the run with a named
    /// error, see [`Parallelism::from_threads`]). With 2, lines of at least
    /// [`crate::line::array::PAR_MIN_CELLS`] cells split their residual sweep and the
    /// integrator's vector passes and tridiagonal solve in two halves.
    pub threads: usize,
    /// BDF only: steps after which the Newton matrices are refreshed even though Newton
    /// converges (≥ 1; default 50, [`integrators::BdfOptions::max_jacobian_age`]). Left out
    /// of the echo at its default.
    #[serde(skip_serializing_if = "is_default_age")]
    pub jacobian_age: usize,
    /// BDF only: whether the first Newton iteration after a change of `α` is tested with at
    /// least the rate that change implies (default `false`;
    /// [`integrators::BdfOptions::newton_alpha_bound`]). Left out of the echo when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub newton_alpha_bound: bool,
    /// BDF only: the highest order it may select, 1 to 5 (default 5,
    /// [`integrators::BdfOptions::max_order`]). Orders 3–5 damp a cell-to-cell zigzag least:
    /// where the model itself grows one (a ring of Maxwell cells whose active stress softens
    /// them), they put the most of their error into it (docs/model.md §8.1). Left out of the
    /// echo at its default.
    #[serde(skip_serializing_if = "is_default_order")]
    pub max_order: usize,
    /// Most steps a solve may take; it stops at the next with
    /// [`integrators::ErrorKind::TooManySteps`], keeping what it computed (default 10⁶,
    /// [`integrators::Options::max_steps`]). Left out of the echo at its default.
    #[serde(skip_serializing_if = "is_default_max_steps")]
    pub max_steps: usize,
    /// Whether steps end at every output time instead of interpolating there (default `None`:
    /// for every method but BDF, whose dense output its error test controls;
    /// [`integrators::Options::land_on_outputs`]). Left out of the echo when not set.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub land_on_outputs: Option<bool>,
    /// Whether outputs that read rates (a Kelvin–Voigt cell's stress and pressure) take the
    /// interpolated `ẏ` instead of one solved from the output's state (default `false`;
    /// [`integrators::Options::interpolate_rates`]). Left out of the echo when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interpolate_rates: bool,
    /// Whether each run is repeated at a tenfold tighter `rtol` and `atol` and compared with
    /// it, cell by cell at the profile times and in the stretch extremes at the series times
    /// (default `false`; the comparison is the record's
    /// [`crate::observe::RunRecord::accuracy_check`], see [`crate::scenario::accuracy_check`]).
    /// Left out of the echo when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub accuracy_check: bool,
}

impl Default for SolveSettings {
    /// BDF, `rtol = 1e-6`, `atol = 1e-8`, max norm, direct linear solver, one thread: the
    /// scenario's `[solver]` defaults.
    fn default() -> Self {
        Self {
            method: MethodKind::Bdf.into(),
            rtol: 1e-6,
            atol: 1e-8,
            norm: ErrorNorm::Max,
            linear_solver: LinearSolverChoice::Direct,
            threads: 1,
            jacobian_age: integrators::BdfOptions::default().max_jacobian_age,
            newton_alpha_bound: false,
            max_order: integrators::BdfOptions::default().max_order,
            max_steps: Options::default().max_steps,
            land_on_outputs: None,
            interpolate_rates: false,
            accuracy_check: false,
        }
    }
}

impl SolveSettings {
    /// The integrators' options for these settings (their other fields at their defaults),
    /// checked: a tolerance or thread count out of range is an error naming it.
    ///
    /// ```
    /// use celltissue::SolveSettings;
    /// let o = SolveSettings { rtol: 1e-8, ..Default::default() }.options()?;
    /// assert_eq!(o.rtol, 1e-8);
    /// assert!(SolveSettings { rtol: 0.0, ..Default::default() }.options().is_err());
    /// # Ok::<(), integrators::OptionsError>(())
    /// ```
    pub fn options(&self) -> Result<Options, OptionsError> {
        let opts = Options {
            rtol: self.rtol,
            atol: self.atol,
            norm: self.norm,
            linear_solver: self.linear_solver,
            parallel: Parallelism::from_threads(self.threads)?,
            land_on_outputs: self.land_on_outputs,
            interpolate_rates: self.interpolate_rates,
            max_steps: self.max_steps,
            bdf: integrators::BdfOptions {
                max_jacobian_age: self.jacobian_age,
                newton_alpha_bound: self.newton_alpha_bound,
                max_order: self.max_order,
                ..Default::default()
            },
            ..Options::default()
        };
        opts.validate()?;
        Ok(opts)
    }
}

fn is_default_max_steps(m: &usize) -> bool {
    *m == Options::default().max_steps
}

fn is_default_order(q: &usize) -> bool {
    *q == integrators::BdfOptions::default().max_order
}

fn is_default_age(a: &usize) -> bool {
    *a == integrators::BdfOptions::default().max_jacobian_age
}

fn linear_solver_fields<S: serde::Serializer>(
    c: &LinearSolverChoice,
    s: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    match c {
        LinearSolverChoice::Direct => s.serialize_str("direct"),
        LinearSolverChoice::Iterative(it) => {
            let mut m = s.serialize_map(Some(4))?;
            m.serialize_entry("kind", "iterative")?;
            m.serialize_entry("krylov_rtol", &it.rtol)?;
            m.serialize_entry("krylov_max_iters", &it.max_iters)?;
            m.serialize_entry("newton_factor", &it.newton_factor)?;
            m.end()
        }
    }
}

fn norm_name<S: serde::Serializer>(n: &ErrorNorm, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(match n {
        ErrorNorm::Rms => "rms",
        ErrorNorm::Max => "max",
    })
}

fn method_name<S: serde::Serializer>(m: &MethodChoice, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(m.name())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serialises_by_name_as_the_scenario_echo_shows_it() {
        let s = SolveSettings {
            linear_solver: LinearSolverChoice::Iterative(integrators::IterativeSettings {
                rtol: 1e-3,
                max_iters: 50,
                newton_factor: 0.1,
            }),
            ..Default::default()
        };
        let v = serde_json::to_value(s).unwrap();
        assert_eq!(v["method"], "bdf");
        assert_eq!(v["norm"], "max");
        assert_eq!(v["linear_solver"]["kind"], "iterative");
        assert_eq!(v["linear_solver"]["krylov_max_iters"], 50);
        assert_eq!(v["threads"], 1);
    }

    #[test]
    fn options_reject_out_of_range_values_by_name() {
        for (s, key) in [
            (
                SolveSettings {
                    rtol: 0.0,
                    ..Default::default()
                },
                "rtol",
            ),
            (
                SolveSettings {
                    atol: f64::NAN,
                    ..Default::default()
                },
                "atol",
            ),
        ] {
            let e = s.options().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
        assert!(SolveSettings {
            threads: 0,
            ..Default::default()
        }
        .options()
        .is_err());
    }
}
