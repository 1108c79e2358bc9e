//! Cost of the discrete uniaxial sheet vs N·M (docs/model.md §4.1; free top, K = ½, m = 0,
//! neo-Hookean, BDF rtol 1e-6, atol 1e-8 in cell units, max error norm), integrated to t = 10,
//! with the sparse direct LU (`direct/…`) and with ILU(0) + BiCGStab (`iterative/…`, default
//! [`IterativeSettings`]: BDF's Newton-aware stopping rule).
//! Run: `cargo bench --bench sheet_scaling`. The large cases are the example
//! `LINSOLVE=iterative cargo run --release --example sheet_large -- 1000 10` (raw parameters) and
//! `FAMILY=macro LINSOLVE=iterative cargo run --release --example sheet_large -- 1000` (the
//! macroscale-fixed family).

use celltissue::array::ArrayProblem;
use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
use celltissue::NeoHookean;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use integrators::{ErrorNorm, IterativeSettings, LinearSolverChoice, MethodKind, Options, Solver};

fn run(n: usize, linear_solver: LinearSolverChoice) -> usize {
    let law = NeoHookean::new(1.0).unwrap();
    let p = SheetParams {
        cells_x: n,
        cells_y: n,
        ..Default::default()
    };
    let sheet = UniaxialSheet::discrete(law, &p)
        .unwrap()
        .with_cell_atol(1e-8);
    let y0 = sheet.initial_state();
    let mut prob = ArrayProblem::new(sheet);
    let opts = Options {
        rtol: 1e-6,
        atol: 1e-8,
        norm: ErrorNorm::Max,
        linear_solver,
        ..Options::default()
    };
    let sol = Solver::new(MethodKind::Bdf, opts)
        .solve(&mut prob, 0.0, &y0, &[10.0])
        .expect("sheet solve");
    sol.stats.steps
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("sheet_to_t10");
    g.sample_size(10);
    let iterative = LinearSolverChoice::Iterative(IterativeSettings::default());
    for (name, choice) in [
        ("direct", LinearSolverChoice::Direct),
        ("iterative", iterative),
    ] {
        for n in [10usize, 20, 50, 100] {
            g.throughput(Throughput::Elements((n * n) as u64));
            g.bench_with_input(BenchmarkId::new(name, format!("{n}x{n}")), &n, |b, &n| {
                b.iter(|| run(n, choice))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
