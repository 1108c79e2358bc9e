//! A continuum model of the **proliferating** line (beyond the thesis: its §3.4 future work;
//! MODEL.md §3.1 notes that division "is not represented" by the growth PDE).
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
//! Then, term by term from the discrete boundary form (MODEL.md §2.2–2.4, §2.7):
//!
//! * stretch `λ = x_X/ℓ`, elastic stretch `α = λ/g = x_X/γ`, width `W = γ₀g₂/α`;
//! * drag: one boundary per `ΔX`, each with `Kκ ẋ = W(σ_{j+1} − σ_j) ≈ W σ_X/ρ`, so
//!   `K ρ κ x_t = W ∂_X σ` with `κ = (g g₂)^m = (γ g₂/ℓ)^m`;
//! * growth `ġ = G(σ)` per cell gives `γ_t = ℓ G(σ)` — the *relative* growth rate `G/g`
//!   doubles when `g` resets, which is how division accelerates elongation;
//! * division (area rule): where `g = γ/ℓ` reaches 2, `ℓ ← γ` and `ρ ← 2ρ`
//!   (so `N(t) = ∫₀^{l₀} ρ dX`). `α`, `σ_el`, `p_el` are continuous; `κ` jumps by `2^{−m}`.
//!
//! Without division (`ρ ≡ ρ₀`, `ℓ ≡ 1`) this is the growth PDE (3.48)–(3.51) of MODEL.md §3.1.
//! The division rule is *sharp*: `ρ` and `ℓ` are piecewise constant in `X` with jumps at
//! division fronts that sweep through the tissue.
//!
//! # Discretisation
//!
//! The conservative scheme (MODEL.md §3.3a) with `n` segments of width `h`: segment `i` carries
//! `g_i = γ_i/ℓ_i` in the state and `ℓ_i`, `r_i = ρ_i/ρ₀` as parameters; it is a continuum
//! [`crate::line::Line`] whose segment reference length is `hℓ_i` and whose node drag is
//! `K h ρ̄_face/L̄` (mean of the two segments' densities). A segment divides — all its
//! `r_i N₀/n` cells at once — when `g_i g₂` reaches 2 (an integrator event; no resize, only
//! `ℓ_i`, `r_i` and two drags change: [`integrators::EventAction::Modified`]). With `n = N₀`
//! and uniform cells the model before the first division is exactly the discrete model.
//!
//! # Agreement with the discrete model
//!
//! Measured by `tests/growth_proliferating_continuum.rs` (free end, σ₀ = 0.1, m = 0, N₀ = 100);
//! see the numbers there and in the report table below.
//!
//! (table filled in by the validation runs; see `AGREEMENT` in the test file)

mod density;

pub use density::DensityContinuum;
