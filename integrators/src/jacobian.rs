//! Building the iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ` from the declared pattern: coloured
//! exact directional derivatives (AD) or coloured finite differences — one evaluation per
//! colour (bandwidth+1 for banded), never one per column.
