//! Criterion bench of the hostile round's worst-case scan (2026-12-06, D2;
//! `harmonav_bench::hostile`): one `Navigator::observe_scan` of a full turn of ranges at
//! random on a fresh navigator, refused (`ContainsRobot`). Target: ≤ 10 ms for 360 beams
//! (`hostile::TARGET_US`; `cargo xtask bench --json` reports `observe_scan_hostile_us_360`).
//! Before the fix the 360-beam scan took about 40 s.

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use harmonav::NavError;
use harmonav_bench::hostile;

/// Ranges uniform in [0.05, 3] m (the round's scan at 360 beams), and in [1.9, 2.1] m (no
/// hit near the robot: the fits wall it in all round).
fn hostile_scans(c: &mut Criterion) {
    let fresh = hostile::navigator();
    let pose = hostile::pose();
    let mut group = c.benchmark_group("observe_scan/hostile");
    for (name, beams, lo, hi) in [
        ("uniform_0.05_3", 360, 0.05, 3.0),
        ("uniform_0.05_3", 3600, 0.05, 3.0),
        ("ring_1.9_2.1", 1000, 1.9, 2.1),
    ] {
        let scan = hostile::scan(beams, lo, hi);
        assert_eq!(
            fresh.clone().observe_scan(pose, &scan),
            Err(NavError::ContainsRobot),
            "{name} {beams}"
        );
        group.bench_with_input(BenchmarkId::new(name, beams), &scan, |b, scan| {
            b.iter_batched(
                || fresh.clone(),
                |mut nav| black_box(nav.observe_scan(pose, black_box(scan))),
                BatchSize::SmallInput,
            );
        });
    }
    group.finish();
}

criterion_group!(benches, hostile_scans);
criterion_main!(benches);
