//! Criterion bench of a large ROS map's set-up (issue 52): `FloorMap::from_ros_map` on two of
//! the public maps of `scenarios/floorplans/public/`, each with its file's start, goal and
//! speck setting and the file defaults otherwise (a robot of radius 0.2 m with a 0.05 m margin,
//! `max_element` 0.2 m): loading the image, tracing and opening the free space, meshing, the
//! iterative boundary-element solve and the far field. Goal: ≤ 10 s (and ≤ 1 GB, which this
//! bench does not measure: `/usr/bin/time -v`) for a 60 × 60 m floor on the 2-core machine.
//!
//! Before 2026-12-06 `warehouse` (30 × 50 m, 144 985 elements) took about 60 s and 2.6 GB and
//! `willow-2010` (57 × 61 m, 173 983 elements) 47–112 s and 1.3 GB (docs/benchmarks.md,
//! "Public maps"). `cargo bench -p harmonav-bench --bench public_maps`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harmonav::floorplan::ros_map::MapOptions;
use harmonav::{FloorMap, FloorOptions};
use nalgebra::Vector2;

/// A public map and its file's `robot.start`, `robot.goal` and `speck_pixels`.
struct Map {
    name: &'static str,
    start: [f64; 2],
    goal: [f64; 2],
    specks: Option<usize>,
}

const MAPS: [Map; 2] = [
    Map {
        name: "warehouse",
        start: [-14.54, 6.15],
        goal: [-14.42, -24.39],
        specks: Some(0),
    },
    Map {
        name: "willow-2010",
        start: [14.75, 15.25],
        goal: [34.05, 4.15],
        specks: None,
    },
];

fn public_maps(c: &mut Criterion) {
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/public/maps");
    let mut group = c.benchmark_group("public_map_setup");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(60));
    for Map {
        name,
        start,
        goal,
        specks,
    } in MAPS
    {
        let yaml = dir.join(format!("{name}.yaml"));
        let mut options = MapOptions::new(FloorOptions::new(0.2, 0.25));
        if let Some(n) = specks {
            options.speck_pixels = n;
        }
        let (start, goal) = (Vector2::from(start), Vector2::from(goal));
        let floor = FloorMap::from_ros_map(&yaml, start, goal, &options)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        println!("{name}: {} boundary elements", floor.map().elements().len());
        group.bench_with_input(BenchmarkId::from_parameter(name), &yaml, |b, yaml| {
            b.iter(|| black_box(FloorMap::from_ros_map(yaml, start, goal, &options)));
        });
    }
    group.finish();
}

criterion_group!(benches, public_maps);
criterion_main!(benches);
