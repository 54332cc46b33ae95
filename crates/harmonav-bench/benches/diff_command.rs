//! Criterion bench of one command of a differential-drive base (issue 53: target ≤ 30 µs per
//! command, release build; `harmonav_bench::diff::TARGET_US`) and of a command with 20 movers
//! (issue 54: within reach ≤ 20 µs, out of reach within 1 µs of none). `cargo xtask bench
//! --only diff_command` and `--only navigator_command` report the same figures as medians
//! (docs/benchmarks.md, "Per-call cost").
//!
//! Each `command_pose` figure replays the poses of a closed-loop flight in order on a fresh
//! copy of the navigator (the copy made outside the timing) and is reported per flight; divide
//! by the commands it printed for the cost of one.

use std::hint::black_box;
use std::path::Path;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use harmonav::{Navigator, World};
use harmonav_bench::diff::{self, Flight};

fn replay_group<W: World + Clone>(c: &mut Criterion, name: &str, flight: &Flight<W>) {
    let mut group = c.benchmark_group("command_pose");
    group.throughput(Throughput::Elements(flight.poses.len() as u64));
    eprintln!(
        "command_pose/{name}: {} commands per flight, arrived {}",
        flight.poses.len(),
        flight.arrived
    );
    group.bench_function(BenchmarkId::new(name, flight.poses.len()), |b| {
        b.iter_batched(
            || flight.nav.clone(),
            |mut nav: Navigator<W>| black_box(diff::replay(&mut nav, &flight.poses, None)),
            BatchSize::SmallInput,
        );
    });
    group.finish();
}

fn command_pose(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for accel in [false, true] {
        let suffix = if accel { "_accel" } else { "" };
        let discs = diff::disc_world(accel).expect("the disc world flies");
        replay_group(c, &format!("discs10{suffix}"), &discs);
        let floor = diff::floor_plan(&root, accel).expect("the L room flies");
        replay_group(c, &format!("floor_l_room{suffix}"), &floor);
    }
    // With 20 movers set before each command (no acceleration limits).
    let discs = diff::disc_world(false).expect("the disc world flies");
    let inflation = discs.nav.options().inflation();
    for near in [false, true] {
        let rings: Vec<_> = discs
            .poses
            .iter()
            .map(|&(x, _)| diff::ring(x, inflation, near))
            .collect();
        let name = if near {
            "movers_20_near"
        } else {
            "movers_20_far"
        };
        let mut group = c.benchmark_group("command_pose");
        group.throughput(Throughput::Elements(discs.poses.len() as u64));
        group.bench_function(
            BenchmarkId::new(format!("discs10_{name}"), discs.poses.len()),
            |b| {
                b.iter_batched(
                    || discs.nav.clone(),
                    |mut nav| black_box(diff::replay(&mut nav, &discs.poses, Some(&rings))),
                    BatchSize::SmallInput,
                );
            },
        );
        group.finish();
    }
}

/// The holonomic `Navigator::command` of the kinematic law with 20 movers set before it
/// (`navigator_command_ns_m6_kinematic_movers_20_*` of `cargo xtask bench`), and without.
fn command_movers(c: &mut Criterion) {
    let (fresh, states) = diff::control_world();
    let inflation = fresh.options().inflation();
    let mut group = c.benchmark_group("command/kinematic_m6");
    group.throughput(Throughput::Elements(states.len() as u64));
    group.bench_function("no_movers", |b| {
        let mut nav = fresh.clone();
        b.iter(|| {
            for &(x, v) in &states {
                let _ = black_box(nav.command(black_box(x), black_box(v)));
            }
        });
    });
    for (name, near) in [("movers_20_far", false), ("movers_20_near", true)] {
        let rings: Vec<_> = states
            .iter()
            .map(|&(x, _)| diff::ring(x, inflation, near))
            .collect();
        group.bench_function(name, |b| {
            let mut nav = fresh.clone();
            b.iter(|| {
                for (&(x, v), m) in states.iter().zip(&rings) {
                    let _ = nav.set_movers(m);
                    let _ = black_box(nav.command(black_box(x), black_box(v)));
                }
            });
        });
    }
    group.finish();
}

criterion_group!(benches, command_pose, command_movers);
criterion_main!(benches);
