//! The line's own iteration matrix ([`Line::jacobian_into`]): one streaming sweep that
//! evaluates each cell once in dual numbers and differentiates each residual row on its stencil
//! columns, and the Jacobian's structure ([`Line::jacobian_entries`]). Tested entry by entry
//! against the coloured AD Jacobian (`tests/line_jacobian.rs`). The thesis's line takes the
//! blocked form of the same sweep (`super::blocked`), bitwise the same entries.

use super::*;
use integrators::linalg::EntrySink;

/// A cell evaluated in dual numbers for [`Line::jacobian_into`]: `s` seeded along its right
/// boundary (`x_j` with derivative 1, `v_j` with `c`), `g` seeded along its growth stretch
/// (`g_j` with 1, `ġ_j` with `c`; all derivatives zero when `g` is not an unknown).
#[derive(Clone, Copy)]
pub(super) struct LocalCell {
    pub(super) s: CellEval<Dual64>,
    pub(super) g: CellEval<Dual64>,
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

impl<E: StrainEnergy> Line<E> {
    /// The iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ` of a non-periodic line, added into `jac`
    /// (zeroed by the caller, shaped by [`CellArray::pattern`]), in one streaming sweep over
    /// the cells; `Ok(false)` for a ring (its sparse pattern is left to the coloured AD
    /// Jacobian of [`crate::ArrayProblem`]).
    ///
    /// A Maxwell branch and an external pressure are added to each evaluated cell as the
    /// residual adds them; a cell with a branch is evaluated once more seeded along its viscous
    /// stretch `a_v` (with `ȧ_v` seeded `c`), for the columns `a_v` and for its own flow row.
    /// The blocked sweep of the thesis's line never takes either.
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
        self.jacobian_rows_into(t, y, yp, c, jac, 0..=self.n_cells())
    }

    /// The rows of [`jacobian_into`](Line::jacobian_into) that belong to the cells `cells` (a
    /// cell's rows: its `g` and its right boundary `x`), added into `jac`, whose other rows are
    /// left alone: the same sweep over those cells and their neighbours only, O(k) for k
    /// cells. A division re-evaluates this way the rows around the daughters
    /// ([`crate::events::Dividing`]'s Jacobian map). `Ok(false)` where `jacobian_into` has
    /// none (a ring).
    ///
    /// ```
    /// use celltissue::line::build::{discrete, LineParams};
    /// use celltissue::{CellArray, NeoHookean};
    /// use integrators::linalg::Matrix;
    /// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(6)).unwrap();
    /// let (y, yp) = (line.initial_state(), vec![0.0; line.dim()]);
    /// let mut all = Matrix::zeros(line.dim(), &line.pattern());
    /// line.jacobian_into(0.0, &y, &yp, 1.0, &mut all).unwrap();
    /// let mut some = Matrix::zeros(line.dim(), &line.pattern());
    /// assert!(line.jacobian_rows_into(0.0, &y, &yp, 1.0, &mut some, 2..=3).unwrap());
    /// // boundaries 2 and 3 (unknowns 1 and 2) have their rows, boundary 1 has none
    /// assert_eq!((some.get(1, 0), some.get(2, 2)), (all.get(1, 0), all.get(2, 2)));
    /// assert_eq!(some.get(0, 0), 0.0);
    /// ```
    pub fn jacobian_rows_into(
        &self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
        cells: std::ops::RangeInclusive<usize>,
    ) -> Result<bool, ResidualError> {
        if self.right.is_periodic() {
            return Ok(false);
        }
        let n = self.n_cells();
        let (lo, hi) = (*cells.start(), (*cells.end()).min(n));
        if n == 0 || lo > hi {
            return Ok(true);
        }
        if lo <= 1 && hi == n {
            if let Some(done) = self.jacobian_blocked(t, y, yp, c, jac) {
                return done.map(|()| true);
            }
        }
        let mine = |cell: usize| (lo..=hi).contains(&cell);
        let lay = &self.layout;
        let d = Dual64::new;
        // a boundary row needs the cells on both sides (and one more with the centre form)
        let first = lo.saturating_sub(1).max(1);
        let last = (hi + 1).min(n);
        let mut left = self.boundary(first - 1, t, y, yp);
        // the last three cells in a ring (cell j at j mod 3: moving them would copy 1 KB per cell)
        let mut win: [LocalCell; 3] = [LocalCell::default(); 3];
        // with a Maxwell branch, the same cells seeded along their viscous stretch
        let mut win_v: [CellEval<Dual64>; 3] = [LocalCell::default().s; 3];
        let extended = self.uniform.extended;
        let branch = self.maxwell.is_some();
        // the viscous-seeded cells of a row's window, when the line has a branch
        macro_rules! viscous {
            ($($w:expr),*) => {
                branch.then(|| [$(&win_v[$w]),*])
            };
        }
        for cell in first..=last {
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
            let vk = if branch { lay.vi[cell - 1] } else { NONE };
            if extended {
                // the branch and the external pressure, as the residual adds them, in place
                // (a copy of the evaluations costs a call to memcpy per cell): with the
                // viscous stretch held, then seeded on its own
                let here = &mut win[w2];
                let av = if vk == NONE { 1.0 } else { y[vk] };
                let mut sv = here.s.along(Dir::Zero, c);
                self.extend_cell(cell, &mut here.s, d(av, 0.0))?;
                self.extend_cell(cell, &mut here.g, d(av, 0.0))?;
                if vk != NONE {
                    self.extend_cell(cell, &mut sv, d(av, 1.0))?;
                }
                win_v[w2] = sv;
            }
            if vk != NONE && mine(cell) {
                if let Some(b) = &self.maxwell {
                    self.emit_flow_row(jac, b, cell, (y[vk], yp[vk]), &win[w2], &win_v[w2], c);
                }
            }
            if gk != NONE && mine(cell) {
                if let Some(law) = &self.growth {
                    let ypg = yp[gk];
                    self.emit(jac, gk, cell, [&win[w2]], viscous!(w2), c, |e| {
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
            if row == NONE || !mine(b) {
                continue;
            }
            match self.form {
                DragForm::Boundary => {
                    let cells = [&win[w1], &win[w2]];
                    self.emit(jac, row, b, cells, viscous!(w1, w2), c, |e| {
                        self.boundary_row(b, &e[0], &e[1])
                    })
                }
                DragForm::Centre if b >= 2 => {
                    let cells = [&win[w0], &win[w1], &win[w2]];
                    self.emit(jac, row, b - 1, cells, viscous!(w0, w1, w2), c, |e| {
                        let f_prev = self.face_force(&e[0], &e[1]);
                        let f = self.face_force(&e[1], &e[2]);
                        self.centre_row(b, &e[1], f_prev, f)
                    })
                }
                DragForm::Centre => {
                    let cells = [&win[w1], &win[w2]];
                    self.emit(jac, row, b, cells, viscous!(w1, w2), c, |e| {
                        let f = self.face_force(&e[0], &e[1]);
                        self.centre_row(b, &e[0], d(0.0, 0.0), f)
                    })
                }
            }
        }
        if self.right.is_free() && mine(n) {
            let row = lay.xi[n];
            let (w1, w2) = ((n + 2) % 3, n % 3);
            match self.form {
                DragForm::Centre if n >= 2 => {
                    let cells = [&win[w1], &win[w2]];
                    self.emit(jac, row, n - 1, cells, viscous!(w1, w2), c, |e| {
                        let f_prev = self.face_force(&e[0], &e[1]);
                        self.end_row(t, &e[1], f_prev)
                    })
                }
                _ => self.emit(jac, row, n, [&win[w2]], viscous!(w2), c, |e| {
                    self.end_row(t, &e[0], d(0.0, 0.0))
                }),
            }
        }
        Ok(true)
    }

    /// Adds row `row` of the Jacobian: `f` (a row expression of the residual) is evaluated
    /// once per unknown the `Q` consecutive cells `first..first + Q` depend on — their
    /// boundaries `first − 1 ..= first + Q − 1`, when growing their `g`, and with `viscous`
    /// (the cells seeded along their viscous stretches) their `a_v` — with every cell's
    /// derivatives projected on that unknown; the dual part is the entry.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn emit<J: EntrySink, const Q: usize>(
        &self,
        jac: &mut J,
        row: usize,
        first: usize,
        cells: [&LocalCell; Q],
        viscous: Option<[&CellEval<Dual64>; Q]>,
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
        if let Some(viscous) = viscous {
            for k in 0..Q {
                let col = lay.vi.get(first + k - 1).copied().unwrap_or(NONE);
                if col == NONE {
                    continue;
                }
                let mut e = [cells[0].s; Q];
                for q in 0..Q {
                    e[q] = if q == k {
                        *viscous[q]
                    } else {
                        cells[q].along(Dir::Zero, c)
                    };
                }
                jac.add(row, col, f(&e).eps);
            }
        }
    }

    /// Adds the flow row of cell `cell`'s viscous stretch, `ȧ_v − rate(a_v, σ_b(α, a_v))`, at
    /// `(a_v, ȧ_v) = av`: its columns are the cell's two boundaries and `g` (through `α`, from
    /// `local`) and `a_v` itself (from `viscous`, the cell seeded along `a_v`, with `ȧ_v`
    /// seeded `c`).
    #[allow(clippy::too_many_arguments)]
    fn emit_flow_row<J: EntrySink>(
        &self,
        jac: &mut J,
        b: &MaxwellBranch,
        cell: usize,
        (av, avd): (f64, f64),
        local: &LocalCell,
        viscous: &CellEval<Dual64>,
        c: f64,
    ) {
        let lay = &self.layout;
        let row = lay.vi[cell - 1];
        let held = |e: &CellEval<Dual64>| {
            self.flow_row(b, Dual64::new(av, 0.0), Dual64::new(avd, 0.0), e)
                .eps
        };
        for (col, dir) in [(lay.xi[cell - 1], Dir::Left), (lay.xi[cell], Dir::Right)] {
            if col != NONE {
                jac.add(row, col, held(&local.s.along(dir, c)));
            }
        }
        if lay.gi[cell - 1] != NONE {
            jac.add(row, lay.gi[cell - 1], held(&local.g));
        }
        let own = self.flow_row(b, Dual64::new(av, 1.0), Dual64::new(avd, c), viscous);
        jac.add(row, row, own.eps);
    }

    /// Structural entries `(row, col)` of the Jacobian, from the stencil (an entry may be
    /// listed more than once).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// // x₁, x₂, x₃ each couple to their neighbours: a tridiagonal 3 × 3 pattern
    /// let mut e = line.jacobian_entries();
    /// e.sort();
    /// e.dedup(); // an entry may be listed more than once
    /// assert_eq!(e, [(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2)]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn jacobian_entries(&self) -> Vec<(usize, usize)> {
        let mut entries = Vec::new();
        self.for_each_jacobian_entry(|i, j| entries.push((i, j)));
        entries
    }

    /// Calls `f(row, col)` for every structural entry of the Jacobian (with repeats), without
    /// storing them: the banded pattern of a long line needs only the widest offsets, and a
    /// list of the 10⁷ entries of a 10⁶-cell line would be 100+ MB of fresh memory.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let mut count = 0;
    /// line.for_each_jacobian_entry(|_, _| count += 1);
    /// assert_eq!(count, line.jacobian_entries().len());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_each_jacobian_entry(&self, f: impl FnMut(usize, usize)) {
        let n = self.n_cells();
        self.for_each_jacobian_entry_in(1..=n, 0..=n, f);
    }

    /// [`for_each_jacobian_entry`](Self::for_each_jacobian_entry) restricted to the rows of
    /// the cells in `cells` (their growth and viscous-stretch rows) and of the boundaries in
    /// `boundaries` (their position rows).
    pub(crate) fn for_each_jacobian_entry_in(
        &self,
        cells: std::ops::RangeInclusive<usize>,
        boundaries: std::ops::RangeInclusive<usize>,
        mut f: impl FnMut(usize, usize),
    ) {
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
        for c in cells.filter(|c| (1..=n).contains(c)) {
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
        for b in boundaries.filter(|b| *b <= n) {
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
