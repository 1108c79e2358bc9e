//! Linear algebra by pattern: the iteration-matrix storage [`Matrix`] (dense, banded or sparse)
//! and [`LinearSolver`], which factorises it with the algorithm that fits the pattern:
//! dense LU (faer), banded LU with partial pivoting in O(n·b²) (hand-written: no maintained
//! crate offers one), sparse LU (faer) with the symbolic factorisation reused until the pattern
//! changes.
//!
//! Also the "complex pair" construction used by Radau IIA: the real 2n×2n matrix
//! `[[A, -B], [B, A]]` with rows/columns interleaved so that a banded pattern stays banded.

// IMPLEMENTATION NOTE: skeleton signatures fixed by the integrators design; bodies are filled in
// by the linalg work item.
