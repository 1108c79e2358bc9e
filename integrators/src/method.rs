//! The [`Method`] trait every time-stepping scheme implements; [`MethodKind`], which picks a
//! built-in one by value or by name; and [`MethodChoice`], which also covers methods of the
//! caller's own [`register`]ed by name.

use crate::error::SolverError;
use crate::system::System;

/// One time-stepping scheme. A method owns its step-size/order state and history, not the
/// problem; the driver ([`crate::Solver`]) owns the loop, output, and events, and restarts the
/// method with [`start`](Method::start) after every event (possibly with a new dimension).
///
/// ```
/// use integrators::{methods, MethodKind};
/// // the built-in methods are `Method` objects; a solver drives one through start/step/interpolate
/// let radau = methods::build(MethodKind::Radau);
/// assert_eq!(radau.name(), "radau");
/// ```
pub trait Method {
    /// Short name (`"bdf"`, `"esdirk"`, `"radau"`, `"dopri"`).
    fn name(&self) -> &'static str;

    /// (Re)starts from a consistent state `(t, y, ẏ)`. `h` is a step-size hint (`None`: the method
    /// estimates one). Called at the start and after every event/resize; the dimension may differ
    /// from the previous call (rebuild workspaces from `sys`).
    fn start(
        &mut self,
        sys: &mut System<'_>,
        t: f64,
        y: &[f64],
        yp: &[f64],
        h: Option<f64>,
    ) -> Result<(), SolverError>;

    /// Continues across a resizing event at `t` (inside the last accepted step) that the
    /// problem maps ([`crate::Problem::map_history`]) instead of restarting from a consistent
    /// initialisation: `y`, `yp` are the state after the event and its mapped derivative, and
    /// the method keeps what it can of its state before the event. BDF goes on from them at
    /// order 1 with its step size and its Newton matrices (mapped with
    /// [`crate::Problem::map_jacobian`] through `sys.problem`), its first step checked by step
    /// doubling: a predictor built from the history before the event misses the kink a
    /// division makes. Returns `Ok(false)` when it cannot (no step taken yet); the driver then
    /// calls [`start`](Method::start). Default: `Ok(false)`.
    fn resume(
        &mut self,
        _sys: &mut System<'_>,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
    ) -> Result<bool, SolverError> {
        Ok(false)
    }

    /// Advances by one accepted step, never beyond `t_stop` (landing on it exactly when it is
    /// reached), and returns how many accepted steps that took: 1, or more for a method that
    /// takes internal sub-steps (BDF's restart takes two half steps). The driver counts steps
    /// from it (`Stats::steps`, `Options::max_steps`); a method does not touch `stats.steps`.
    /// The method reports each rejected attempt with [`System::reject_step`] (which counts it
    /// in `Stats::rejected_steps` and passes it to the solve's observer). On error the method's
    /// state is the last accepted one.
    fn step(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<usize, SolverError>;

    /// Time of the last accepted step.
    fn t(&self) -> f64;
    /// Time at the start of the last accepted step.
    fn t_prev(&self) -> f64;
    /// State at [`t`](Method::t).
    fn y(&self) -> &[f64];
    /// Derivative at [`t`](Method::t).
    fn yp(&self) -> &[f64];
    /// Step size to try next.
    fn h_next(&self) -> f64;
    /// Dense output: state and derivative at any `t` in `[t_prev, t]`.
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]);
    /// Whether the local error test also bounds [`interpolate`](Method::interpolate)'s error
    /// inside a step (default `false`). BDF's interpolant is the polynomial its predictor
    /// extrapolates and its error estimate measures, so it is; a one-step method's continuous
    /// extension is not checked, and on a stiff problem near its quasi-static limit, where a
    /// stiffly accurate step's end is exact to leading order and the steps grow long, it can
    /// err by far more than the tolerance between step ends. Unless
    /// [`Options::land_on_outputs`](crate::Options::land_on_outputs) says otherwise, a method
    /// returning `false` ends a step at every output time instead of interpolating.
    ///
    /// ```
    /// use integrators::methods::{bdf::Bdf, radau::Radau5};
    /// use integrators::Method;
    /// assert!(Bdf::new().dense_output_controlled());
    /// assert!(!Radau5::new().dense_output_controlled());
    /// ```
    fn dense_output_controlled(&self) -> bool {
        false
    }

    /// Whether an explicit method's steps are held at its stability limit on a stiff problem
    /// (see [`StabilityLimit`]); `None` (the default, and always for an implicit method)
    /// otherwise. The driver warns once per solve when it first is, and stops with
    /// [`ErrorKind::Stiff`](crate::ErrorKind::Stiff) when the rest of the span at the current
    /// step would take more than [`Options::max_steps`](crate::Options::max_steps).
    ///
    /// ```
    /// use integrators::methods::{bdf::Bdf, dopri::Dopri5};
    /// use integrators::Method;
    /// assert!(Bdf::new().stability_limit().is_none());
    /// assert!(Dopri5::new().stability_limit().is_none()); // not before its test has failed
    /// ```
    fn stability_limit(&self) -> Option<StabilityLimit> {
        None
    }
}

/// Where an explicit method found its steps held at its stability limit: since `since`, its
/// stiffness test has failed repeatedly (DOPRI5: `h·ρ > 3.25` at 15 tests running, `ρ` the
/// problem's fastest rate estimated from two stages). Steps there are set by stability, not
/// accuracy; an implicit method would take far fewer.
///
/// ```
/// use integrators::method::StabilityLimit;
/// let s = StabilityLimit { since: 2.0, h_rho: 3.3, component: Some(7) };
/// assert!(s.h_rho > 3.25);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityLimit {
    /// End of the step whose test made the count of failed tests reach the limit.
    pub since: f64,
    /// `h·ρ` at the last test.
    pub h_rho: f64,
    /// The component whose rate changed most between the two stages (the fastest), if known.
    pub component: Option<usize>,
}

/// The available methods, selectable in one line of code or by name.
///
/// ```
/// use integrators::MethodKind;
/// let m: MethodKind = "radau".parse().unwrap();
/// assert_eq!(m, MethodKind::Radau);
/// assert!("euler".parse::<MethodKind>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MethodKind {
    /// Variable-order (1–5), variable-step BDF in residual form (ode15s / IDA family).
    Bdf,
    /// L-stable ESDIRK (TR-BDF2 with embedded error estimate).
    Esdirk,
    /// Radau IIA, order 5.
    Radau,
    /// Dormand–Prince 5(4), explicit (non-stiff; needs `∂F/∂ẏ` nonsingular).
    Dopri,
}

impl MethodKind {
    /// All methods, in a fixed order.
    pub const ALL: [MethodKind; 4] = [
        MethodKind::Bdf,
        MethodKind::Esdirk,
        MethodKind::Radau,
        MethodKind::Dopri,
    ];

    /// The name accepted by [`std::str::FromStr`].
    ///
    /// ```
    /// use integrators::MethodKind;
    /// assert_eq!(MethodKind::Radau.name().parse::<MethodKind>().unwrap(), MethodKind::Radau);
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Bdf => "bdf",
            MethodKind::Esdirk => "esdirk",
            MethodKind::Radau => "radau",
            MethodKind::Dopri => "dopri",
        }
    }

    /// Whether the method is implicit (handles stiffness and algebraic components).
    ///
    /// ```
    /// use integrators::MethodKind;
    /// assert!(MethodKind::Bdf.is_stiff() && !MethodKind::Dopri.is_stiff());
    /// ```
    pub fn is_stiff(self) -> bool {
        !matches!(self, MethodKind::Dopri)
    }

    /// A fresh method object.
    ///
    /// ```
    /// use integrators::MethodKind;
    /// assert_eq!(MethodKind::Esdirk.build().name(), "esdirk"); // a fresh method object
    /// ```
    pub fn build(self) -> Box<dyn Method> {
        crate::methods::build(self)
    }
}

impl std::str::FromStr for MethodKind {
    type Err = MethodError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "bdf" => Ok(MethodKind::Bdf),
            "esdirk" | "trbdf2" | "tr-bdf2" => Ok(MethodKind::Esdirk),
            "radau" | "radau5" | "radauiia" => Ok(MethodKind::Radau),
            "dopri" | "dopri5" | "rk45" => Ok(MethodKind::Dopri),
            other => Err(MethodError::Unknown {
                name: other.to_string(),
                valid: "bdf, esdirk, radau, dopri".into(),
            }),
        }
    }
}

impl std::fmt::Display for MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A method of the caller's own, selectable by name once [`register`]ed: its name and a
/// constructor of fresh method objects.
///
/// Compared, hashed and printed by name (names are unique in the registry).
///
/// ```
/// use integrators::{CustomMethod, MethodKind};
/// let m = CustomMethod { name: "stiff_bdf", build: || integrators::methods::build(MethodKind::Bdf), stiff: true };
/// assert_eq!(format!("{m:?}"), "CustomMethod(\"stiff_bdf\")"); // printed and compared by name
/// assert_eq!((m.build)().name(), "bdf");
/// ```
#[derive(Clone, Copy)]
pub struct CustomMethod {
    /// The name scenarios and [`std::str::FromStr`] use (not a built-in name or alias).
    pub name: &'static str,
    /// A fresh method object.
    pub build: fn() -> Box<dyn Method>,
    /// Whether it is implicit (handles stiffness and algebraic components).
    pub stiff: bool,
}

impl PartialEq for CustomMethod {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}
impl Eq for CustomMethod {}
impl std::hash::Hash for CustomMethod {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.name.hash(state)
    }
}
impl std::fmt::Debug for CustomMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("CustomMethod").field(&self.name).finish()
    }
}

/// A method by value: a built-in [`MethodKind`] or a [`CustomMethod`]. Accepted wherever a
/// method is chosen ([`crate::Solver::new`] takes `impl Into<MethodChoice>`, so a
/// [`MethodKind`] works as before), parsed from the built-in names and the registered ones.
///
/// ```
/// use integrators::method::{register, CustomMethod, MethodChoice};
/// use integrators::MethodKind;
/// // a user method: here BDF under another name (a real one implements `Method` itself)
/// fn build() -> Box<dyn integrators::Method> { MethodKind::Bdf.build() }
/// register(CustomMethod { name: "my_bdf", build, stiff: true })?;
/// let m: MethodChoice = "my_bdf".parse()?;
/// assert_eq!(m.name(), "my_bdf");
/// assert_eq!("radau".parse::<MethodChoice>()?, MethodKind::Radau);
/// assert!("euler".parse::<MethodChoice>().unwrap_err().to_string().contains("my_bdf"));
/// # Ok::<(), integrators::method::MethodError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MethodChoice {
    /// A built-in method.
    Builtin(MethodKind),
    /// A registered method of the caller's own.
    Custom(CustomMethod),
}

impl Default for MethodChoice {
    /// BDF.
    fn default() -> Self {
        MethodChoice::Builtin(MethodKind::Bdf)
    }
}

impl From<MethodKind> for MethodChoice {
    fn from(kind: MethodKind) -> Self {
        MethodChoice::Builtin(kind)
    }
}

impl From<CustomMethod> for MethodChoice {
    fn from(m: CustomMethod) -> Self {
        MethodChoice::Custom(m)
    }
}

impl PartialEq<MethodKind> for MethodChoice {
    fn eq(&self, other: &MethodKind) -> bool {
        *self == MethodChoice::Builtin(*other)
    }
}

impl MethodChoice {
    /// The name [`std::str::FromStr`] accepts.
    ///
    /// ```
    /// use integrators::{MethodChoice, MethodKind};
    /// assert_eq!(MethodChoice::from(MethodKind::Bdf).name(), "bdf");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            MethodChoice::Builtin(k) => k.name(),
            MethodChoice::Custom(m) => m.name,
        }
    }

    /// Whether the method is implicit (handles stiffness and algebraic components).
    ///
    /// ```
    /// use integrators::{MethodChoice, MethodKind};
    /// assert!(!MethodChoice::from(MethodKind::Dopri).is_stiff());
    /// ```
    pub fn is_stiff(self) -> bool {
        match self {
            MethodChoice::Builtin(k) => k.is_stiff(),
            MethodChoice::Custom(m) => m.stiff,
        }
    }

    /// A fresh method object.
    ///
    /// ```
    /// use integrators::{MethodChoice, MethodKind};
    /// assert_eq!(MethodChoice::default().build().name(), "bdf");
    /// ```
    pub fn build(self) -> Box<dyn Method> {
        match self {
            MethodChoice::Builtin(k) => k.build(),
            MethodChoice::Custom(m) => (m.build)(),
        }
    }
}

impl std::fmt::Display for MethodChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown method name, or a registration under a name already taken.
///
/// ```
/// use integrators::method::MethodError;
/// use integrators::MethodKind;
/// let e = "euler".parse::<MethodKind>().unwrap_err();
/// assert!(matches!(e, MethodError::Unknown { .. }));
/// assert_eq!(e.to_string(), "unknown method `euler`; valid: bdf, esdirk, radau, dopri");
/// ```
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MethodError {
    /// No built-in or registered method has this name.
    #[error("unknown method `{name}`; valid: {valid}")]
    Unknown {
        /// The name given.
        name: String,
        /// The valid names, comma-separated.
        valid: String,
    },
    /// The name is a built-in one (or alias) or already registered.
    #[error("method name `{0}` is already taken")]
    Taken(String),
}

impl std::str::FromStr for MethodChoice {
    type Err = MethodError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if let Ok(k) = s.parse::<MethodKind>() {
            return Ok(k.into());
        }
        let reg = registry().read().unwrap_or_else(|e| e.into_inner());
        if let Some(m) = reg.iter().find(|m| m.name == s) {
            return Ok((*m).into());
        }
        let valid: Vec<&str> = MethodKind::ALL
            .iter()
            .map(|k| k.name())
            .chain(reg.iter().map(|m| m.name))
            .collect();
        Err(MethodError::Unknown {
            name: s.to_string(),
            valid: valid.join(", "),
        })
    }
}

/// The process-wide registry of [`CustomMethod`]s (read-mostly: registered at start-up by a
/// user's `main`, read when scenarios are parsed).
fn registry() -> &'static std::sync::RwLock<Vec<CustomMethod>> {
    static REGISTRY: std::sync::RwLock<Vec<CustomMethod>> = std::sync::RwLock::new(Vec::new());
    &REGISTRY
}

/// Makes `method` selectable by name ([`MethodChoice`]'s `FromStr`, so scenario files too).
/// Fails if the name is a built-in name or alias or already registered.
///
/// ```
/// use integrators::method::{register, registered, CustomMethod};
/// use integrators::{MethodChoice, MethodKind};
/// // BDF under a name of one's own, selectable by name from then on
/// let mine = CustomMethod { name: "my_bdf", build: || integrators::methods::build(MethodKind::Bdf), stiff: true };
/// register(mine).unwrap();
/// assert_eq!("my_bdf".parse::<MethodChoice>().unwrap(), MethodChoice::Custom(mine));
/// assert!(registered().contains(&mine));
/// // a built-in name is taken
/// assert!(register(CustomMethod { name: "radau", ..mine }).is_err());
/// ```
pub fn register(method: CustomMethod) -> Result<(), MethodError> {
    if method.name.parse::<MethodKind>().is_ok() {
        return Err(MethodError::Taken(method.name.to_string()));
    }
    let mut reg = registry().write().unwrap_or_else(|e| e.into_inner());
    if reg.iter().any(|m| m.name == method.name) {
        return Err(MethodError::Taken(method.name.to_string()));
    }
    reg.push(method);
    Ok(())
}

/// The registered methods, in registration order.
///
/// ```
/// // nothing registered in this program
/// assert!(integrators::method::registered().is_empty());
/// ```
pub fn registered() -> Vec<CustomMethod> {
    registry().read().unwrap_or_else(|e| e.into_inner()).clone()
}
