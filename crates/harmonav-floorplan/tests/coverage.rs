//! The certified fraction of the reachable free space (`FloorField::certified_area`, issue
//! 52): against an independent evaluation of `Θ < c_δ` on points of another grid, its
//! reachability (a door narrower than the robot keeps the other room out), its negative
//! controls (a level nothing is below; a long corridor, where `c_δ` certifies little), and
//! its grid's cell.

mod common;

use std::sync::Arc;

use harmonav_field::KPolicy;
use harmonav_floorplan::{
    CentrePolicy, FloorField, FloorMap, FloorOptions, LayerLevel, LevelOptions, MAX_AREA_SAMPLES,
    area_cell,
};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The U room of `common::u_room` (6 × 4 m, a U-shaped hole), radius + margin 0.2 m.
fn u_field() -> (FloorField, LayerLevel) {
    let floor = common::u_room(0.1, 0.2, CentrePolicy::Solve);
    let field = FloorField::new(floor, v(5.2, 2.0), KPolicy::default()).unwrap();
    let level = field.certify_layer_level(&LevelOptions::default());
    (field, level)
}

#[test]
fn the_fraction_matches_an_independent_evaluation_on_another_grid() {
    let (field, level) = u_field();
    let start = v(0.6, 0.6);
    let area = field.certified_area(&level, start, 0.2, &[], MAX_AREA_SAMPLES, 2);
    assert_eq!(area.cell, 0.05, "{area:?}");
    let fraction = area.fraction();
    // Measured: 21 % (1 311 of 6 114 samples).
    assert!(fraction > 0.1 && fraction < 1.0, "{area:?}");
    // The whole free space at 0.2 m from the walls is one component here: 5.6 × 3.6 m less
    // the U (2.6 m²) grown by 0.2 m (its 10.8 m rim, 2.2 m² more).
    let reachable = area.reachable_area();
    assert!(
        (14.8..15.8).contains(&reachable),
        "{reachable} m²: {area:?}"
    );
    // Independently: a grid offset by a third of a cell and twice as coarse, Θ evaluated
    // directly, the free space tested by the distances alone.
    let floor = field.floor();
    let (mut free, mut below) = (0usize, 0usize);
    let mut x = 0.1 / 3.0;
    while x < 6.0 {
        let mut y = 0.1 / 3.0;
        while y < 4.0 {
            let p = v(x, y);
            if floor.walls().contains(p) && floor.wall_distance(p) >= 0.2 {
                free += 1;
                if field.eval(p).is_ok_and(|e| e.value < level.certified()) {
                    below += 1;
                }
            }
            y += 0.1;
        }
        x += 0.1;
    }
    let brute = below as f64 / free as f64;
    assert!(
        (brute - fraction).abs() < 0.02,
        "grid {fraction} against brute force {brute} ({below} of {free}): {area:?}"
    );
    // Convergence from the start (the far corner) is not certified, nor from the goal's
    // component as a whole; at the goal it is.
    assert!(!level.holds(field.eval(start).unwrap().phi));
    assert!(level.holds(field.eval(v(5.0, 2.0)).unwrap().phi));
}

#[test]
fn the_counts_do_not_depend_on_the_threads_and_an_empty_level_certifies_nothing() {
    let (field, level) = u_field();
    let start = v(0.6, 0.6);
    let one = field.certified_area(&level, start, 0.2, &[], 5_000, 1);
    let three = field.certified_area(&level, start, 0.2, &[], 5_000, 3);
    assert_eq!(one, three);
    assert_eq!(one.cell, 0.1, "5 000 samples over 6 × 4 m: {one:?}");
    // Negative control: a level nothing lies below certifies nothing; one everything lies
    // below certifies all of W_δ, which here (δ = 0.1 m < 0.2 m) is all but the corners cut
    // by the mitred offset of the walls.
    let none = LayerLevel {
        phi_certified: f64::NEG_INFINITY,
        ..level
    };
    let all = LayerLevel {
        phi_certified: f64::INFINITY,
        ..level
    };
    let zero = field.certified_area(&none, start, 0.2, &[], 5_000, 2);
    assert_eq!((zero.certified, zero.fraction()), (0, 0.0), "{zero:?}");
    let every = field.certified_area(&all, start, 0.2, &[], 5_000, 2);
    assert_eq!(
        every.certified + every.skipped,
        every.in_region,
        "{every:?}"
    );
    assert!(every.region_fraction() > 0.99, "{every:?}");
    assert!(one.certified < every.certified, "{one:?} {every:?}");
}

#[test]
fn an_obstacle_is_left_out_of_the_free_space() {
    let (field, level) = u_field();
    let start = v(0.6, 0.6);
    let without = field.certified_area(&level, start, 0.2, &[], 5_000, 2);
    let disc = StarShape::circle(v(1.0, 2.0), 0.3).unwrap();
    let with = field.certified_area(&level, start, 0.2, &[disc], 5_000, 2);
    // The disc grown by 0.2 m: π·0.5² ≈ 0.79 m², 78 samples of 0.1 m.
    let gone = without.reachable - with.reachable;
    assert!((70..=86).contains(&gone), "{gone}: {without:?} {with:?}");
}

#[test]
fn a_door_narrower_than_the_robot_keeps_the_other_room_out() {
    // Two 3 × 3 m rooms joined by a door 0.3 m wide; the robot needs 0.4 m.
    let room = vec![
        v(0.0, 0.0),
        v(3.0, 0.0),
        v(3.0, 1.35),
        v(3.2, 1.35),
        v(3.2, 0.0),
        v(6.2, 0.0),
        v(6.2, 3.0),
        v(3.2, 3.0),
        v(3.2, 1.65),
        v(3.0, 1.65),
        v(3.0, 3.0),
        v(0.0, 3.0),
    ];
    let floor = Arc::new(FloorMap::new(room, vec![], &FloorOptions::new(0.2, 0.2)).unwrap());
    let field = FloorField::new(floor, v(2.0, 1.5), KPolicy::default()).unwrap();
    let level = field.certify_layer_level(&LevelOptions::default());
    let left = field.certified_area(&level, v(1.0, 1.0), 0.2, &[], MAX_AREA_SAMPLES, 2);
    let right = field.certified_area(&level, v(5.0, 1.0), 0.2, &[], MAX_AREA_SAMPLES, 2);
    // One room's free space: 2.6 × 2.6 m, less nothing (its corners are convex).
    for (area, which) in [(left, "left"), (right, "right")] {
        let a = area.reachable_area();
        assert!((6.5..6.9).contains(&a), "{which}: {a} m², {area:?}");
    }
    // The goal is in the left room, and some of it is certified.
    assert!(left.certified > 0, "{left:?}");
}

#[test]
fn a_long_corridor_is_certified_near_its_goal_only() {
    // 16 × 1 m, the goal 1 m from one end: the far end crowds into the disk next to the goal's
    // image's opposite, Θ within rounding of 1, and c_δ covers the goal's end alone.
    let corridor = vec![v(0.0, 0.0), v(16.0, 0.0), v(16.0, 1.0), v(0.0, 1.0)];
    let floor = Arc::new(FloorMap::new(corridor, vec![], &FloorOptions::new(0.1, 0.2)).unwrap());
    let field = FloorField::new(floor, v(1.0, 0.5), KPolicy::default()).unwrap();
    let level = field.certify_layer_level(&LevelOptions::default());
    let area = field.certified_area(&level, v(15.0, 0.5), 0.2, &[], MAX_AREA_SAMPLES, 2);
    // Measured: 2.5 % (92 of 3 744 samples), against 21 % in the U room.
    assert!(area.fraction() < 0.05, "{area:?}");
    assert!(!level.holds(field.eval(v(15.0, 0.5)).unwrap().phi));
}

#[test]
fn the_cell_is_fine_on_a_room_bounded_on_a_building_and_never_above_the_robot() {
    assert_eq!(area_cell(v(6.0, 4.0), 0.25, MAX_AREA_SAMPLES), 0.05);
    // 60 × 60 m: 0.1 m would give 360 000 samples, 0.2 m gives 90 000 (below the robot's
    // 0.25 m).
    let cell = area_cell(v(60.0, 60.0), 0.25, MAX_AREA_SAMPLES);
    assert_eq!(cell, 0.2);
    assert!(3600.0 / (cell * cell) <= MAX_AREA_SAMPLES as f64);
    // A small robot on a large plan: the cell is the robot's clearance, within 16 times the
    // samples.
    let small = area_cell(v(60.0, 60.0), 0.12, MAX_AREA_SAMPLES);
    assert_eq!(small, 0.12);
    // A tiny robot on a huge plan: bounded by 16 times the samples.
    let huge = area_cell(v(1000.0, 1000.0), 0.01, MAX_AREA_SAMPLES);
    assert!(1e6 / (huge * huge) <= 16.0 * MAX_AREA_SAMPLES as f64 * (1.0 + 1e-9));
    // Degenerate input gives a finite positive cell.
    assert_eq!(area_cell(v(0.0, 0.0), 0.0, 0), 0.05);
}
