//! Deformation modes by name: what `kind = "<name>"` in a scenario's `[model]` resolves to when
//! it is not one of the built-in kinds (`line`, `sheet`, `shear`). A new mode is a [`Mode`]
//! — its configuration type, its [`CellArray`] built discretely or as the continuum on `n`
//! segments (the mode declares its own continuum scaling of drag, viscosity and forces), and
//! what to record of a state — plus one [`register`] call; the scenario layer, the runner
//! ([`run_mode`]), the outputs, plots, sweeps, `--set`, `--jobs` and the Python module then
//! treat it like the built-in kinds. `examples/tethered_line.rs` is one, out of the library's
//! source, in one file (`docs/guide-deformation-mode.md`).
//!
//! The registry is a [`crate::registry::Registry`] like the division rules' and growth laws':
//! the `[model]` table's keys other than `kind`, `models` and `nodes` are the mode's
//! parameters, deserialized into [`Mode::Config`] and checked by [`Mode::check`] when the
//! scenario loads, errors naming `model.<key>`.

use crate::array::{ArrayProblem, CellArray};
use crate::observe::{ModelKind, Profile, RunRecord, Series};
use crate::registry::{checked, Constructor, Kind, Named, ParamError, Registry, RegistryError};
use crate::runner::OutputTimes;
use crate::runner::{run_recorded, ObservationError, Recorder, SeriesRow};
use crate::settings::SolveSettings;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::fmt::Debug;
use std::marker::PhantomData;
use std::sync::Arc;

/// A deformation mode: how a scenario's parameters become a cell array, and what is recorded of
/// its states.
///
/// Every record has the series `length`, `max_pressure`, `min_pressure`, `max_stretch`,
/// `min_stretch` (the extremes taken over the [`Profile`] that [`observe`](Mode::observe)
/// returns) plus the mode's [`extra_series`](Mode::extra_series), and at the profile times the
/// profiles themselves.
///
/// A mode reusing the line of cells: a configurable number of cells held 10 % short
/// (`examples/tethered_line.rs` is a whole new array):
///
/// ```
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::line::build::{continuum, discrete, LineParams};
/// use celltissue::line::{Line, OutputTimes};
/// use celltissue::modes::{run_mode, Mode};
/// use celltissue::observe::{ModelKind, Profile};
/// use celltissue::registry::ParamError;
/// use celltissue::{NeoHookean, SolveSettings};
/// struct Squeezed;
/// #[derive(serde::Serialize, serde::Deserialize, Debug)]
/// struct Cells { cells: usize }
/// impl Mode for Squeezed {
///     type Config = Cells;
///     type Array = Line<NeoHookean>;
///     fn check(c: &Cells) -> Result<(), ParamError> {
///         if c.cells == 0 { return Err(ParamError::range("cells", 0, ">= 1")); }
///         Ok(())
///     }
///     fn build(c: &Cells, model: ModelKind, nodes: Option<usize>)
///         -> Result<(Line<NeoHookean>, Vec<f64>), ParamError> {
///         let mut p = LineParams::unit_cells(c.cells);
///         p.k = 1.0.into();
///         p.right = RightEnd::Prescribed(Ramp::Constant(0.9 * c.cells as f64));
///         let law = NeoHookean::new(1.0).unwrap();
///         let line = match model {
///             ModelKind::Discrete => discrete(law, &p),
///             ModelKind::Continuum => continuum(law, &p, nodes.unwrap_or(c.cells)),
///         }
///         .map_err(|e| ParamError::new("cells", e))?;
///         // start uniformly compressed, consistent with the held end
///         let y0 = line.initial_state().iter().map(|x| 0.9 * x).collect();
///         Ok((line, y0))
///     }
///     fn observe(line: &Line<NeoHookean>, t: f64, y: &[f64]) -> Profile {
///         line.snapshot(t, y, &vec![0.0; y.len()]).map(|s| s.profile()).unwrap_or_default()
///     }
///     fn length(_: &Line<NeoHookean>, _: f64, y: &[f64]) -> f64 { y.len() as f64 + 1.0 }
/// }
/// let rec = run_mode::<Squeezed>(&Cells { cells: 10 }, ModelKind::Discrete, None,
///                                &SolveSettings::default(), &OutputTimes::at(&[0.0, 50.0]));
/// assert!(rec.error.is_none(), "{:?}", rec.error);
/// // uniformly compressed, at rest: λ = 0.9 and p = 1/0.81 throughout
/// assert!(rec.series.min_stretch.iter().all(|l| (l - 0.9).abs() < 1e-9));
/// assert!((rec.series.max_pressure[1] - 1.0 / 0.81).abs() < 1e-9);
/// ```
pub trait Mode: Send + Sync + 'static {
    /// The `[model]` table's keys (other than `kind`, `models`, `nodes`).
    type Config: Serialize + DeserializeOwned + Debug + Send + Sync + 'static;
    /// The cell array.
    type Array: CellArray;

    /// Checks the configuration when the scenario loads (default: nothing); the error names
    /// the key and its valid range.
    fn check(_config: &Self::Config) -> Result<(), ParamError> {
        Ok(())
    }

    /// The array and its initial state: the discrete array, or the continuum on `nodes`
    /// segments (`None`: the mode's default).
    fn build(
        config: &Self::Config,
        model: ModelKind,
        nodes: Option<usize>,
    ) -> Result<(Self::Array, Vec<f64>), ParamError>;

    /// The per-cell (per-segment) profile of a state at `t`: reference and current positions,
    /// stretch, pressure and any extra fields.
    fn observe(array: &Self::Array, t: f64, y: &[f64]) -> Profile;

    /// The array's length `l(t)`.
    fn length(array: &Self::Array, t: f64, y: &[f64]) -> f64;

    /// Further scalar series of a state (default: none).
    fn extra_series(_array: &Self::Array, _t: f64, _y: &[f64]) -> Vec<(String, f64)> {
        Vec::new()
    }
}

/// A configured mode, ready to run (what the registry builds from a scenario's table).
///
/// ```
/// # use celltissue::{line::Line, modes::Mode, observe::{ModelKind, Profile},
/// #     registry::ParamError, NeoHookean};
/// # #[derive(serde::Serialize, serde::Deserialize, Debug)]
/// # struct Config { cells: usize }
/// # struct Unbuilt;
/// # impl Mode for Unbuilt {
/// #     type Config = Config;
/// #     type Array = Line<NeoHookean>;
/// #     fn build(c: &Config, _: ModelKind, _: Option<usize>) -> Result<(Line<NeoHookean>, Vec<f64>), ParamError> {
/// #         Err(ParamError::range("cells", c.cells, "a line this mode can build"))
/// #     }
/// #     fn observe(_: &Line<NeoHookean>, _: f64, _: &[f64]) -> Profile { Profile::default() }
/// #     fn length(_: &Line<NeoHookean>, _: f64, _: &[f64]) -> f64 { 0.0 }
/// # }
/// use celltissue::modes::{register, ModeSpec};
/// use celltissue::runner::OutputTimes;
/// register::<Unbuilt>("unbuilt")?;
/// // what the scenario layer does with `kind = "unbuilt"`: build the mode, then run it
/// let spec: ModeSpec = toml::from_str("kind = \"unbuilt\"\ncells = 3").unwrap();
/// let rec = spec.law().run(ModelKind::Discrete, None, &Default::default(), &OutputTimes::at(&[1.0]));
/// assert_eq!(rec.error.as_deref(), Some("invalid `cells` = 3: must be a line this mode can build"));
/// # Ok::<(), celltissue::registry::RegistryError>(())
/// ```
pub trait ModeRun: Send + Sync + Debug {
    /// Runs one model (discrete, or continuum on `nodes`).
    fn run(
        &self,
        model: ModelKind,
        nodes: Option<usize>,
        solver: &SolveSettings,
        out: &OutputTimes,
    ) -> RunRecord;
}

/// A mode with its configuration.
struct Configured<M: Mode>(M::Config);

impl<M: Mode> Debug for Configured<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl<M: Mode> ModeRun for Configured<M> {
    fn run(
        &self,
        model: ModelKind,
        nodes: Option<usize>,
        solver: &SolveSettings,
        out: &OutputTimes,
    ) -> RunRecord {
        run_mode::<M>(&self.0, model, nodes, solver, out)
    }
}

/// A mode as a scenario's configuration holds it: its name (`kind`), resolved parameters and
/// the configured mode.
pub type ModeSpec = Named<Modes>;

/// The registry of deformation modes (selected by the `kind` key).
///
/// ```
/// use celltissue::modes::{ModeSpec, Modes};
/// use celltissue::registry::{Kind, Params};
/// // the built-in kinds (line, sheet, …) are not modes; a program registers its own
/// assert!(Modes::registry().names().is_empty());
/// let e = ModeSpec::build("tethered", &Params::new()).unwrap_err();
/// assert!(e.to_string().contains("not a registered deformation mode"), "{e}");
/// ```
pub struct Modes;

static MODES: Registry<Arc<dyn ModeRun>> = Registry::new("deformation mode", "kind", Vec::new);

impl Kind for Modes {
    type Law = Arc<dyn ModeRun>;
    fn registry() -> &'static Registry<Self::Law> {
        &MODES
    }
}

/// Registers the mode `M` under `name` (`[a-z0-9_]+`; not a built-in kind, not taken):
/// scenarios may then write `kind = "<name>"` with `M::Config`'s keys in `[model]`.
///
/// ```
/// let e = celltissue::modes::register::<NoMode>("line").unwrap_err();
/// assert_eq!(e.to_string(), "a deformation mode named `line` is already registered");
/// # use celltissue::{modes::Mode, observe::{ModelKind, Profile}, registry::ParamError};
/// # struct NoMode;
/// # impl Mode for NoMode {
/// #     type Config = ();
/// #     type Array = celltissue::line::Line<celltissue::NeoHookean>;
/// #     fn build(_: &(), _: ModelKind, _: Option<usize>)
/// #         -> Result<(Self::Array, Vec<f64>), ParamError> { unreachable!() }
/// #     fn observe(_: &Self::Array, _: f64, _: &[f64]) -> Profile { unreachable!() }
/// #     fn length(_: &Self::Array, _: f64, _: &[f64]) -> f64 { unreachable!() }
/// # }
/// ```
pub fn register<M: Mode>(name: &str) -> Result<(), RegistryError> {
    if crate::scenario::model::KINDS.contains(&name) {
        return Err(RegistryError::Duplicate(name.to_owned(), MODES.what()));
    }
    let ctor: Constructor<Arc<dyn ModeRun>> =
        checked::<M::Config, _>(M::check, |config| Arc::new(Configured::<M>(config)));
    MODES.register(name, ctor)
}

/// The registered mode names (the built-in kinds not included), sorted.
///
/// ```
/// // nothing registered in this program: the built-in kinds are not listed
/// assert!(!celltissue::modes::names().contains(&"line".to_string()));
/// ```
pub fn names() -> Vec<String> {
    MODES.names()
}

/// Runs a mode: builds the array and records it with [`crate::runner::run_recorded`] (the
/// loop every model uses) at the series and profile times. A failed build or solve gives a
/// record with `error` (and whatever it had computed before the failure); see [`Mode`] for a
/// run.
///
/// ```
/// # use celltissue::{line::Line, modes::{run_mode, Mode}, observe::{ModelKind, Profile},
/// #     registry::ParamError, runner::OutputTimes, NeoHookean, SolveSettings};
/// # struct Never;
/// # impl Mode for Never {
/// #     type Config = ();
/// #     type Array = Line<NeoHookean>;
/// #     fn build(_: &(), _: ModelKind, _: Option<usize>) -> Result<(Line<NeoHookean>, Vec<f64>), ParamError> {
/// #         Err(ParamError::new("cells", "cannot be built"))
/// #     }
/// #     fn observe(_: &Line<NeoHookean>, _: f64, _: &[f64]) -> Profile { Profile::default() }
/// #     fn length(_: &Line<NeoHookean>, _: f64, _: &[f64]) -> f64 { 0.0 }
/// # }
/// // a mode whose build fails gives a record naming the key, and no data
/// let rec = run_mode::<Never>(&(), ModelKind::Discrete, None, &SolveSettings::default(),
///                             &OutputTimes::at(&[1.0]));
/// assert_eq!(rec.error.as_deref(), Some("invalid `cells`: cannot be built"));
/// assert!(rec.series.t.is_empty());
/// ```
pub fn run_mode<M: Mode>(
    config: &M::Config,
    model: ModelKind,
    nodes: Option<usize>,
    solver: &SolveSettings,
    out: &OutputTimes,
) -> RunRecord {
    let mut rec = RunRecord {
        label: String::new(),
        model,
        parameters: serde_json::to_value(config).unwrap_or_default(),
        series: Series::default(),
        profiles: Vec::new(),
        stats: Default::default(),
        divisions: Vec::new(),
        error: None,
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    };
    if let Err(e) = out.check() {
        rec.error = Some(e.to_string());
        return rec;
    }
    let (array, y0) = match M::build(config, model, nodes) {
        Ok(built) => built,
        Err(e) => {
            rec.error = Some(format!("invalid {e}"));
            return rec;
        }
    };
    let mut problem = ArrayProblem::new(array);
    let r = run_recorded(
        &mut problem,
        &y0,
        &[],
        solver,
        out,
        &mut ModeRecorder::<M>(PhantomData),
    );
    rec.series = r.series;
    rec.profiles = r.profiles;
    rec.stats = r.stats;
    rec.error = r.error;
    rec
}

/// What a mode's run records: the mode's [`Mode::observe`] profile, its extremes with
/// [`Mode::length`] and [`Mode::extra_series`] as the series.
struct ModeRecorder<M>(PhantomData<M>);

impl<M: Mode> Recorder<M::Array> for ModeRecorder<M> {
    fn series_row(
        &mut self,
        array: &M::Array,
        t: f64,
        y: &[f64],
        _: &[f64],
    ) -> Result<SeriesRow, ObservationError> {
        let mut row = SeriesRow::from_profile(&M::observe(array, t, y), M::length(array, t, y));
        row.extra = M::extra_series(array, t, y);
        Ok(row)
    }

    fn profile(
        &mut self,
        array: &M::Array,
        t: f64,
        y: &[f64],
        _: &[f64],
    ) -> Result<Profile, ObservationError> {
        Ok(M::observe(array, t, y))
    }
}
