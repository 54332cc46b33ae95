//! Criterion bench of a join (issue 52, furniture against the walls; docs/maths/12-range-scans.md
//! §12.22): `FloorMap::carved`, which cuts a sensed obstacle out of `W_s` and solves `H` again,
//! on the lidar room of `scenarios/floorplans/lidar-furnished.toml` (10 × 6 m, `δ` = 0.1 m) and
//! on the public `warehouse` map (30 × 50 m, the file's defaults). The obstacle is a disc of
//! radius 0.3 m 0.1 m from the wall nearest the start. A join costs what the map's set-up costs
//! without reading and tracing the image (`public_maps`), and the caller's loop waits for it.
//! `cargo bench -p harmonav-bench --bench floor_join`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harmonav::floorplan::ros_map::MapOptions;
use harmonav::{FloorMap, FloorOptions, StarShape};
use nalgebra::Vector2;

/// A disc of radius 0.3 m whose edge is 0.1 m from the true wall nearest `start` (along the
/// shrunk walls' normal there), grown by the floor's shrink: the cut of a join.
fn furniture(floor: &FloorMap, start: Vector2<f64>) -> StarShape {
    let n = floor.toward_boundary(start).expect("start on the boundary");
    let to_wall = floor.signed_distance(start) + floor.shrink();
    let centre = start + (to_wall - 0.1 - 0.3) * n;
    StarShape::circle(centre, 0.3 + floor.shrink()).expect("a disc")
}

fn floor_join(c: &mut Criterion) {
    let v = Vector2::new;
    let room = FloorMap::new(
        vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 6.0), v(0.0, 6.0)],
        vec![vec![v(4.0, 3.8), v(4.0, 4.8), v(6.0, 4.8), v(6.0, 3.8)]],
        &FloorOptions::new(0.1, 0.2),
    )
    .expect("the lidar room");
    let yaml = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/floorplans/public/maps/warehouse.yaml");
    let mut options = MapOptions::new(FloorOptions::new(0.2, 0.25));
    options.speck_pixels = 0;
    let (start, goal) = (v(-14.54, 6.15), v(-14.42, -24.39));
    let warehouse =
        FloorMap::from_ros_map(&yaml, start, goal, &options).expect("the warehouse map");
    let cases = [
        ("lidar-room", room, v(0.8, 0.8), v(9.2, 5.2)),
        ("warehouse", warehouse, start, goal),
    ];
    let mut group = c.benchmark_group("floor_join");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(30));
    for (name, floor, start, goal) in &cases {
        let cut = [furniture(floor, *start)];
        let carved = floor.carved(&cut, *goal).expect("the join");
        println!(
            "{name}: {} boundary elements, {} after the join",
            floor.map().elements().len(),
            carved.map().elements().len()
        );
        group.bench_with_input(BenchmarkId::from_parameter(name), &cut, |b, cut| {
            b.iter(|| black_box(floor.carved(cut, *goal)));
        });
    }
    group.finish();
}

criterion_group!(benches, floor_join);
criterion_main!(benches);
