//! The slide level `c_s` (docs/maths.md §13.9): the arcs it rests on hold the true directions
//! (`−∇Θ` from `eval` at points of each disc, the nearest-wall direction at points of
//! `∂W_δ`), it is `+∞` where no sample of the edge rests and bounds from below every
//! attracting rest point that the samples prove (the negative control: a bar with the goal
//! just behind it).

mod common;

use std::sync::Arc;

use harmonav_field::KPolicy;
use harmonav_floorplan::{CentrePolicy, FloorField, FloorMap, FloorOptions, LevelOptions};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The L room of the suite (`scenarios/floorplans/l-room.toml`'s walls), `h = 0.1`, 0.2 m.
fn l_room(centre: CentrePolicy) -> Arc<FloorMap> {
    let walls = vec![
        v(0.0, 0.0),
        v(6.0, 0.0),
        v(6.0, 2.0),
        v(2.0, 2.0),
        v(2.0, 5.0),
        v(0.0, 5.0),
    ];
    let mut options = FloorOptions::new(0.1, 0.2);
    options.centre = centre;
    Arc::new(FloorMap::new(walls, vec![], &options).unwrap())
}

/// Deterministic points of the disc `B(x, ρ)` (a sunflower).
fn disc_points(x: Vector2<f64>, rho: f64, n: usize) -> impl Iterator<Item = Vector2<f64>> {
    (0..n).map(move |i| {
        let r = rho * ((i as f64 + 0.5) / n as f64).sqrt();
        let t = i as f64 * 2.399_963_229_728_653;
        x + r * v(t.cos(), t.sin())
    })
}

#[test]
fn the_descent_arc_holds_the_direction_of_minus_grad_theta_at_every_point_of_its_disc() {
    for (floor, goal) in [
        (l_room(CentrePolicy::Solve), v(5.0, 1.0)),
        (l_room(CentrePolicy::Goal), v(5.0, 1.0)),
        (common::u_room(0.1, 0.2, CentrePolicy::Goal), v(5.2, 2.0)),
    ] {
        let field = FloorField::new(floor.clone(), goal, KPolicy::default()).unwrap();
        let delta = floor.delta();
        let (mut discs, mut points) = (0, 0);
        let mut tight: Vec<f64> = Vec::new();
        for (i, &p) in floor.layer_edge().iter().enumerate().step_by(3) {
            let rho = delta * [0.6, 0.3, 0.1][(i / 3) % 3];
            let Some(arc) = field.descent_arc(p, rho) else {
                continue;
            };
            discs += 1;
            let mut spread = 0.0_f64;
            for y in disc_points(p, rho, 60) {
                let Ok(e) = field.eval(y) else { continue };
                let d = e.direction.unwrap();
                assert!(
                    arc.contains(d),
                    "{p:?} ρ {rho}: {d:?} at {y:?} outside {arc:?}"
                );
                let off = d.y.atan2(d.x) - arc.mid;
                spread = spread.max(off.sin().atan2(off.cos()).abs());
                points += 1;
            }
            tight.push(spread / arc.half);
        }
        assert!(
            discs > 50 && points > 1000,
            "{discs} discs, {points} points"
        );
        // Not vacuous: somewhere the sampled directions fill more than a third of the arc
        // (measured 0.48–0.93; the median disc's arc is 10–20 times their spread).
        let most = tight.iter().copied().fold(0.0, f64::max);
        assert!(most > 1.0 / 3.0, "every arc is loose: {most}");
    }
}

#[test]
fn the_normal_arc_holds_the_direction_to_the_nearest_wall_at_the_edge_points_of_its_disc() {
    let floor = common::u_room(0.1, 0.2, CentrePolicy::Solve);
    let field = FloorField::new(floor.clone(), v(5.2, 2.0), KPolicy::default()).unwrap();
    let edge = floor.layer_edge();
    let delta = floor.delta();
    let mut checked = 0;
    for (i, &x) in edge.iter().enumerate().step_by(5) {
        let x = x + v(0.3, -0.2) * delta * 0.1;
        let rho = delta * [0.3, 0.1][i % 2];
        let Some(arc) = field.normal_arc(x, rho) else {
            continue;
        };
        for &p in edge.iter().filter(|p| (*p - x).norm() <= rho) {
            let n = floor.toward_boundary(p).unwrap();
            assert!(
                arc.contains(n),
                "{x:?} ρ {rho}: {n:?} at {p:?} outside {arc:?}"
            );
            checked += 1;
        }
    }
    assert!(checked > 200, "{checked}");
}

/// In the L room no sample of `∂W_δ` rests (the reflex corner's slide passes round it), and
/// the covering proves it: `c_s = +∞`, so every start of `W_δ` is certified.
#[test]
fn the_l_rooms_slide_is_proven_free_of_rest_points() {
    let field =
        FloorField::new(l_room(CentrePolicy::Solve), v(5.0, 1.0), KPolicy::default()).unwrap();
    assert!(field.layer_slide().attracting.is_empty());
    let slide = field.certify_slide_level(&LevelOptions::default());
    assert_eq!(slide.phi_certified, f64::INFINITY, "{slide:?}");
    assert_eq!(slide.unresolved, 0);
    let level = field.certify_level(&LevelOptions::default());
    assert!(
        level.holds(1e300) && level.convergence() == 1.0,
        "{level:?}"
    );
    // With a sensed obstacle the walls' covering proves nothing: not run, c_δ alone.
    let rock = StarShape::circle(v(1.0, 3.5), 0.2).unwrap();
    let sensed = field.with_obstacle(rock).unwrap();
    let slide = sensed.certify_slide_level(&LevelOptions::default());
    assert!(
        slide.skipped && slide.phi_certified == f64::NEG_INFINITY,
        "{slide:?}"
    );
    assert_eq!(slide.evaluations, 0);
}

/// The negative control: below a bar with the goal just behind it the slide has attracting
/// rest points (tests/level.rs). `c_s` is finite and at or below `phi_k` at each of them, so
/// no start that slides into one is called certified; with the normals ignored it would be
/// `+∞`.
#[test]
fn c_s_lies_below_every_attracting_rest_point_the_samples_prove() {
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let bar = vec![v(1.0, 1.8), v(5.0, 1.8), v(5.0, 2.2), v(1.0, 2.2)];
    let floor = Arc::new(FloorMap::new(room, vec![bar], &FloorOptions::new(0.1, 0.2)).unwrap());
    let field = FloorField::new(floor, v(3.0, 2.6), KPolicy::default()).unwrap();
    let rests = field.layer_slide().attracting;
    assert!(!rests.is_empty());
    let slide = field.certify_slide_level(&LevelOptions::default());
    assert!(slide.phi_certified.is_finite(), "{slide:?}");
    for p in &rests {
        // The midpoint between two samples of the edge, nudged into W_δ as they are.
        let n = field.floor().toward_boundary(*p).unwrap();
        let q = p - 1e-7 * n;
        let phi = field.eval(q).unwrap().phi;
        assert!(slide.phi_certified <= phi, "{slide:?} above {phi} at {p:?}");
        let level = field.certify_level(&LevelOptions::default());
        assert!(
            !level.holds(phi),
            "{level:?} certifies the rest point {p:?}"
        );
    }
}
