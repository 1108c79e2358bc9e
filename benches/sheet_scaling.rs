//! Cost of the discrete uniaxial sheet vs N·M (MODEL.md §4.1; free top, K = ½, m = 0,
//! neo-Hookean, BDF rtol 1e-6, atol 1e-8 in cell units), integrated to t = 10.
//! Run: `cargo bench --bench sheet_scaling`. The 1000 × 1000 case is the example
//! `cargo run --release --example sheet_large -- 1000 10`.

use celltissue::array::ArrayProblem;
use celltissue::sheet::uniaxial::{SheetParams, UniaxialSheet};
use celltissue::NeoHookean;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use integrators::{MethodKind, Options, Solver};

fn run(n: usize) -> usize {
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
    for n in [10usize, 20, 50, 100] {
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_with_input(
            BenchmarkId::from_parameter(format!("{n}x{n}")),
            &n,
            |b, &n| b.iter(|| run(n)),
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
