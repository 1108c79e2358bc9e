//! Adapters onto the residual form: explicit ODEs `ẏ = f(t, y)` and mass-matrix systems
//! `M(t, y)·ẏ = f(t, y)`.
