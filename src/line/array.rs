//! [`Line`]: the line of cells as a [`CellArray`] — the residual of docs/model.md §2.9, written once
//! generically over the scalar (plain `f64` or dual numbers for exact Jacobian columns).
//!
//! The same type is the discrete model (N cells) and the conservative continuum scheme
//! (n segments of length `h`, drag `K·h` per node; docs/model.md §3.3a); see [`crate::line::build`].
//!
//! Unknowns are interleaved `(g₁, x₁, g₂, x₂, …)` (growth) or just the free boundary positions;
//! the residual streams over the cells once, keeping only the previous cell, so it allocates
//! nothing and costs O(N). Lines of at least [`PAR_MIN_CELLS`] cells sweep the two halves on two
//! threads when the solver passes `threads ≥ 2`, with the same result. Without growth the
//! layout is read as "boundary `j` is unknown `j − 1`", and per-cell fields that are uniform
//! (detected by `Line::rebuild_layout` / `Line::refresh_uniform_fields`) are not streamed;
//! the fields are changed from outside the crate only through [`Line::edit_fields`], which
//! refreshes that detection, so it cannot go stale.
//!
//! A non-periodic line also provides its own iteration matrix ([`Line::jacobian_into`]): one
//! streaming sweep that differentiates the residual's own cell and row expressions locally in
//! dual numbers, instead of the integrators' coloured sweeps of the whole residual.
//!
//! Here: the line's data ([`Cells`], [`Layout`], [`Line`]), its accessors, field edits, layout
//! and initial state. Submodules: `eval` (one cell's state, [`CellEval`]), `residual` (the
//! rows), `jacobian` (the streaming iteration matrix), `blocked` (both in vectorised blocks for
//! the thesis's line), `blocked_growing` (the residual of a growing, dividing line in such
//! blocks), `cell_array` (the [`CellArray`] interface the integrators see).

use crate::array::CellArray;
use crate::boundary::RightEnd;
use crate::cell::{Active, GrowthLaw, MaxwellBranch, ViscousBranch};
use crate::energy::StrainEnergy;
use crate::line::LineError;
use crate::scalar::Scalar;
use crate::substrate::{drag_factor, DragForm, WidthRule};
use integrators::{JacobianSink, Pattern, ResidualError, SparsityPattern};
use num_dual::Dual64;
use std::sync::Arc;

/// Marker for "not an unknown" in the layout maps.
pub const NONE: usize = usize::MAX;

/// Lines with at least this many cells (and not closed into a ring) evaluate their residual on
/// two threads when the solver passes `threads ≥ 2` ([`integrators::Options::parallel`], via
/// [`CellArray::set_threads`]), each sweeping half of the cells; below it a thread's start-up
/// (tens of µs) would be a noticeable share of a sweep. The result is bitwise that of the
/// serial sweep.
pub const PAR_MIN_CELLS: usize = integrators::System::PARALLEL_MIN;

/// Per-cell data, one `Vec` per field, cells in order `1..=N` at index `0..N`. Inserting a cell
/// (division) is one `insert` per field, O(N).
///
/// ```
/// use celltissue::cell::Field;
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(4);
/// p.eta = Field::Constant(0.5);
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let cells = line.cells();
/// assert_eq!((cells.len(), cells.x_ref.clone()), (4, vec![0.5, 1.5, 2.5, 3.5]));
/// assert!(cells.eta.iter().all(|&e| e > 0.0)); // η (with its factor 2, see the field's doc)
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cells {
    /// Reference (resting) length `L₀,j`.
    pub l0: Vec<f64>,
    /// Reference centre `X_{j−1/2}` (initial centre; reported as `X`).
    pub x_ref: Vec<f64>,
    /// Scale factor on the strain energy (the cell's shear modulus for a unit-modulus law).
    pub mu: Vec<f64>,
    /// Kelvin–Voigt viscosity `η_j` (including the factor 2).
    pub eta: Vec<f64>,
    /// Drag coefficient of the cell, used by the cell-centre form (C).
    pub k_cell: Vec<f64>,
    /// Active-stress amplitude `A_j` (multiplies `b_j(t)`).
    pub active_amp: Vec<f64>,
    /// Active-stress phase `t_R,j = 2π X_{j−1/2}/l₀`.
    pub phase: Vec<f64>,
    /// External pressure `p_e` on the cell's lateral faces (docs/model.md §8.2; 0 = the
    /// thesis's zero traction).
    pub p_ext: Vec<f64>,
}

impl Cells {
    /// Number of cells.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(5))?;
    /// assert_eq!((line.cells().len(), line.cells().is_empty()), (5, false));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn len(&self) -> usize {
        self.l0.len()
    }
    /// Whether there are no cells.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert!(!line.cells().is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn is_empty(&self) -> bool {
        self.l0.is_empty()
    }
}

/// Mutable views of a [`Line`]'s per-cell fields and face drag, handed out by
/// [`Line::edit_fields`]: slices, so values can change but not the number of cells.
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::NeoHookean;
/// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(5)).unwrap();
/// // a stiff cell in the middle and no drag on the first face
/// line.edit_fields(|f| { f.mu[2] = 4.0; f.k_face[0] = 0.0; }).unwrap();
/// assert_eq!(line.cells().mu[2], 4.0);
/// ```
#[derive(Debug)]
pub struct FieldsMut<'a> {
    /// Reference lengths `L₀,j`.
    pub l0: &'a mut [f64],
    /// Reference centres `X_{j−1/2}`.
    pub x_ref: &'a mut [f64],
    /// Energy scale factors `μ_j`.
    pub mu: &'a mut [f64],
    /// Viscosities `η_j`.
    pub eta: &'a mut [f64],
    /// Cell drag coefficients (cell-centre form).
    pub k_cell: &'a mut [f64],
    /// Active-stress amplitudes.
    pub active_amp: &'a mut [f64],
    /// Active-stress phases.
    pub phase: &'a mut [f64],
    /// Face drag `K_j`, `j = 0..=N`.
    pub k_face: &'a mut [f64],
}

/// Where each cell's `g` and each boundary's `x` live in the unknown vector (`NONE` if not an
/// unknown). Rebuilt by `Line::rebuild_layout` after any change in the number of cells.
///
/// ```
/// use celltissue::line::array::NONE;
/// use celltissue::line::{discrete, LineParams};
/// // four cells between a wall and a held end: x₁, x₂, x₃ are the unknowns, nothing grows
/// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
/// let l = line.layout();
/// assert_eq!((l.dim, l.xi[0], l.xi[1], l.xi[3], l.xi[4]), (3, NONE, 0, 2, NONE));
/// assert!(l.gi.iter().all(|&i| i == NONE));
/// assert_eq!(line.initial_state(), [1.0, 2.0, 3.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    /// `gi[j]` for cell `j = 1..=N` at index `j − 1`.
    pub gi: Vec<usize>,
    /// `xi[j]` for boundary `j = 0..=N`.
    pub xi: Vec<usize>,
    /// `vi[j]` for the viscous stretch `a_v` of cell `j = 1..=N` at index `j − 1` (a Maxwell
    /// branch, [`Line::maxwell`]).
    pub vi: Vec<usize>,
    /// Number of unknowns.
    pub dim: usize,
}

/// The per-cell fields (and the face drag) that hold one value, bit for bit, for every cell:
/// the residual uses the value instead of streaming the vector (8 bytes per cell and field).
/// Detected by `Line::rebuild_layout`, so every change to [`Cells`] or `k_face` must be
/// followed by it: the fields are private to the crate (whose builders, cell division and
/// density continuum do so) and the public [`Line::edit_fields`] does it itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct UniformFields {
    /// `1/L₀` when `L₀` is uniform.
    inv_l0: Option<f64>,
    mu: Option<f64>,
    eta: Option<f64>,
    k_face: Option<f64>,
    p_ext: Option<f64>,
    /// Whether a cell needs [`Line::extended_stress`] (a Maxwell branch or a non-zero
    /// external pressure); set by `Line::refresh_uniform_fields`.
    extended: bool,
}

impl UniformFields {
    /// The fields of `cells` and `k_face` that are uniform.
    fn of(cells: &Cells, k_face: &[f64]) -> Self {
        // bitwise equality, so that the residual is bitwise the one that reads the vectors
        let same = |v: &[f64]| {
            let f = *v.first()?;
            v.iter().all(|x| x.to_bits() == f.to_bits()).then_some(f)
        };
        Self {
            inv_l0: same(&cells.l0).map(|l| 1.0 / l),
            mu: same(&cells.mu),
            eta: same(&cells.eta),
            // the free end's row reads its own face (`end_row`), which may carry the tip's
            // half cell (`FreeEndDrag::Cells`)
            k_face: same(match k_face.split_last() {
                Some((_, inner)) if !inner.is_empty() => inner,
                _ => k_face,
            }),
            p_ext: same(&cells.p_ext),
            extended: false,
        }
    }
}

/// How the residual reads the layout: [`Indexed`] (the maps of [`Layout`]) or [`Contiguous`].
trait Lookup: Copy {
    /// Unknown of boundary `j` (or `NONE`).
    fn xi(&self, j: usize) -> usize;
    /// Unknown of cell `i + 1`'s growth stretch (or `NONE`).
    fn gi(&self, i: usize) -> usize;
    /// Unknown of cell `i + 1`'s viscous stretch (or `NONE`).
    fn vi(&self, i: usize) -> usize;
}

/// The layout's maps.
#[derive(Clone, Copy)]
struct Indexed<'a>(&'a Layout);

impl Lookup for Indexed<'_> {
    #[inline(always)]
    fn xi(&self, j: usize) -> usize {
        self.0.xi[j]
    }
    #[inline(always)]
    fn gi(&self, i: usize) -> usize {
        self.0.gi[i]
    }
    #[inline(always)]
    fn vi(&self, i: usize) -> usize {
        self.0.vi[i]
    }
}

/// The layout of a line without growth that is not a ring: boundary `j` is unknown `j − 1`
/// for `1 ≤ j ≤ last`, `last = N − 1` (prescribed end) or `N` (free end); no `g`.
#[derive(Clone, Copy)]
struct Contiguous {
    last: usize,
}

impl Lookup for Contiguous {
    #[inline(always)]
    fn xi(&self, j: usize) -> usize {
        // j = 0 wraps to usize::MAX, which is ≥ last
        let k = j.wrapping_sub(1);
        if k < self.last {
            k
        } else {
            NONE
        }
    }
    #[inline(always)]
    fn gi(&self, _i: usize) -> usize {
        NONE
    }
    #[inline(always)]
    fn vi(&self, _i: usize) -> usize {
        NONE
    }
}

/// The layout of a growing line without Maxwell branch that is not a ring: cell `i + 1`'s
/// growth stretch is unknown `2i` and boundary `j` is unknown `2j − 1` for `1 ≤ j ≤ last`
/// (`last = N − 1`, prescribed end, or `N`, free end), as [`Line::rebuild_layout`] interleaves
/// them; computed, so the residual need not stream `layout.xi`, `layout.gi` and `layout.vi`.
#[derive(Clone, Copy)]
struct Interleaved {
    last: usize,
}

impl Lookup for Interleaved {
    #[inline(always)]
    fn xi(&self, j: usize) -> usize {
        // j = 0 wraps to usize::MAX, which is ≥ last
        let k = j.wrapping_sub(1);
        if k < self.last {
            2 * k + 1
        } else {
            NONE
        }
    }
    #[inline(always)]
    fn gi(&self, i: usize) -> usize {
        2 * i
    }
    #[inline(always)]
    fn vi(&self, _i: usize) -> usize {
        NONE
    }
}

/// Quantities of one cell at `(t, y, ẏ)`.
///
/// ```
/// use celltissue::line::{discrete, LineParams};
/// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
/// // the first cell stretched to 1.2 (x₁ = 1.2), at rest
/// let y = [1.2, 2.0, 3.0];
/// let c = line.eval_cell(1, 0.0, &y, &[0.0; 3])?;
/// assert!((c.lam - 1.2).abs() < 1e-15 && (c.alpha - 1.2).abs() < 1e-15);
/// // neo-Hookean line stress μ(α² − α⁻²), no viscosity: σ = σ_el
/// assert!((c.sigma_el - (1.44 - 1.0 / 1.44)).abs() < 1e-14 && c.sigma == c.sigma_el);
/// assert!((c.w - 1.0 / 1.2).abs() < 1e-15); // width γ₀g₂/α
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct CellEval<S> {
    /// Total stretch `λ`.
    pub lam: S,
    /// Elastic stretch `α = λ/g`.
    pub alpha: S,
    /// `α̇`.
    pub alpha_dot: S,
    /// Elastic stress `μ_j σ_el(α)`.
    pub sigma_el: S,
    /// Full axial stress `σ` (elastic + viscous + active).
    pub sigma: S,
    /// Width `W = γ₀ g₂/α`.
    pub w: S,
    /// Drag factor `κ = (g g₂)^m`.
    pub kappa: S,
    /// Velocity of the left boundary.
    pub vl: S,
    /// Velocity of the right boundary.
    pub vr: S,
    /// Growth stretch `g` (1 without growth).
    pub g: S,
}

/// The line of cells (docs/model.md §2), generic over the strain energy `E`.
///
/// Build one with [`crate::line::build::discrete`] or [`crate::line::build::continuum`]; wrap
/// it in [`crate::ArrayProblem`] to integrate it.
///
/// ```
/// use celltissue::line::build::{continuum, discrete, LineParams};
/// use celltissue::NeoHookean;
/// let p = LineParams::unit_cells(100);
/// let cells = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let coarse = continuum(NeoHookean::new(1.0).unwrap(), &p, 20).unwrap(); // n = 20 segments
/// assert_eq!((cells.n_cells(), coarse.n_cells()), (100, 20));
/// // a held right end: the interior boundaries x₁ … x₉₉ are the unknowns
/// assert_eq!(cells.initial_state().len(), 99);
/// ```
#[derive(Clone)]
pub struct Line<E: StrainEnergy> {
    /// The strain energy (scaled per cell by [`Cells::mu`]).
    pub energy: E,
    /// Per-cell data (read it with [`Line::cells`], change it with [`Line::edit_fields`]).
    /// Private to the crate: the residual caches which of its fields are uniform, so every
    /// change must be followed by `Line::rebuild_layout` (the builders, cell division and
    /// the density continuum do so).
    pub(crate) cells: Cells,
    /// Drag per boundary `K_j` (`j = 0..=N`), already multiplied by `h/L̄` on a continuum grid
    /// (read it with [`Line::k_face`]; same rule as `cells`).
    pub(crate) k_face: Vec<f64>,
    /// The part of `k_face[N]` that is the tip boundary's own half cell (`K/2`) on a continuum
    /// grid built with [`FreeEndDrag::Cells`](crate::substrate::FreeEndDrag::Cells), else 0:
    /// the proliferating density continuum scales the rest of the face with the density.
    pub(crate) k_tip: f64,
    /// Drag-area exponent `m`.
    pub m: f64,
    /// Lateral growth stretch `g₂`.
    pub g2: f64,
    /// Planar aspect ratio `γ₀`.
    pub gamma0: f64,
    /// Shared-width rule.
    pub width: WidthRule,
    /// Drag form.
    pub form: DragForm,
    /// Right-end condition (read it with [`Line::right`]; the layout depends on it).
    pub(crate) right: RightEnd,
    /// Active stress, if any.
    pub active: Option<Active>,
    /// Growth law, if growing (then `g` is in the state; read it with [`Line::growth`]; the
    /// layout depends on it).
    pub(crate) growth: Option<Arc<dyn GrowthLaw>>,
    /// Maxwell branch of every cell, if any (then each cell's viscous stretch `a_v` is in the
    /// state; docs/viscoelasticity.md; read it with [`Line::maxwell`]; the layout depends on
    /// it); the line's own Jacobian sweep differentiates it with the cells.
    pub(crate) maxwell: Option<MaxwellBranch>,
    /// Reference length `l₀ = Σ L₀,j` (read it with [`Line::l0_total`]).
    pub(crate) l0_total: f64,
    /// A ring's circumference `x_N − x₀` (read it with [`Line::period`]): `Σ L₀,j` when the
    /// line is built or its fields are set, and unchanged by division, which splits cells
    /// inside the same ring.
    pub(crate) period: f64,
    /// Absolute tolerance in cell units (positions: times the local reference cell length).
    pub atol_cell: f64,
    /// Unknown layout (read it with [`Line::layout`]; derived from `cells`, `right` and
    /// `growth` by `Line::rebuild_layout`).
    pub(crate) layout: Layout,
    /// The per-cell fields that hold one value for every cell (detected by
    /// `Line::rebuild_layout`).
    pub(crate) uniform: UniformFields,
    /// The cells each segment of a continuum grid stands for ([`continuum`]'s segments of
    /// `h = l₀/n` over cells of length `L`: `h/L` each, `N` in all; `None` where each entry is
    /// one cell). Records count and average per cell with them ([`Snapshot::cell_counts`]).
    ///
    /// [`continuum`]: crate::line::build::continuum
    /// [`Snapshot::cell_counts`]: crate::line::observe::Snapshot::cell_counts
    pub(crate) segment_cells: Option<Vec<f64>>,
    /// Threads of the residual sweep (1 unless the solver passes more through
    /// [`CellArray::set_threads`]); two halves from [`PAR_MIN_CELLS`] cells when ≥ 2.
    pub threads: usize,
}

impl<E: StrainEnergy> Line<E> {
    /// Number of cells `N`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(5))?;
    /// assert_eq!((line.n_cells(), line.l0_total()), (5, 5.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// Whether `g` is part of the state.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// // a growing line carries each cell's growth stretch g_j: three more unknowns
    /// assert!(line.is_growing() && line.growth().is_some());
    /// assert_eq!(line.layout().dim, 3 + 3); // x₁, x₂, x₃ (free end) and g₁, g₂, g₃
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn is_growing(&self) -> bool {
        self.growth.is_some()
    }

    /// The per-cell data (read-only: change it with [`Line::edit_fields`]).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert_eq!((line.cells().l0.as_slice(), line.cells().mu[0]), (&[1.0; 4][..], 1.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cells(&self) -> &Cells {
        &self.cells
    }

    /// The drag per boundary `K_j`, `j = 0..=N` (read-only: change it with
    /// [`Line::edit_fields`]).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(4);
    /// p.k = 0.5.into();
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// assert_eq!(line.k_face(), [0.5; 5]); // one per boundary, j = 0..=N
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn k_face(&self) -> &[f64] {
        &self.k_face
    }

    /// Where each `g_j` and `x_j` live in the unknown vector.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert_eq!(line.layout().dim, 3);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The right-end condition.
    ///
    /// ```
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert!(matches!(line.right(), RightEnd::Prescribed(_))); // held at l₀ = 4
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn right(&self) -> &RightEnd {
        &self.right
    }

    /// The growth law, if growing.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// assert!(line.growth().is_none() && !line.is_growing());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn growth(&self) -> Option<&Arc<dyn GrowthLaw>> {
        self.growth.as_ref()
    }

    /// The Maxwell branch, if any (its viscous stretches are then in the state).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(4);
    /// p.maxwell = Some(MaxwellBranch::maxwell(1.0, 4.0)?);
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// assert_eq!(line.maxwell().map(|b| b.relaxation_time()), Some(1.0)); // η_m/(4μ_m)
    /// assert_eq!(line.layout().vi.len(), 4); // a viscous stretch per cell
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn maxwell(&self) -> Option<&MaxwellBranch> {
        self.maxwell.as_ref()
    }

    /// Reference length `l₀ = Σ L₀,j`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.ref_lengths = vec![1.0, 2.0, 0.5];
    /// p.right = celltissue::boundary::RightEnd::Prescribed(celltissue::boundary::Ramp::Constant(3.5));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// assert_eq!(line.l0_total(), 3.5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn l0_total(&self) -> f64 {
        self.l0_total
    }

    /// A ring's circumference `x_N − x₀` (the initial `Σ L₀,j`; division does not change it).
    ///
    /// ```
    /// use celltissue::boundary::RightEnd;
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(6);
    /// p.right = RightEnd::Periodic { gauge: true };
    /// let ring = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// assert_eq!(ring.period(), 6.0); // x_N ≡ x₀ + 6
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Changes per-cell fields and the face drag in place, then checks them and re-derives
    /// what the residual caches from them (which fields are uniform, `l₀ = Σ L₀,j`): the only
    /// public way to change them, so the residual can never read a stale cache. The number
    /// of cells cannot change here (division does that).
    ///
    /// # Errors
    /// [`LineError::Invalid`] naming the field and cell if a value is out of range (`L₀`
    /// finite and > 0, `μ` finite and > 0, `η` and `K` finite and ≥ 0, the others finite);
    /// the line is then left unchanged.
    ///
    /// ```
    /// use celltissue::line::build::{LineParams, discrete};
    /// use celltissue::NeoHookean;
    /// let mut line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
    /// line.edit_fields(|f| f.mu[2] = 3.0).unwrap();
    /// assert_eq!(line.cells().mu, vec![1.0, 1.0, 3.0, 1.0]);
    /// assert!(line.edit_fields(|f| f.eta[0] = -1.0).is_err());
    /// ```
    pub fn edit_fields(&mut self, f: impl FnOnce(FieldsMut<'_>)) -> Result<(), LineError> {
        let mut cells = self.cells.clone();
        let mut k_face = self.k_face.clone();
        f(FieldsMut {
            l0: &mut cells.l0,
            x_ref: &mut cells.x_ref,
            mu: &mut cells.mu,
            eta: &mut cells.eta,
            k_cell: &mut cells.k_cell,
            active_amp: &mut cells.active_amp,
            phase: &mut cells.phase,
            k_face: &mut k_face,
        });
        let checks: [(&str, &[f64], f64, bool, &str); 8] = [
            ("L0", &cells.l0, 0.0, false, "finite and > 0"),
            ("mu", &cells.mu, 0.0, false, "finite and > 0"),
            ("eta", &cells.eta, 0.0, true, "finite and >= 0"),
            ("K (cell)", &cells.k_cell, 0.0, true, "finite and >= 0"),
            ("K (face)", &k_face, 0.0, true, "finite and >= 0"),
            ("x_ref", &cells.x_ref, f64::NEG_INFINITY, true, "finite"),
            (
                "active_amp",
                &cells.active_amp,
                f64::NEG_INFINITY,
                true,
                "finite",
            ),
            ("phase", &cells.phase, f64::NEG_INFINITY, true, "finite"),
        ];
        for (key, v, low, closed, range) in checks {
            let ok = |x: f64| x.is_finite() && (x > low || (closed && x == low));
            if let Some((i, &x)) = v.iter().enumerate().find(|(_, &x)| !ok(x)) {
                return Err(LineError::invalid(&format!("{key}[{i}]"), x, range));
            }
        }
        self.l0_total = cells.l0.iter().sum();
        self.period = self.l0_total;
        self.cells = cells;
        self.k_face = k_face;
        self.refresh_uniform_fields();
        Ok(())
    }

    /// Re-detects which per-cell fields (`L₀`, `μ`, `η`) and the face drag `K_j` hold one
    /// value for every cell, after they were changed in place without changing `N` (a change
    /// of `N` goes through `rebuild_layout`, which calls this). The
    /// residual reads such a field's value instead of streaming its vector, so a stale
    /// detection would give a wrong residual: every in-place change must be followed by this.
    pub(crate) fn refresh_uniform_fields(&mut self) {
        self.uniform = UniformFields::of(&self.cells, &self.k_face);
        self.uniform.extended = self.maxwell.is_some() || self.uniform.p_ext != Some(0.0);
    }

    /// Recomputes the unknown layout from `N`, the right end and the growth flag (call after
    /// inserting or removing cells, or after changing the per-cell fields or `k_face`: it also
    /// re-detects the fields shared by every cell, as `Line::refresh_uniform_fields`).
    /// Ordering: ring: `x₀` first; then per cell `g_j` (growth) followed by `x_j` when
    /// boundary `j` is free; a Maxwell branch puts `a_v,j` after `g_j`.
    pub(crate) fn rebuild_layout(&mut self) {
        self.refresh_uniform_fields();
        let n = self.n_cells();
        // the previous layout's vectors, refilled (no allocation per division event)
        let fill = |v: &mut Vec<usize>, len: usize| {
            let mut v = std::mem::take(v);
            v.clear();
            v.resize(len, NONE);
            v
        };
        let mut gi = fill(&mut self.layout.gi, n);
        let mut vi = fill(&mut self.layout.vi, n);
        let mut xi = fill(&mut self.layout.xi, n + 1);
        let mut k = 0;
        if let RightEnd::Periodic { gauge: false } = self.right {
            xi[0] = k;
            k += 1;
        }
        let free_end = self.right.is_free();
        for j in 1..=n {
            if self.growth.is_some() {
                gi[j - 1] = k;
                k += 1;
            }
            if self.maxwell.is_some() {
                vi[j - 1] = k;
                k += 1;
            }
            if j < n || free_end {
                xi[j] = k;
                k += 1;
            }
        }
        self.layout = Layout { gi, xi, vi, dim: k };
    }

    /// Initial state: `x_j = Σ_{i≤j} L₀,i`, `g = 1`, `a_v = 1`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let y = line.initial_state();
    /// let l = line.layout();
    /// // boundaries at Σ L₀ and unit growth stretches
    /// assert_eq!((y[l.xi[3]], y[l.gi[0]]), (3.0, 1.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial_state(&self) -> Vec<f64> {
        let mut y = vec![0.0; self.layout.dim];
        let mut x = 0.0;
        if self.layout.xi[0] != NONE {
            y[self.layout.xi[0]] = 0.0;
        }
        for j in 1..=self.n_cells() {
            x += self.cells.l0[j - 1];
            if self.layout.gi[j - 1] != NONE {
                y[self.layout.gi[j - 1]] = 1.0;
            }
            if let (Some(b), Some(&k)) = (&self.maxwell, self.layout.vi.get(j - 1)) {
                if k != NONE {
                    y[k] = b.initial();
                }
            }
            if self.layout.xi[j] != NONE {
                y[self.layout.xi[j]] = x;
            }
        }
        y
    }

    /// Initial guess for `ẏ` (0 for positions, ½G_m-ish 0.5 for `g`).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let yp = line.initial_derivative_guess();
    /// let l = line.layout();
    /// assert_eq!((yp[l.xi[1]], yp[l.gi[1]]), (0.0, 0.5)); // at rest, growing at about G_m/2
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn initial_derivative_guess(&self) -> Vec<f64> {
        let mut yp = vec![0.0; self.layout.dim];
        if let Some(law) = &self.growth {
            let (r0, _) = law.rate(0.0);
            for &gi in &self.layout.gi {
                yp[gi] = r0;
            }
        }
        yp
    }

    /// Position and velocity of boundary `j` at `(t, y, ẏ)`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let (y, yp) = (line.initial_state(), [0.1, 0.2, 0.3]);
    /// assert_eq!(line.boundary(2, 0.0, &y, &yp), (2.0, 0.2)); // an unknown
    /// assert_eq!(line.boundary(0, 0.0, &y, &yp), (0.0, 0.0)); // the wall
    /// assert_eq!(line.boundary(4, 0.0, &y, &yp), (4.0, 0.0)); // the held end
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline(always)]
    pub fn boundary<S: Scalar>(&self, j: usize, t: f64, y: &[S], yp: &[S]) -> (S, S) {
        self.boundary_in(Indexed(&self.layout), j, t, y, yp)
    }

    /// [`boundary`](Line::boundary) with the layout read through `lk`.
    #[inline(always)]
    fn boundary_in<S: Scalar, L: Lookup>(
        &self,
        lk: L,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
    ) -> (S, S) {
        // the common case (a free boundary) inline in the residual's loop; the ends apart
        let k = lk.xi(j);
        if k != NONE {
            return (y[k], yp[k]);
        }
        self.end_boundary(j, t, y, yp)
    }

    /// [`boundary`](Line::boundary) of a boundary that is not an unknown (a wall, a
    /// prescribed end or the ring's seam copy).
    #[inline(never)]
    fn end_boundary<S: Scalar>(&self, j: usize, t: f64, y: &[S], yp: &[S]) -> (S, S) {
        let n = self.n_cells();
        if j == 0 {
            return (S::from(0.0), S::from(0.0));
        }
        debug_assert_eq!(j, n);
        match &self.right {
            RightEnd::Prescribed(r) => {
                let (l, ld) = r.eval(t);
                (S::from(l), S::from(ld))
            }
            RightEnd::Periodic { .. } => {
                let (x0, v0) = self.boundary(0, t, y, yp);
                (x0 + self.period, v0)
            }
            RightEnd::Free(_) => unreachable!("free end is an unknown"),
        }
    }

    /// Human-readable name of unknown `k`: `"x_j (boundary between cells j and j+1)"` or
    /// `"g_j (growth stretch of cell j)"`.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let mut p = LineParams::unit_cells(3);
    /// p.right = celltissue::boundary::RightEnd::Free(None);
    /// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &p)?;
    /// let l = line.layout();
    /// assert_eq!(line.unknown_name(l.xi[2]), "x_2 (boundary between cells 2 and 3)");
    /// assert_eq!(line.unknown_name(l.gi[0]), "g_1 (growth stretch of cell 1)");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn unknown_name(&self, k: usize) -> String {
        let n = self.n_cells();
        if let Some(j) = self.layout.gi.iter().position(|&g| g == k) {
            return format!("g_{} (growth stretch of cell {})", j + 1, j + 1);
        }
        if let Some(j) = self.layout.vi.iter().position(|&v| v == k) {
            return format!("a_v{} (viscous stretch of cell {})", j + 1, j + 1);
        }
        if let Some(b) = self.layout.xi.iter().position(|&x| x == k) {
            return match b {
                0 => "x_0 (ring seam, between cells N and 1)".to_string(),
                b if b == n => format!("x_{n} (free right end of cell {n})"),
                b => format!("x_{b} (boundary between cells {b} and {})", b + 1),
            };
        }
        format!("unknown {k}")
    }

    /// The unknown to blame for cell `j` (1-based): its right boundary, else left, else `g`.
    fn blame(&self, j: usize) -> Option<usize> {
        [
            self.layout.xi[j],
            self.layout.xi[j - 1],
            self.layout.gi[j - 1],
        ]
        .into_iter()
        .find(|&k| k != NONE)
    }
}

mod blocked;
mod blocked_growing;
mod cell_array;
mod eval;
mod jacobian;
mod residual;

#[cfg(test)]
mod tests;
