//! A continuum model of the **proliferating** line (beyond the thesis: its §3.4 future work;
//! docs/model.md §3.1 notes that division "is not represented" by the growth PDE).
//!
//! Three models live here: [`DensityContinuum`], a density of cells in the material coordinate
//! (derived below); [`CellGrid`], a grid in the cell-number coordinate whose segments hold whole
//! cells, which holds where the density fails (see "A grid in the cell-number coordinate"
//! below); and [`travelling_rim`], the long-time rim of a free end under strong drag as a steady
//! profile in the cell-number coordinate (module [`rim`]).
//!
//! # Derivation
//!
//! Label material points by their initial position `X ∈ [0, l₀]`. Division splits a cell at its
//! midpoint; a cell is homogeneously stretched, so the midpoint in `x` is the midpoint in `X`,
//! and material points never move across boundaries. After `k` divisions a cell descending from
//! an initial unit cell occupies `ΔX = 2^{−k}`. Define, per unit `X`:
//!
//! * the cell density `ρ(X,t) = 1/ΔX` (cells per unit reference length; `ρ₀ = N₀/l₀`);
//! * the grown length `γ(X,t) = L₀g/ΔX` (continuous through a division: `L₀g → 2·(L₀g/2)` over
//!   `ΔX → ΔX/2`);
//! * the current cells' reference length `ℓ(X,t) = L₀/ΔX`, so the cells' growth stretch is
//!   `g = γ/ℓ`.
//!
//! Then, term by term from the discrete boundary form (docs/model.md §2.2–2.4, §2.7):
//!
//! * stretch `λ = x_X/ℓ`, elastic stretch `α = λ/g = x_X/γ`, width `W = γ₀g₂/α`;
//! * drag: one boundary per `ΔX`, each with `Kκ ẋ = W(σ_{j+1} − σ_j) ≈ W σ_X/ρ`, so
//!   `K ρ κ x_t = W ∂_X σ` with `κ = (g g₂)^m = (γ g₂/ℓ)^m`;
//! * growth `ġ = G(σ)` per cell gives `γ_t = ℓ G(σ)` — the *relative* growth rate `G/g`
//!   doubles when `g` resets, which is how division accelerates elongation;
//! * division (area rule): where `g = γ/ℓ` reaches 2, `ℓ ← γ` and `ρ ← 2ρ`
//!   (so `N(t) = ∫₀^{l₀} ρ dX`). `α`, `σ_el`, `p_el` are continuous; `κ` jumps by `2^{−m}`.
//!
//! Without division (`ρ ≡ ρ₀`, `ℓ ≡ 1`) this is the growth PDE (3.48)–(3.51) of docs/model.md §3.1.
//! The division rule is *sharp*: `ρ` and `ℓ` are piecewise constant in `X` with jumps at
//! division fronts that sweep through the tissue.
//!
//! # Discretisation
//!
//! The conservative scheme (docs/model.md §3.3a) with `n` segments of width `h`: segment `i` carries
//! `g_i = γ_i/ℓ_i` in the state and `ℓ_i`, `r_i = ρ_i/ρ₀` as parameters; it is a continuum
//! [`crate::line::Line`] whose segment reference length is `hℓ_i` and whose node drag is
//! `K h ρ̄_face/L̄` (mean of the two segments' densities; for cells of unequal reference
//! lengths the initial boundaries each node carries, docs/model.md §3.3). A segment divides —
//! all its `r_i c_i` cells at once (`c_i` its initial cells, `N₀/n` for equal cells,
//! [`crate::line::build::segment_cells`]) — when `g_i g₂` reaches 2 (an integrator event; no resize, only
//! `ℓ_i`, `r_i` and two drags change: [`integrators::EventAction::Modified`]). With `n = N₀`
//! and uniform cells the model before the first division is exactly the discrete model.
//!
//! # Agreement with the discrete model
//!
//! Free end, σ₀ = 0.1, m = 0, N₀ = 100, area rule, BDF rtol 1e-8
//! (`tests/growth_proliferating_continuum.rs`); max relative error over `t ∈ [2.5, 10]`:
//!
//! | K | n | error in `l(t)` | error in `N(t)` |
//! |---|---|---|---|
//! | 1e-5 | 50 | 3.2e-2 | 3.5e-2 |
//! | 1e-5 | 100 | 1.6e-2 | 1.8e-2 |
//! | 1e-5 | 200 | 6.7e-3 | 6.6e-3 |
//! | 1e-2 | 50 | 3.8e-2 | 2.8e-2 |
//! | 1e-2 | 100 | 2.2e-2 | 2.8e-2 |
//! | 1e-2 | 200 | 1.1e-2 | 1.4e-2 |
//!
//! * **Where it works.** At K = 1e-5 the first division wave (t = 2.0–2.6) and the plateau
//!   `N = 200` are reproduced exactly for n ≥ 100 (`N(3) = 200`, `N(5) = 248`, `N(6) = 288`
//!   as in the discrete model); the division fronts `x_d/l(t)` of the scenario `fig3_3` lie on
//!   the discrete waves, including the kink near t ≈ 8 where waves overlap. The error is first
//!   order in `h` (it halves from n = 100 to 200).
//! * **Where it fails.**
//!   1. *Long times with fixed n*: a segment holds `r_i N₀/n` cells that all divide at once, so
//!      as the density doubles the division front is resolved ever more coarsely. In `fig3_3`
//!      (n = 200, t = 18) `N` is 914 against 971 (−5.9 %) and `l` 1313 against 1383 (−5.1 %).
//!      Most of that lag is not the division front but the free end's drag: the discrete line's
//!      tip boundary carries half a cell of drag beyond the distributed drag (docs/model.md
//!      §3.3a, "The free end's drag"), which the default end node (`free_end_drag =
//!      "segment"`) drops. With `free_end_drag = "cells"` the end node keeps that half cell at
//!      one boundary whatever the density, and at rtol 1e-8 the gap at t = 6 / 10 / 14 / 18 is,
//!      n = 200: `l` −0.00 % / −0.01 % / −0.06 % / −0.59 %, `N` 0 / +0.18 % / +0.40 % /
//!      +1.13 %; n = 400: `l` +0.00 % / −0.00 % / −0.01 % / −0.16 %, `N` +0.17 % / +0.18 % /
//!      +0.67 % / −1.13 % (`tests/line_continuum_free_end_drag.rs`). What is left is the
//!      division front: the staggered division of neighbouring cells (each restarting fast
//!      relative growth `G/g` as soon as it divides) replaced by one event per segment, which
//!      refining `n` with `N` (h ≲ 1/ρ) removes, at the discrete cost. Over the scenario's 80
//!      output times to t = 18 (n = 200, rtol 1e-6) the largest gaps with "cells" are, at
//!      K = 1e-5 / 1e-4 / 1e-3 / 1e-2, 0.59 / 1.8 / 2.7 / 1.9 % in `l` and 2.8 / 5.9 / 4.6 /
//!      3.7 % in `N` (the discrete `N` rises in steps), against 5.1 / 7.4 / 8.0 / 5.1 % and
//!      7.1 / 12 / 11 / 3.7 % with "segment". With the default end node, the measured drift
//!      (K = 1e-5, `tests/growth_proliferating_continuum.rs`,
//!      `long_run_drift_at_fixed_n`), relative error at t = 6 / 10 / 14 / 18: n = 200: `l`
//!      −0.06 % / −0.67 % / −2.3 % / −5.1 %, `N` 0 / −0.55 % / −2.0 % / −5.9 %; n = 400: `l`
//!      +0.10 % / −0.19 % / −1.1 % / −3.2 %, `N` +0.17 % / −0.18 % / −0.80 % / −2.0 %. The lag
//!      roughly triples every 4 time units (one division generation doubles the cells per
//!      segment) and is first order in `h` for `N`, weaker for `l` (×0.62 from n = 200 to 400).
//!   2. *Large drag (K = 1e-2), a proliferating rim*: only 9 divisions by t = 10, all within a
//!      few cells of the free end; `N` is then an integer of order 100 and a continuum can only
//!      represent it to ±(cells per segment) — errors of 1–3 % in `N` and `l` for n ≤ 200, and
//!      the free-end cell (which divides first, at t = 2.5824) is smeared over a segment.
//!      At long times it fails outright (t = 1000: 419 against 1 637 cells, n = 200): the rim's
//!      cells all descend from the last initial cell, so the rim lives in a sliver of `X` that
//!      halves with every division at the tip, and the last segment ends up holding 256 cells
//!      that share one compressed mean stress and hardly grow. No fixed grid in `X` resolves
//!      that; in the cell-number coordinate the rim is a travelling wave whose speed
//!      [`travelling_rim`] predicts to 0.36 % (docs/model.md §8.4).
//!   3. *Asynchronous populations* (random thresholds, age rules with scattered births) have no
//!      sharp front; this model would need a size-structured density `n(X, g, t)` (a
//!      McKendrick–von Foerster equation in `g` coupled to the mechanics). The runner rejects
//!      non-area rules for it; the cell-number grid below takes them.
//!
//! # A grid in the cell-number coordinate
//!
//! The density continuum fixes the material width of its segments, so the number of cells per
//! segment doubles with each division there. [`CellGrid`] fixes the number of cells per segment
//! instead: a segment of `c` cells that reaches `g = 2` splits into two segments of `c` cells
//! (the discrete model's split, [`crate::events::Dividing`]), so the grid is uniform in the
//! cell number `u` and follows the rim wherever it goes. A segment stands for `c` boundaries;
//! lumping their drags on its faces gives `K c` at an interior face and `K (c + 1)/2` at a free
//! end (the tip boundary itself plus half of the others: the tip's "half a cell" of §8.4).
//! `c = 1` is the discrete model, step for step.
//!
//! Two errors remain, and they differ in kind:
//!
//! * A segment's `c` cells divide at one instant. Over `t ≤ 18` that costs little: with
//!   `c = 2`, `l(t)` is within 3.0e-5 / 1.3e-4 / 8.0e-4 / 3.4e-3 and `N(t)` within 0.4 / 1.1 /
//!   1.5 / 1.9 % at K = 1e-5 / 1e-4 / 1e-3 / 1e-2, for half the steps
//!   (`tests/proliferation_cell_grid.rs`). It converges in `c`: at K = 1e-5, `l` errs by
//!   3.0e-5 / 1.3e-4 / 6.5e-4 and `N` by 0.38 / 0.96 / 2.1 % for `c` = 2 / 4 / 10 (observed
//!   orders 2.1 and 1.7 in `l`, 1.4 and 0.8 in `N`).
//! * Under strong drag the rim's division pattern is a property of single cells (at
//!   K = 1e-2 the tip divides at depths 1, 3, 7 and 12 in a fixed cycle, docs/model.md §8.4),
//!   and the phases the cells keep when they stop growing set `N`. With `c = 2` to t = 1000,
//!   `l` stays within 1.1 % but `N` is off by 21 % (12 % with merging). So the rim needs
//!   `c = 1` where cells grow.
//!
//! What makes `c = 1` affordable is that few cells grow. With [`Coarsening`], neighbouring
//! segments whose growth rate has fallen below a fraction θ of `G(0)` merge (up to
//! `max_cells` cells). A merged segment keeps its length, `Σ L₀g` and `Σ L₀` (so the growth of
//! length), and it keeps each member's growth stretch as a constant offset from its own `g`:
//! the members share its stress, so they grow alike. When a member reaches the rule it divides
//! inside the segment, whose reference length and cell count grow (no resize). The only
//! approximation is that shared stress. At K = 1e-2, t ≤ 1000 (1 637 cells):
//!
//! | θ | segments at t = 1000 | error in `l(t)` | error in `N(t)` | divisions with `x/l > 0.9` after t = 100 |
//! |---|---|---|---|---|
//! | discrete | 1 637 | — | — | 99.86 % |
//! | 1e-2 | 87 | 1.0e-4 | 0.40 % | 99.64 % |
//! | 1e-3 | 236 | 1.2e-6 | 0 (every output time) | 99.86 % |
//!
//! Where the cells are added, counted by tenths of the line, is the discrete line's to 1.3e-3
//! at θ = 1e-2 and exactly at θ = 1e-3; at t ≤ 18 with `c = 2` to 0.010 and 0.005 at K = 1e-5
//! and 1e-4. The error falls with θ; θ = 0 is the discrete model. The steps are the discrete
//! model's (divisions set them), but each costs in proportion to the segments. Soft cells (μ = 0.5),
//! which keep growing and dividing behind the rim: θ = 1e-3 ends with 2 143 cells against
//! 2 142 and `l` within 2e-7, on 302 segments; θ = 1e-2 with 2 117 (−1.2 %) on 96
//! (`celltissue run models/fig3_3d_cell_grid.toml --set model.mu=0.5`).
//!
//! *Any rule.* Under the area and age rules the cells born together stay in phase, and a
//! segment divides as one (age rule, period 2.5, `c = 2`, t ≤ 8: `N` exact, `l` within 4e-5 at
//! K = 1e-5 and 4.1e-3 at K = 1e-2). A rule that draws a threshold per cell makes
//! [`CellGrid::asynchronous`]: each segment starts as `c` single-cell members with their own
//! thresholds, which divide one by one inside it (the merged segments' mechanism, a daughter
//! drawing its own threshold), and a growing segment that has doubled its cells splits at its
//! middle member. That is the mean-field closure: the cells of a segment share its stress and
//! keep their own phases. Against 64 discrete realisations of `models/fig3_3_ensemble.toml`
//! (U[1.8, 2.2], K = 1e-5, t ≤ 12) the ensemble means of `N` agree within sampling error and
//! those of `l` within 1.3e-3 for `c` = 2, 4, 10, on 0.87 / 0.68 / 0.46 of the discrete steps.
//!
//! *Merging in phase.* At small K every cell grows, so merging where cells stop growing does
//! nothing, and the grid with `c = 1` is the discrete line. There neighbours bear nearly the
//! same stress and grow alike: with [`Coarsening::stress_within`] = ε, neighbours whose
//! stresses differ by at most ε of the growth law's stress scale merge too, and a merged
//! segment splits again once the stress across it exceeds 4ε of it, so the grid follows the
//! stress profile. At K = 1e-8, N₀ = 100 → 6 400 cells (t ≤ 14), ε = 1e-3: 203 segments at
//! the end, `l` within 1.2e-4 and `N` within 4.3e-4, 27× less time than the discrete line;
//! at K = 1e-5 (t ≤ 18), ε = 1e-2: 92 segments, `l` within 3.6e-4, `N` within 1.2 %
//! (docs/model.md §8.4).
//!
//! *Where it ends.* The merged members' shared stress is the error θ and ε control; the
//! segments a given ε needs grow with the stress's range along the line. It is a
//! scenario option, `division.cell_grid`, and a library type
//! (`CellGrid::new(continuum(..), n0, rule)`, or `CellGrid::with_cell_lengths(cell_groups(..), ..)`
//! for cells of unequal reference lengths).

mod cell_grid;
mod density;
mod members;
pub mod rim;

pub use cell_grid::{CellGrid, Coarsening, Member};
pub use density::DensityContinuum;
pub use rim::{rim_profile, travelling_rim, RimError, RimSpeed};
