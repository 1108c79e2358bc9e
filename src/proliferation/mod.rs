//! A continuum model of the **proliferating** line (beyond the thesis: its §3.4 future work;
//! docs/model.md §3.1 notes that division "is not represented" by the growth PDE).
//!
//! Two models live here: [`DensityContinuum`], a density of cells in the material coordinate
//! (derived below), and [`travelling_rim`], the long-time rim of a free end under strong drag in
//! the cell-number coordinate, where the material coordinate fails (module [`rim`]).
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
//! `K h ρ̄_face/L̄` (mean of the two segments' densities). A segment divides — all its
//! `r_i N₀/n` cells at once — when `g_i g₂` reaches 2 (an integrator event; no resize, only
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
//!      (n = 200, t = 18) `N` is 914 against 971 (−5.9 %) and `l` 1313 against 1383 (−5.1 %):
//!      the continuum lags because the staggered division of neighbouring cells (each restarting
//!      fast relative growth `G/g` as soon as it divides) is replaced by one late event per
//!      segment. Refining `n` with `N` (h ≲ 1/ρ) restores agreement, at the discrete cost.
//!      Measured drift (K = 1e-5, `tests/growth_proliferating_continuum.rs`,
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
//!      McKendrick–von Foerster equation in `g` coupled to the mechanics) — not implemented;
//!      the runner rejects non-area rules for the continuum.

mod density;
pub mod rim;

pub use density::DensityContinuum;
pub use rim::{rim_profile, travelling_rim, RimError, RimSpeed};
