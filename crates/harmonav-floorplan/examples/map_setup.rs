//! Where a ROS map's set-up goes: `cargo run --release -p harmonav-floorplan --example
//! map_setup -- MAP.yaml SX SY GX GY [SPECK_PIXELS]` prints the time of each stage (load, free
//! space, `FloorMap::new` with the harmonic map's own split: mesh, assembly, GMRES iterations,
//! far field, and the rest: the layer's edge and its images) for a robot of radius 0.2 m with a
//! 0.05 m margin and the default `max_element` 0.2 m, as the files of
//! `scenarios/floorplans/public/` (run it from that folder with `maps/NAME.yaml`). Peak memory:
//! `/usr/bin/time -v`; a profile: `perf record -g` on the release binary.

use std::time::Instant;

use harmonav_floorplan::ros_map::{MapOptions, RosMap};
use harmonav_floorplan::{FloorMap, FloorOptions};
use nalgebra::Vector2;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 5 {
        return Err("usage: map_setup MAP.yaml SX SY GX GY [SPECK_PIXELS]".into());
    }
    let num = |i: usize| args[i].parse::<f64>();
    let start = Vector2::new(num(1)?, num(2)?);
    let goal = Vector2::new(num(3)?, num(4)?);
    let mut options = MapOptions::new(FloorOptions::new(0.2, 0.25));
    if let Some(s) = args.get(5) {
        options.speck_pixels = s.parse()?;
    }
    let clock = Instant::now();
    let ros = RosMap::load(&args[0])?;
    let load = clock.elapsed();
    let clock = Instant::now();
    let space = ros.free_space(start, goal, &options)?;
    let outline = clock.elapsed();
    let vertices: usize = space.outer.len() + space.holes.iter().map(Vec::len).sum::<usize>();
    let clock = Instant::now();
    let floor = FloorMap::new(space.outer, space.holes, &options.floor)?;
    let total = clock.elapsed();
    let c = floor.map().setup_cost();
    println!(
        "load {:.3} s, outline {:.3} s ({} holes, {vertices} vertices), FloorMap::new {:.3} s: \
         {} elements, mesh {:.3}, assembly {:.3}, iterations {:.3} ({}), far field {:.3}, rest {:.3}",
        load.as_secs_f64(),
        outline.as_secs_f64(),
        floor.domain().holes().len(),
        total.as_secs_f64(),
        floor.map().elements().len(),
        c.mesh.as_secs_f64(),
        c.assembly.as_secs_f64(),
        c.factor.as_secs_f64(),
        c.iterations,
        c.far_field.as_secs_f64(),
        (total - c.total()).as_secs_f64(),
    );
    Ok(())
}
