//! The static equilibrium of a long line whose every cell has its own μ (a Gaussian bump,
//! (2.82)), held 10 % short: the solve behind the quasi-static overlay of a run's plots, timed.
//!
//! `cargo run --release --example static_equilibrium_large -- 1000000` prints the solve's
//! time, the common stress and the smallest stretch (BENCHMARKS.md, "The write phase").

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::Field;
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::static_solve::static_equilibrium;
use celltissue::NeoHookean;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 1_000_000,
    };
    let mut p = LineParams::unit_cells(n);
    p.mu = Field::gaussian_bump(1.0, 1.0, 0.5, 0.1);
    p.right = RightEnd::Prescribed(Ramp::Constant(0.9 * n as f64));
    let line = discrete(NeoHookean::new(1.0)?, &p)?;
    let start = std::time::Instant::now();
    let s = static_equilibrium(&line, 0.9 * n as f64)?;
    println!(
        "N = {n}: {:.3} s, stress {:.15}, smallest stretch {:.15}",
        start.elapsed().as_secs_f64(),
        s.stress,
        s.min_stretch()
    );
    Ok(())
}
