//! Criterion benches of the potential: a single gradient (M = 6) and the batched kernel
//! (M ∈ {6, 20, 100, 1000}, N = 4096). `cargo xtask bench --json` reports the headline figures.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use harmonav_potential::{BatchGradient, PointWorld, Vector2, arrangements};

/// The golden-spiral benchmark world of `m` points and `n` query points between them.
fn setup(m: usize, n: usize) -> (PointWorld, Vec<f64>, Vec<f64>) {
    let world = arrangements::golden_spiral(m);
    let hx = (0..n)
        .map(|i| -3.0 + 6.0 * ((i * 7919) % n) as f64 / n as f64 + 1e-3)
        .collect();
    let hy = (0..n)
        .map(|i| -3.0 + 6.0 * i as f64 / n as f64 + 2e-3)
        .collect();
    (world, hx, hy)
}

fn single(c: &mut Criterion) {
    let (world, hx, hy) = setup(6, 64);
    let mut i = 0;
    c.bench_function("grad_phi_k/single/m6", |b| {
        b.iter(|| {
            i = (i + 1) % 64;
            black_box(world.grad_phi_k(black_box(Vector2::new(hx[i], hy[i]))))
        })
    });
}

fn batch(c: &mut Criterion) {
    let n = 4096;
    let mut group = c.benchmark_group("grad_phi_k/batch");
    for m in [6, 20, 100, 1000] {
        let (world, hx, hy) = setup(m, n);
        let kernel = BatchGradient::new(&world);
        let (mut gx, mut gy) = (vec![0.0; n], vec![0.0; n]);
        group.throughput(Throughput::Elements((m * n) as u64));
        group.bench_with_input(BenchmarkId::new("n4096", m), &m, |b, _| {
            b.iter(|| {
                kernel
                    .eval(&hx, &hy, &mut gx, &mut gy)
                    .expect("regular points")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, single, batch);
criterion_main!(benches);
