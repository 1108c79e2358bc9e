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
//! (detected by [`Line::rebuild_layout`] / [`Line::refresh_uniform_fields`]) are not streamed;
//! the fields are changed from outside the crate only through [`Line::edit_fields`], which
//! refreshes that detection, so it cannot go stale.
//!
//! A non-periodic line also provides its own iteration matrix ([`Line::jacobian_into`]): one
//! streaming sweep that differentiates the residual's own cell and row expressions locally in
//! dual numbers, instead of the integrators' coloured sweeps of the whole residual.

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
    pub fn len(&self) -> usize {
        self.l0.len()
    }
    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.l0.is_empty()
    }
}

/// Mutable views of a [`Line`]'s per-cell fields and face drag, handed out by
/// [`Line::edit_fields`]: slices, so values can change but not the number of cells.
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
/// unknown). Rebuilt by [`Line::rebuild_layout`] after any change in the number of cells.
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
/// Detected by [`Line::rebuild_layout`], so every change to [`Cells`] or `k_face` must be
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
    /// external pressure); set by [`Line::refresh_uniform_fields`].
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
            k_face: same(k_face),
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

/// Quantities of one cell at `(t, y, ẏ)`.
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

/// A cell evaluated in dual numbers for [`Line::jacobian_into`]: `s` seeded along its right
/// boundary (`x_j` with derivative 1, `v_j` with `c`), `g` seeded along its growth stretch
/// (`g_j` with 1, `ġ_j` with `c`; all derivatives zero when `g` is not an unknown).
#[derive(Clone, Copy)]
struct LocalCell {
    s: CellEval<Dual64>,
    g: CellEval<Dual64>,
}

impl Default for LocalCell {
    fn default() -> Self {
        let z = Dual64::new(0.0, 0.0);
        let e = CellEval {
            lam: z,
            alpha: z,
            alpha_dot: z,
            sigma_el: z,
            sigma: z,
            w: z,
            kappa: z,
            vl: z,
            vr: z,
            g: z,
        };
        Self { s: e, g: e }
    }
}

/// The unknown a cell's derivatives are projected on in [`Line::jacobian_into`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dir {
    /// An unknown the cell does not depend on.
    Zero,
    /// Its left boundary `x_{j−1}`.
    Left,
    /// Its right boundary `x_j`.
    Right,
    /// Its growth stretch `g_j`.
    Growth,
}

impl CellEval<Dual64> {
    /// The same values with every derivative multiplied by `k`.
    #[inline(always)]
    fn scaled(&self, k: f64) -> Self {
        let f = |v: Dual64| Dual64::new(v.re, k * v.eps);
        CellEval {
            lam: f(self.lam),
            alpha: f(self.alpha),
            alpha_dot: f(self.alpha_dot),
            sigma_el: f(self.sigma_el),
            sigma: f(self.sigma),
            w: f(self.w),
            kappa: f(self.kappa),
            vl: f(self.vl),
            vr: f(self.vr),
            g: f(self.g),
        }
    }

    /// Seeded along the right boundary, projected on `dir` (the growth direction is not
    /// derivable from this seed: see [`LocalCell::along`]).
    #[inline(always)]
    fn along(&self, dir: Dir, c: f64) -> Self {
        match dir {
            Dir::Right => *self,
            Dir::Left => {
                // x_{j−1} enters only through x_j − x_{j−1} and v_j − v_{j−1}: negate, and
                // move the velocity seed from v_j to v_{j−1}
                let mut e = self.scaled(-1.0);
                e.vl = Dual64::new(self.vl.re, c);
                e.vr = Dual64::new(self.vr.re, 0.0);
                e
            }
            Dir::Zero | Dir::Growth => self.scaled(0.0),
        }
    }
}

impl LocalCell {
    /// The cell's values with derivatives along `dir`.
    #[inline(always)]
    fn along(&self, dir: Dir, c: f64) -> CellEval<Dual64> {
        match dir {
            Dir::Growth => self.g,
            _ => self.s.along(dir, c),
        }
    }
}

/// The line of cells (docs/model.md §2), generic over the strain energy `E`.
///
/// Build one with [`crate::line::build::discrete`] or [`crate::line::build::continuum`]; wrap
/// it in [`crate::ArrayProblem`] to integrate it.
#[derive(Clone)]
pub struct Line<E: StrainEnergy> {
    /// The strain energy (scaled per cell by [`Cells::mu`]).
    pub energy: E,
    /// Per-cell data (read it with [`Line::cells`], change it with [`Line::edit_fields`]).
    /// Private to the crate: the residual caches which of its fields are uniform, so every
    /// change must be followed by [`Line::rebuild_layout`] (the builders, cell division and
    /// the density continuum do so).
    pub(crate) cells: Cells,
    /// Drag per boundary `K_j` (`j = 0..=N`), already multiplied by `h/L̄` on a continuum grid
    /// (read it with [`Line::k_face`]; same rule as `cells`).
    pub(crate) k_face: Vec<f64>,
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
    /// it). The line's own Jacobian is then not provided: the integrators' coloured AD
    /// Jacobian is used.
    pub(crate) maxwell: Option<MaxwellBranch>,
    /// Reference length `l₀ = Σ L₀,j` (ring period; read it with [`Line::l0_total`]).
    pub(crate) l0_total: f64,
    /// Absolute tolerance in cell units (positions: times the local reference cell length).
    pub atol_cell: f64,
    /// Unknown layout (read it with [`Line::layout`]; derived from `cells`, `right` and
    /// `growth` by [`Line::rebuild_layout`]).
    pub(crate) layout: Layout,
    /// The per-cell fields that hold one value for every cell (detected by
    /// [`Line::rebuild_layout`]).
    pub(crate) uniform: UniformFields,
    /// Threads of the residual sweep (1 unless the solver passes more through
    /// [`CellArray::set_threads`]); two halves from [`PAR_MIN_CELLS`] cells when ≥ 2.
    pub threads: usize,
}

impl<E: StrainEnergy> Line<E> {
    /// Number of cells `N`.
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// Whether `g` is part of the state.
    pub fn is_growing(&self) -> bool {
        self.growth.is_some()
    }

    /// The per-cell data (read-only: change it with [`Line::edit_fields`]).
    pub fn cells(&self) -> &Cells {
        &self.cells
    }

    /// The drag per boundary `K_j`, `j = 0..=N` (read-only: change it with
    /// [`Line::edit_fields`]).
    pub fn k_face(&self) -> &[f64] {
        &self.k_face
    }

    /// Where each `g_j` and `x_j` live in the unknown vector.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The right-end condition.
    pub fn right(&self) -> &RightEnd {
        &self.right
    }

    /// The growth law, if growing.
    pub fn growth(&self) -> Option<&Arc<dyn GrowthLaw>> {
        self.growth.as_ref()
    }

    /// The Maxwell branch, if any (its viscous stretches are then in the state).
    pub fn maxwell(&self) -> Option<&MaxwellBranch> {
        self.maxwell.as_ref()
    }

    /// Reference length `l₀ = Σ L₀,j` (the ring period).
    pub fn l0_total(&self) -> f64 {
        self.l0_total
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
        self.cells = cells;
        self.k_face = k_face;
        self.refresh_uniform_fields();
        Ok(())
    }

    /// Re-detects which per-cell fields (`L₀`, `μ`, `η`) and the face drag `K_j` hold one
    /// value for every cell, after they were changed in place without changing `N` (a change
    /// of `N` goes through [`rebuild_layout`](Line::rebuild_layout), which calls this). The
    /// residual reads such a field's value instead of streaming its vector, so a stale
    /// detection would give a wrong residual: every in-place change must be followed by this.
    pub fn refresh_uniform_fields(&mut self) {
        self.uniform = UniformFields::of(&self.cells, &self.k_face);
        self.uniform.extended = self.maxwell.is_some() || self.uniform.p_ext != Some(0.0);
    }

    /// Recomputes the unknown layout from `N`, the right end and the growth flag (call after
    /// inserting or removing cells, or after changing the per-cell fields or `k_face`: it also
    /// re-detects the fields shared by every cell, as [`Line::refresh_uniform_fields`]).
    /// Ordering: ring: `x₀` first; then per cell `g_j` (growth) followed by `x_j` when
    /// boundary `j` is free; a Maxwell branch puts `a_v,j` after `g_j`.
    pub fn rebuild_layout(&mut self) {
        self.refresh_uniform_fields();
        let n = self.n_cells();
        let mut gi = vec![NONE; n];
        let mut vi = vec![NONE; n];
        let mut xi = vec![NONE; n + 1];
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
                (x0 + self.l0_total, v0)
            }
            RightEnd::Free(_) => unreachable!("free end is an unknown"),
        }
    }

    /// Human-readable name of unknown `k`: `"x_j (boundary between cells j and j+1)"` or
    /// `"g_j (growth of cell j)"`.
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

    /// Evaluates cell `j` (1-based). Rejects non-positive or non-finite stretch with a
    /// recoverable error naming the cell and the unknown.
    #[inline]
    pub fn eval_cell<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
    ) -> Result<CellEval<S>, ResidualError> {
        let left = self.boundary(j - 1, t, y, yp);
        self.eval_cell_from(j, t, y, yp, left).map(|(e, _)| e)
    }

    /// [`eval_cell`](Line::eval_cell) with the left boundary's `(x, v)` already known (the
    /// residual streams over the cells and hands each cell's right boundary to the next, so
    /// every boundary is looked up once); also returns the right boundary's `(x, v)`.
    #[inline(always)]
    pub(crate) fn eval_cell_from<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
        left: (S, S),
    ) -> Result<(CellEval<S>, (S, S)), ResidualError> {
        self.eval_cell_in::<S, Indexed, true>(Indexed(&self.layout), j, t, y, yp, left)
    }

    /// [`eval_cell_from`](Line::eval_cell_from) with the layout read through `lk`.
    #[inline(always)]
    fn eval_cell_in<S: Scalar, L: Lookup, const EXT: bool>(
        &self,
        lk: L,
        j: usize,
        t: f64,
        y: &[S],
        yp: &[S],
        left: (S, S),
    ) -> Result<(CellEval<S>, (S, S)), ResidualError> {
        let right = self.boundary_in(lk, j, t, y, yp);
        let growth = match lk.gi(j - 1) {
            NONE => (S::from(1.0), S::from(0.0)),
            k => (y[k], yp[k]),
        };
        let mut e = self.eval_core(j, t, left, right, growth)?;
        // `EXT = false` compiles the test out of the thesis's sweep (measured: the runtime
        // test alone cost ≈ 7 % of the f64 residual)
        if EXT && self.uniform.extended {
            let av = match lk.vi(j - 1) {
                NONE => S::from(1.0),
                k => y[k],
            };
            self.extend_cell(j, &mut e, av)?;
        }
        Ok((e, right))
    }

    /// Cell `j` (1-based) from its left and right boundaries' `(x, v)` and its `(g, ġ)`
    /// (a Maxwell branch and an external pressure are added by [`Line::extend_cell`]): the
    /// one expression of a cell's stretch, stresses, width and drag factor, shared by the
    /// residual (any scalar) and the line's own Jacobian ([`Line::jacobian_into`], which seeds
    /// the cell's local directions in dual numbers).
    #[inline(always)]
    fn eval_core<S: Scalar>(
        &self,
        j: usize,
        t: f64,
        (xl, vl): (S, S),
        (xr, vr): (S, S),
        (g, gd): (S, S),
    ) -> Result<CellEval<S>, ResidualError> {
        let c = &self.cells;
        let i = j - 1;
        // divisions bound the f64 sweep (≈ 5 per cell): 1/L₀ of a uniform line is computed
        // once, and without growth (g ≡ 1, ġ ≡ 0) `λ/g` and `1/g` are skipped — the general
        // expressions reduce exactly (x/1 = x, x·1 = x, x − 0 = x), so the rows are bitwise
        // the same
        let inv_l0 = match self.uniform.inv_l0 {
            Some(v) => v,
            None => 1.0 / c.l0[i],
        };
        let lam = (xr - xl) * inv_l0;
        let growing = self.growth.is_some();
        let alpha = if growing { lam / g } else { lam };
        let a = alpha.re();
        if !(a > 0.0 && a.is_finite() && g.re() > 0.0) {
            return Err(ResidualError::Recoverable {
                reason: format!(
                    "cell {j} has non-positive or non-finite stretch (λ = {:.6e}, g = {:.6e})",
                    lam.re(),
                    g.re()
                ),
                component: self.blame(j),
            });
        }
        if let Err(e) = self.energy.admissible([a, 1.0 / a, 1.0]) {
            return Err(self.outside_domain(j, e));
        }
        let alpha_dot = if growing {
            let inv_g = g.recip();
            (vr - vl) * inv_l0 * inv_g - alpha * gd * inv_g
        } else {
            (vr - vl) * inv_l0
        };
        let resp = self.energy.line(a);
        let mu = self.uniform.mu.unwrap_or_else(|| c.mu[i]);
        let sigma_el = alpha.lift(mu * resp.sigma, mu * resp.dsigma);
        let inv_a = alpha.recip();
        let mut sigma = sigma_el;
        let eta = self.uniform.eta.unwrap_or_else(|| c.eta[i]);
        if eta != 0.0 {
            sigma += alpha_dot * eta * (inv_a * inv_a + 1.0);
        }
        if let Some(act) = &self.active {
            let amp = c.active_amp[i] * act.b(t, c.phase[i]);
            if amp != 0.0 {
                sigma += ((lam - 1.0) * (0.5 * act.beta) + 1.0) * amp;
            }
        }
        let w = inv_a * (self.gamma0 * self.g2);
        let kappa = drag_factor(g, self.g2, self.m);
        Ok(CellEval {
            lam,
            alpha,
            alpha_dot,
            sigma_el,
            sigma,
            w,
            kappa,
            vl,
            vr,
            g,
        })
    }

    /// Adds cell `j`'s Maxwell branch (at viscous stretch `av`) and external pressure to its
    /// evaluation `e` (a Maxwell cell, without elastic law, loses its elastic stress). Called
    /// after [`Line::eval_core`] only when the line has either (`uniform.extended`), so the
    /// thesis's cell keeps its lean expression.
    #[inline(never)]
    fn extend_cell<S: Scalar>(
        &self,
        j: usize,
        e: &mut CellEval<S>,
        av: S,
    ) -> Result<(), ResidualError> {
        if let Some(b) = &self.maxwell {
            if !b.admissible(av.re()) {
                return Err(self.bad_viscous_stretch(j, av.re()));
            }
            let ae = e.alpha.re() / av.re();
            if let Err(err) = self.energy.admissible([ae, 1.0 / ae, 1.0]) {
                return Err(self.outside_domain(j, err));
            }
            if !b.keeps_elastic() {
                e.sigma -= e.sigma_el;
                e.sigma_el = S::from(0.0);
            }
            e.sigma += b.stress(&self.energy, e.alpha, av);
        }
        let pe = self
            .uniform
            .p_ext
            .unwrap_or_else(|| self.cells.p_ext[j - 1]);
        if pe != 0.0 {
            e.sigma -= pe;
        }
        Ok(())
    }

    /// The recoverable error of cell `j` whose viscous stretch is not admissible.
    #[cold]
    #[inline(never)]
    fn bad_viscous_stretch(&self, j: usize, av: f64) -> ResidualError {
        ResidualError::Recoverable {
            reason: format!(
                "cell {j} has non-positive or non-finite viscous stretch a_v = {av:.6e}"
            ),
            component: Some(self.layout.vi[j - 1]),
        }
    }

    /// The recoverable error of cell `j` whose state is outside the law's domain.
    #[cold]
    #[inline(never)]
    fn outside_domain(&self, j: usize, e: crate::energy::EnergyError) -> ResidualError {
        ResidualError::Recoverable {
            reason: format!("cell {j}: {e}"),
            component: self.blame(j),
        }
    }

    /// `k_face[b]`, without reading the vector when it is uniform.
    #[inline(always)]
    fn k_face_at(&self, b: usize) -> f64 {
        self.uniform.k_face.unwrap_or_else(|| self.k_face[b])
    }

    /// The force across the face between cells `p` and `cur`: `W_face (σ_cur − σ_p)`.
    #[inline(always)]
    fn face_force<S: Scalar>(&self, p: &CellEval<S>, cur: &CellEval<S>) -> S {
        self.width.face(p.w, cur.w) * (cur.sigma - p.sigma)
    }

    /// Row of interior boundary `b` in the boundary drag form (cells `p = b`, `cur = b + 1`).
    #[inline(always)]
    fn boundary_row<S: Scalar>(&self, b: usize, p: &CellEval<S>, cur: &CellEval<S>) -> S {
        let f = self.face_force(p, cur);
        let kappa = (p.kappa + cur.kappa) * 0.5;
        kappa * p.vr * self.k_face_at(b) - f
    }

    /// Row of interior boundary `b` in the cell-centre drag form: cell `p = b`'s drag minus
    /// the face forces `f_prev` (left of cell `b`) and `f` (right of it).
    #[inline(always)]
    fn centre_row<S: Scalar>(&self, b: usize, p: &CellEval<S>, f_prev: S, f: S) -> S {
        p.kappa * (p.vl + p.vr) * self.cells.k_cell[b - 1] - f_prev - f
    }

    /// Row of the free right end (cell `p = N`; `f_prev` is the face force left of cell `N`,
    /// used by the cell-centre form).
    #[inline(always)]
    fn end_row<S: Scalar>(&self, t: f64, p: &CellEval<S>, f_prev: S) -> S {
        let n = self.n_cells();
        let f_n = -(p.w * p.sigma) + self.f_ext(t);
        match self.form {
            DragForm::Boundary => p.kappa * p.vr * self.k_face_at(n) - f_n,
            DragForm::Centre => p.kappa * (p.vl + p.vr) * self.cells.k_cell[n - 1] - f_prev - f_n,
        }
    }

    /// Row of cell `cur`'s growth stretch: `ġ − G(σ)` (`ypg` is `ġ`).
    #[inline(always)]
    fn growth_row<S: Scalar>(&self, law: &dyn GrowthLaw, ypg: S, cur: &CellEval<S>) -> S {
        let (rate, drate) = law.rate(cur.sigma.re());
        ypg - cur.sigma.lift(rate, drate)
    }

    /// Row of cell `cur`'s viscous stretch: `ȧ_v − a_v σ_m(α/a_v)/η_m`.
    #[inline(always)]
    fn flow_row<S: Scalar>(&self, b: &MaxwellBranch, av: S, avd: S, cur: &CellEval<S>) -> S {
        avd - b.rate(av, b.stress(&self.energy, cur.alpha, av))
    }

    /// Applied force on a free right end at `t` (0 if none).
    #[inline]
    fn f_ext(&self, t: f64) -> f64 {
        match &self.right {
            RightEnd::Free(Some(f)) => f(t).0,
            _ => 0.0,
        }
    }

    /// The residual with cells `1..c0` on this thread and `c0..=N` on a second one, or `None`
    /// when the line cannot be split there (a ring, or `c0` outside `2..N`). The rows of cells
    /// `1..c0` all come before the row of boundary `c0 − 1`, which starts the second half's
    /// rows, so the halves write disjoint slices of `r`. Same result as the serial sweep,
    /// including which error is reported (the first half's, if both fail).
    fn residual_two_threads<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        c0: usize,
    ) -> Option<Result<(), ResidualError>> {
        let n = self.n_cells();
        if self.right.is_periodic() || c0 < 2 || c0 > n {
            return None;
        }
        let split = self.layout.xi[c0 - 1];
        if split == NONE {
            return None;
        }
        let (ra, rb) = r.split_at_mut(split);
        // the second half on a rayon worker (no thread started per residual)
        let (res_a, res_b) = rayon::join(
            || self.residual_cells(t, y, yp, ra, 0, 1, c0 - 1),
            || self.residual_cells(t, y, yp, rb, split, c0, n),
        );
        Some(res_a.and(res_b))
    }

    /// The residual rows of cells `first..=last` (and of the free right end when `last = N`),
    /// written to `r[row − off]`: the serial sweep is `(1, N)` with `off = 0`; a sweep that
    /// starts inside the line first evaluates the two cells before `first` for its running
    /// state (the previous cell and, for the cell-centre form, the face force left of it), so
    /// every row is computed by the same expression as in the serial sweep.
    #[allow(clippy::too_many_arguments)]
    fn residual_cells<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        let ind = Indexed(&self.layout);
        match (self.contiguous(), self.uniform.extended) {
            (Some(lk), false) => {
                self.residual_cells_in::<S, _, false>(lk, t, y, yp, r, off, first, last)
            }
            (Some(lk), true) => {
                self.residual_cells_in::<S, _, true>(lk, t, y, yp, r, off, first, last)
            }
            (None, false) => {
                self.residual_cells_in::<S, _, false>(ind, t, y, yp, r, off, first, last)
            }
            (None, true) => {
                self.residual_cells_in::<S, _, true>(ind, t, y, yp, r, off, first, last)
            }
        }
    }

    /// The layout of a line without growth that is not a ring, if `self.layout` is that of
    /// the current `N` and right end: boundary `j`'s unknown is `j − 1` (the wall `x₀` is not
    /// an unknown), so the residual need not stream `layout.xi` and `layout.gi`. Derived from
    /// the same inputs as [`Line::rebuild_layout`] and checked against the layout's size in
    /// O(1), so it is never out of step with the layout itself.
    #[inline]
    fn contiguous(&self) -> Option<Contiguous> {
        if self.growth.is_some() || self.maxwell.is_some() || self.right.is_periodic() {
            return None;
        }
        let n = self.n_cells();
        let last = n - 1 + self.right.is_free() as usize;
        (self.layout.dim == last && self.layout.xi.len() == n + 1 && self.layout.gi.len() == n)
            .then_some(Contiguous { last })
    }

    /// [`residual_cells`](Line::residual_cells) with the layout read through `lk`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn residual_cells_in<S: Scalar, L: Lookup, const EXT: bool>(
        &self,
        lay: L,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
        off: usize,
        first: usize,
        last: usize,
    ) -> Result<(), ResidualError> {
        let n = self.n_cells();
        // F_{b−1} for the cell-centre form (F₀ = 0 at the wall).
        let (mut prev, mut f_prev, mut left) = if first == 1 {
            let prev = if self.right.is_periodic() {
                Some(self.eval_cell(n, t, y, yp)?)
            } else {
                None
            };
            (prev, S::from(0.0), self.boundary_in(lay, 0, t, y, yp))
        } else {
            let lb = self.boundary_in(lay, first - 2, t, y, yp);
            let (p, right) = self.eval_cell_in::<S, L, EXT>(lay, first - 1, t, y, yp, lb)?;
            let f_prev = if first >= 3 {
                let llb = self.boundary_in(lay, first - 3, t, y, yp);
                let (pp, _) = self.eval_cell_in::<S, L, EXT>(lay, first - 2, t, y, yp, llb)?;
                self.face_force(&pp, &p)
            } else {
                S::from(0.0)
            };
            (Some(p), f_prev, right)
        };
        for c in first..=last {
            let (cur, right) = self.eval_cell_in::<S, L, EXT>(lay, c, t, y, yp, left)?;
            left = right;
            let gk = lay.gi(c - 1);
            if gk != NONE {
                if let Some(law) = &self.growth {
                    r[gk - off] = self.growth_row(law.as_ref(), yp[gk], &cur);
                }
            }
            let vk = lay.vi(c - 1);
            if vk != NONE {
                if let Some(b) = &self.maxwell {
                    r[vk - off] = self.flow_row(b, y[vk], yp[vk], &cur);
                }
            }
            if let Some(p) = prev {
                let b = c - 1;
                let row = lay.xi(b);
                match self.form {
                    DragForm::Boundary => {
                        if row != NONE {
                            r[row - off] = self.boundary_row(b, &p, &cur);
                        }
                    }
                    DragForm::Centre => {
                        let f = self.face_force(&p, &cur);
                        if row != NONE {
                            r[row - off] = self.centre_row(b, &p, f_prev, f);
                        }
                        f_prev = f;
                    }
                }
            }
            prev = Some(cur);
        }
        if last == n && self.right.is_free() {
            let p = prev.expect("at least one cell");
            r[lay.xi(n) - off] = self.end_row(t, &p, f_prev);
        }
        Ok(())
    }

    /// The iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ` of a non-periodic line, added into `jac`
    /// (zeroed by the caller, shaped by [`CellArray::pattern`]), in one streaming sweep over
    /// the cells; `Ok(false)` for a ring (its sparse pattern is left to the coloured AD
    /// Jacobian of [`crate::ArrayProblem`]).
    ///
    /// With a Maxwell branch or an external pressure it returns `Ok(false)` too (the coloured
    /// AD Jacobian is used: the sweep below does not seed the viscous stretches, and keeping
    /// the thesis's sweep free of the extensions' test kept it at its measured cost).
    ///
    /// Each cell is evaluated once by the residual's own cell expression in `Dual64`, seeded
    /// along its right boundary `x_j` (with `ẏ`-part `c`, as the colouring seeds `v`); a cell
    /// depends on its boundaries only through `x_j − x_{j−1}` and `v_j − v_{j−1}`, so the
    /// derivative along `x_{j−1}` is the negated one, apart from the velocities themselves.
    /// A growing cell is evaluated a second time seeded along `g_j`. Each row is then the
    /// residual's own row expression evaluated once per column of its stencil with the cells'
    /// derivatives projected on that column, so every feature of the residual (drag forms,
    /// `κ = (g g₂)^m`, width rule, viscosity, active stress, growth, ends) is differentiated
    /// exactly as the coloured AD Jacobian does, at about the cost of one dual residual sweep
    /// and without dual copies of `y`, `ẏ` and `r`.
    ///
    /// ```
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::{CellArray, NeoHookean};
    /// use integrators::linalg::Matrix;
    /// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(5)).unwrap();
    /// let y = line.initial_state();
    /// let mut jac = Matrix::zeros(line.dim(), &line.pattern());
    /// assert!(line.jacobian_into(0.0, &y, &vec![0.0; y.len()], 1.0, &mut jac).unwrap());
    /// // at rest and without drag (K = 0), boundary 1's own entry is 2·σ_el'(1) = 8μ, and
    /// // boundary 2 pulls on it with −σ_el'(1) = −4μ
    /// assert!((jac.get(0, 0) - 8.0).abs() < 1e-12);
    /// assert!((jac.get(0, 1) + 4.0).abs() < 1e-12);
    /// ```
    pub fn jacobian_into(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        if self.right.is_periodic() || self.uniform.extended {
            return Ok(false);
        }
        let n = self.n_cells();
        let lay = &self.layout;
        let d = Dual64::new;
        let mut left = self.boundary(0, t, y, yp);
        // the last three cells in a ring (cell j at j mod 3: moving them would copy 1 KB per cell)
        let mut win: [LocalCell; 3] = [LocalCell::default(); 3];
        for cell in 1..=n {
            let right = self.boundary(cell, t, y, yp);
            let gk = lay.gi[cell - 1];
            let (g, gd) = match gk {
                NONE => (1.0, 0.0),
                k => (y[k], yp[k]),
            };
            let (xl, xr) = ((d(left.0, 0.0), d(left.1, 0.0)), (right.0, right.1));
            let s = self.eval_core(
                cell,
                t,
                xl,
                (d(xr.0, 1.0), d(xr.1, c)),
                (d(g, 0.0), d(gd, 0.0)),
            )?;
            let ge = if gk != NONE {
                self.eval_core(
                    cell,
                    t,
                    xl,
                    (d(xr.0, 0.0), d(xr.1, 0.0)),
                    (d(g, 1.0), d(gd, c)),
                )?
            } else {
                s.along(Dir::Zero, c)
            };
            left = right;
            let (w0, w1, w2) = ((cell + 1) % 3, (cell + 2) % 3, cell % 3);
            win[w2] = LocalCell { s, g: ge };
            if gk != NONE {
                if let Some(law) = &self.growth {
                    let ypg = yp[gk];
                    self.emit(jac, gk, cell, [&win[w2]], c, |e| {
                        // ġ is seeded with c exactly where g is seeded with 1
                        self.growth_row(law.as_ref(), d(ypg, c * e[0].g.eps), &e[0])
                    });
                }
            }
            if cell < 2 {
                continue;
            }
            let b = cell - 1;
            let row = lay.xi[b];
            if row == NONE {
                continue;
            }
            match self.form {
                DragForm::Boundary => self.emit(jac, row, b, [&win[w1], &win[w2]], c, |e| {
                    self.boundary_row(b, &e[0], &e[1])
                }),
                DragForm::Centre if b >= 2 => {
                    self.emit(jac, row, b - 1, [&win[w0], &win[w1], &win[w2]], c, |e| {
                        let f_prev = self.face_force(&e[0], &e[1]);
                        let f = self.face_force(&e[1], &e[2]);
                        self.centre_row(b, &e[1], f_prev, f)
                    })
                }
                DragForm::Centre => self.emit(jac, row, b, [&win[w1], &win[w2]], c, |e| {
                    let f = self.face_force(&e[0], &e[1]);
                    self.centre_row(b, &e[0], d(0.0, 0.0), f)
                }),
            }
        }
        if self.right.is_free() {
            let row = lay.xi[n];
            let (w1, w2) = ((n + 2) % 3, n % 3);
            match self.form {
                DragForm::Centre if n >= 2 => {
                    self.emit(jac, row, n - 1, [&win[w1], &win[w2]], c, |e| {
                        let f_prev = self.face_force(&e[0], &e[1]);
                        self.end_row(t, &e[1], f_prev)
                    })
                }
                _ => self.emit(jac, row, n, [&win[w2]], c, |e| {
                    self.end_row(t, &e[0], d(0.0, 0.0))
                }),
            }
        }
        Ok(true)
    }

    /// Adds row `row` of the Jacobian: `f` (a row expression of the residual) is evaluated
    /// once per unknown the `Q` consecutive cells `first..first + Q` depend on — their
    /// boundaries `first − 1 ..= first + Q − 1` and, when growing, their `g` — with every
    /// cell's derivatives projected on that unknown; the dual part is the entry.
    #[inline(always)]
    fn emit<const Q: usize>(
        &self,
        jac: &mut JacobianSink,
        row: usize,
        first: usize,
        cells: [&LocalCell; Q],
        c: f64,
        f: impl Fn(&[CellEval<Dual64>; Q]) -> Dual64,
    ) {
        let lay = &self.layout;
        for k in 0..=Q {
            let beta = first - 1 + k;
            let col = lay.xi[beta];
            if col == NONE {
                continue;
            }
            // a plain loop: `std::array::from_fn` was left as a call here, and the copies
            // of its result through the stack stalled on store forwarding
            let mut e = [cells[0].s; Q];
            for q in 0..Q {
                let cell = first + q;
                let dir = if cell == beta {
                    Dir::Right
                } else if cell == beta + 1 {
                    Dir::Left
                } else {
                    Dir::Zero
                };
                e[q] = cells[q].along(dir, c);
            }
            jac.add(row, col, f(&e).eps);
        }
        if self.growth.is_some() {
            for k in 0..Q {
                let col = lay.gi[first + k - 1];
                if col == NONE {
                    continue;
                }
                let mut e = [cells[0].s; Q];
                for q in 0..Q {
                    e[q] = cells[q].along(if q == k { Dir::Growth } else { Dir::Zero }, c);
                }
                jac.add(row, col, f(&e).eps);
            }
        }
    }

    /// Structural entries `(row, col)` of the Jacobian, from the stencil.
    pub fn jacobian_entries(&self) -> Vec<(usize, usize)> {
        let mut entries = Vec::new();
        self.for_each_jacobian_entry(|i, j| entries.push((i, j)));
        entries
    }

    /// Calls `f(row, col)` for every structural entry of the Jacobian (with repeats), without
    /// storing them: the banded pattern of a long line needs only the widest offsets, and a
    /// list of the 10⁷ entries of a 10⁶-cell line would be 100+ MB of fresh memory.
    pub fn for_each_jacobian_entry(&self, mut f: impl FnMut(usize, usize)) {
        let n = self.n_cells();
        let lay = &self.layout;
        let periodic = self.right.is_periodic();
        // unknowns a cell depends on
        let cell_deps = |c: usize, out: &mut Vec<usize>| {
            let right = if c == n && periodic { 0 } else { c };
            let v = lay.vi.get(c - 1).copied().unwrap_or(NONE);
            for k in [lay.xi[c - 1], lay.xi[right], lay.gi[c - 1], v] {
                if k != NONE {
                    out.push(k);
                }
            }
        };
        let wrap = |c: isize| -> Option<usize> {
            if c >= 1 && c as usize <= n {
                Some(c as usize)
            } else if periodic {
                Some(((c - 1).rem_euclid(n as isize) + 1) as usize)
            } else {
                None
            }
        };
        let mut deps = Vec::new();
        for c in 1..=n {
            let v = lay.vi.get(c - 1).copied().unwrap_or(NONE);
            for row in [lay.gi[c - 1], v] {
                if row != NONE {
                    deps.clear();
                    cell_deps(c, &mut deps);
                    for &k in &deps {
                        f(row, k);
                    }
                }
            }
        }
        for b in 0..=n {
            let row = lay.xi[b];
            if row == NONE {
                continue;
            }
            let b = b as isize;
            let cells: &[isize] = match self.form {
                DragForm::Boundary => &[b, b + 1],
                DragForm::Centre => &[b - 1, b, b + 1],
            };
            deps.clear();
            for &c in cells {
                if let Some(c) = wrap(c) {
                    cell_deps(c, &mut deps);
                }
            }
            for &k in &deps {
                f(row, k);
            }
        }
    }
}

impl<E: StrainEnergy> CellArray for Line<E> {
    fn dim(&self) -> usize {
        self.layout.dim
    }

    fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    fn pattern(&self) -> Pattern {
        if self.right.is_periodic() {
            return Pattern::Sparse(Arc::new(SparsityPattern::from_entries(
                self.layout.dim,
                &self.jacobian_entries(),
            )));
        }
        let (mut lower, mut upper) = (0, 0);
        self.for_each_jacobian_entry(|i, j| {
            if i > j {
                lower = lower.max(i - j);
            } else {
                upper = upper.max(j - i);
            }
        });
        Pattern::Banded { lower, upper }
    }

    fn residual<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError> {
        let n = self.n_cells();
        if n >= PAR_MIN_CELLS && self.threads >= 2 {
            if let Some(res) = self.residual_two_threads(t, y, yp, r, n / 2) {
                return res;
            }
        }
        self.residual_cells(t, y, yp, r, 0, 1, n)
    }

    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        self.jacobian_into(t, y, yp, c, jac)
    }

    fn atol(&self) -> Option<Vec<f64>> {
        let n = self.n_cells();
        let lay = &self.layout;
        let mut a = vec![self.atol_cell; lay.dim];
        for b in 0..=n {
            let k = lay.xi[b];
            if k == NONE {
                continue;
            }
            let left = if b >= 1 {
                self.cells.l0[b - 1]
            } else {
                self.cells.l0[n - 1]
            };
            let right = if b < n { self.cells.l0[b] } else { left };
            a[k] = self.atol_cell * left.min(right);
        }
        Some(a)
    }

    /// Positions tested through their cell's stretch (docs/model.md §8.1): boundary `b` is
    /// differenced with boundary `b − 1` when both are unknowns; the first free boundary is an
    /// anchor measured in lengths of its cell, and the last free boundary before a prescribed
    /// end also on its own (the stretch error of that end's cell); growth stretches keep their
    /// own test.
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        use integrators::Row;
        let n = self.n_cells();
        let lay = &self.layout;
        let mut rows = vec![Row::Own; lay.dim];
        for b in 0..=n {
            let k = lay.xi[b];
            if k == NONE {
                continue;
            }
            rows[k] = match b.checked_sub(1).map(|c| (c, lay.xi[c])) {
                Some((_, p)) if p != NONE => Row::Difference { partner: p },
                Some((c, _)) => Row::Anchor {
                    size: self.cells.l0[c],
                },
                None => Row::Anchor {
                    size: self.cells.l0[0],
                },
            };
        }
        let mut map = integrators::ErrorMap::from_rows(rows).ok()?;
        // the last free boundary before a prescribed one: its cell's stretch error is its own
        for b in 0..n {
            let k = lay.xi[b];
            if k != NONE && lay.xi[b + 1] == NONE && !self.right.is_periodic() {
                map = map.with_end(k, self.cells.l0[b]).ok()?;
            }
        }
        Some(map)
    }

    fn algebraic(&self) -> Vec<bool> {
        let n = self.n_cells();
        let lay = &self.layout;
        let mut alg = vec![false; lay.dim];
        let periodic = self.right.is_periodic();
        let eta_at = |c: usize| -> f64 {
            if c >= 1 && c <= n {
                self.cells.eta[c - 1]
            } else if periodic {
                self.cells.eta[if c == 0 { n - 1 } else { 0 }]
            } else {
                0.0
            }
        };
        for b in 0..=n {
            let k = lay.xi[b];
            if k == NONE {
                continue;
            }
            let drag = match self.form {
                DragForm::Boundary => self.k_face[b],
                DragForm::Centre => self.cells.k_cell[b.max(1) - 1],
            };
            let visc = eta_at(b) != 0.0 || eta_at(b + 1) != 0.0;
            alg[k] = drag == 0.0 && !visc;
        }
        alg
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::RightEnd;
    use crate::cell::{Field, TanhGrowth};
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;
    use num_dual::Dual64;

    fn line(n: usize, form: DragForm, growth: bool, free: bool) -> Line<NeoHookean> {
        let mut p = LineParams::unit_cells(n);
        p.k = Field::Constant(0.3);
        p.eta = Field::Constant(0.7);
        p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.2);
        p.form = form;
        if growth {
            p.growth = Some(Arc::new(TanhGrowth::default()));
        }
        if free {
            p.right = RightEnd::Free(None);
        }
        discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap()
    }

    fn state(line: &Line<NeoHookean>) -> (Vec<f64>, Vec<f64>) {
        let mut y = line.initial_state();
        for (i, v) in y.iter_mut().enumerate() {
            *v += 0.05 * ((i as f64) * 0.7).sin();
        }
        let yp = (0..y.len())
            .map(|i| 0.1 * ((i as f64) * 1.3).cos())
            .collect();
        (y, yp)
    }

    #[test]
    fn two_thread_residual_is_the_serial_one() {
        // every split point of small lines (both drag forms, with and without growth, free
        // or prescribed end), in f64 and in dual numbers: bitwise the serial rows
        for form in [DragForm::Boundary, DragForm::Centre] {
            for (growth, free) in [(false, false), (true, true), (false, true)] {
                let l = line(9, form, growth, free);
                let (y, yp) = state(&l);
                let n = y.len();
                let mut serial = vec![0.0; n];
                l.residual_cells(0.3, &y, &yp, &mut serial, 0, 1, 9)
                    .unwrap();
                let yd: Vec<Dual64> = y.iter().map(|&v| Dual64::new(v, 0.5)).collect();
                let ypd: Vec<Dual64> = yp.iter().map(|&v| Dual64::new(v, -0.25)).collect();
                let mut serial_d = vec![Dual64::new(0.0, 0.0); n];
                l.residual_cells(0.3, &yd, &ypd, &mut serial_d, 0, 1, 9)
                    .unwrap();
                for c0 in 2..=9 {
                    let mut r = vec![f64::NAN; n];
                    l.residual_two_threads(0.3, &y, &yp, &mut r, c0)
                        .expect("splittable")
                        .unwrap();
                    assert_eq!(r, serial, "{form:?} growth={growth} free={free} c0={c0}");
                    let mut rd = vec![Dual64::new(f64::NAN, f64::NAN); n];
                    l.residual_two_threads(0.3, &yd, &ypd, &mut rd, c0)
                        .expect("splittable")
                        .unwrap();
                    for (a, b) in rd.iter().zip(&serial_d) {
                        assert_eq!((a.re, a.eps), (b.re, b.eps), "dual c0={c0}");
                    }
                }
            }
        }
    }

    #[test]
    fn two_thread_residual_reports_the_serial_error() {
        // a collapsed cell in either half: the same error as the serial sweep
        let l = line(12, DragForm::Centre, false, false);
        for bad in [2usize, 5, 6, 7, 11] {
            let (mut y, yp) = state(&l);
            // boundary `bad` moved onto boundary `bad − 1`: cell `bad` has zero stretch
            y[l.layout.xi[bad]] = y[l.layout.xi[bad - 1]];
            let mut r = vec![0.0; y.len()];
            let serial = l.residual_cells(0.0, &y, &yp, &mut r, 0, 1, 12);
            assert!(serial.is_err());
            for c0 in [3, 6, 7, 10] {
                let two = l.residual_two_threads(0.0, &y, &yp, &mut r, c0).unwrap();
                assert_eq!(two, serial, "bad={bad} c0={c0}");
            }
        }
    }

    #[test]
    fn large_lines_take_the_two_thread_path_with_the_serial_result() {
        let n = PAR_MIN_CELLS + 5;
        let l = line(n, DragForm::Boundary, false, false);
        let (y, yp) = state(&l);
        let mut serial = vec![0.0; y.len()];
        l.residual_cells(0.1, &y, &yp, &mut serial, 0, 1, n)
            .unwrap();
        let mut r = vec![0.0; y.len()];
        l.residual(0.1, &y, &yp, &mut r).unwrap();
        assert_eq!(r, serial);
    }

    /// The residual of `l` with every layout and field read from the vectors (no contiguous
    /// layout, no uniform fields): the reference the fast paths must reproduce bitwise.
    fn reference_residual<S: Scalar>(l: &Line<NeoHookean>, y: &[S], yp: &[S]) -> Vec<S> {
        let mut slow = l.clone();
        slow.uniform = UniformFields::default();
        slow.uniform.extended = l.uniform.extended;
        let mut r = vec![S::from(f64::NAN); y.len()];
        slow.residual_cells_in::<S, _, true>(
            Indexed(&slow.layout),
            0.4,
            y,
            yp,
            &mut r,
            0,
            1,
            l.n_cells(),
        )
        .unwrap();
        r
    }

    #[test]
    fn fast_paths_give_the_indexed_residual_bitwise() {
        // uniform fields (l0, mu, eta, K all uniform) and the contiguous layout, in f64 and
        // dual numbers, both forms, prescribed and free ends: bitwise the indexed sweep
        for form in [DragForm::Boundary, DragForm::Centre] {
            for free in [false, true] {
                let mut p = LineParams::unit_cells(7);
                p.k = Field::Constant(0.3);
                p.eta = Field::Constant(0.7);
                p.form = form;
                if free {
                    p.right = RightEnd::Free(None);
                }
                let l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
                assert!(l.contiguous().is_some());
                let u = l.uniform;
                assert!(
                    u.inv_l0.is_some() && u.mu.is_some() && u.eta.is_some() && u.k_face.is_some()
                );
                let (y, yp) = state(&l);
                let mut r = vec![0.0; y.len()];
                l.residual(0.4, &y, &yp, &mut r).unwrap();
                assert_eq!(r, reference_residual(&l, &y, &yp), "{form:?} free={free}");
                let yd: Vec<Dual64> = y.iter().map(|&v| Dual64::new(v, 0.5)).collect();
                let ypd: Vec<Dual64> = yp.iter().map(|&v| Dual64::new(v, -0.25)).collect();
                let mut rd = vec![Dual64::new(0.0, 0.0); y.len()];
                l.residual(0.4, &yd, &ypd, &mut rd).unwrap();
                for (a, b) in rd.iter().zip(reference_residual(&l, &yd, &ypd)) {
                    assert_eq!((a.re, a.eps), (b.re, b.eps));
                }
            }
        }
    }

    #[test]
    fn a_divided_line_reads_its_changed_fields() {
        // a growing line with uniform fields; cell 2 divides at g = 1.6, so its daughters have
        // L₀ = 0.8 and L₀ is no longer uniform: the residual must read the new lengths
        let mut p = LineParams::unit_cells(5);
        p.right = RightEnd::Free(None);
        p.k = Field::Constant(0.2);
        p.growth = Some(Arc::new(TanhGrowth::default()));
        let mut l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        assert!(l.uniform.inv_l0.is_some());
        let before = l.uniform;
        let mut y = l.initial_state();
        y[l.layout.gi[1]] = 1.6;
        y[l.layout.xi[2]] += 0.6;
        l.split_cell(2, 0.0, &mut y).unwrap();
        assert_eq!(l.n_cells(), 6);
        assert_eq!(l.uniform.inv_l0, None);
        let yp: Vec<f64> = (0..y.len()).map(|i| 0.01 * i as f64).collect();
        let mut r = vec![0.0; y.len()];
        l.residual(0.0, &y, &yp, &mut r).unwrap();
        assert_eq!(r, reference_residual(&l, &y, &yp));
        // and the check can fail: with the detection of before the split, cells 2 and 3
        // would be read with L₀ = 1
        let mut stale = l.clone();
        stale.uniform = before;
        let mut rs = vec![0.0; y.len()];
        stale.residual(0.0, &y, &yp, &mut rs).unwrap();
        assert_ne!(rs, r);
    }

    #[test]
    fn density_divisions_refresh_the_uniform_fields() {
        use crate::proliferation::DensityContinuum;
        use integrators::{EventAction, Problem};
        let mut p = LineParams::unit_cells(6);
        p.right = RightEnd::Free(None);
        p.k = Field::Constant(0.2);
        p.growth = Some(Arc::new(TanhGrowth::default()));
        let l = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
        let mut d = crate::ArrayProblem::new(DensityContinuum::new(l, 6, 1.5).unwrap());
        let mut y = d.array.line.initial_state();
        let gk = d.array.line.layout.gi[2];
        y[gk] = 1.5;
        let yp = vec![0.0; y.len()];
        let act = d.handle_event(0.0, &[2], &mut y, &yp).unwrap();
        assert_eq!(act, EventAction::Modified);
        let line = &d.array.line;
        assert_eq!(line.uniform.inv_l0, None);
        assert_eq!(line.uniform.k_face, None);
        let mut r = vec![0.0; y.len()];
        line.residual(0.0, &y, &yp, &mut r).unwrap();
        assert_eq!(r, reference_residual(line, &y, &yp));
    }
}
