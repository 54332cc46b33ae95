//! The certified level `c_δ` (docs/maths.md §13.5): a lower bound of `Θ` on `∂W_δ` that no
//! point of `∂W_δ` goes below, found independently of the samples it was refined against, and
//! the exact distances of a point to an annular sector that it rests on.

mod common;

use std::sync::Arc;

use harmonav_field::KPolicy;
use harmonav_floorplan::{CentrePolicy, FloorField, FloorMap, FloorOptions, LevelOptions, Sector};
use harmonav_transform::StarShape;
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The U room of `common::u_room` at `h = 0.1` m, radius + margin 0.2 m.
fn u_trap(centre: CentrePolicy) -> Arc<FloorMap> {
    common::u_room(0.1, 0.2, centre)
}

/// Points of `∂W_δ` found by bisection on `sd = δ` along rays from a grid of interior points
/// in eight directions (not the layer-edge samples the level was refined against), each on
/// the inner side (`sd ≥ δ`, so that `Θ` is defined there).
fn edge_points(floor: &FloorMap) -> Vec<Vector2<f64>> {
    let delta = floor.delta();
    let (lo, hi) = floor.domain().bounding_box();
    let mut out = Vec::new();
    for i in 0..24 {
        for j in 0..16 {
            let p = lo
                + v(
                    (i as f64 + 0.5) / 24.0 * (hi.x - lo.x),
                    (j as f64 + 0.5) / 16.0 * (hi.y - lo.y),
                );
            if floor.signed_distance(p) <= 2.0 * delta {
                continue;
            }
            for k in 0..8 {
                let t = 0.37 + k as f64 * std::f64::consts::FRAC_PI_4;
                let d = v(t.cos(), t.sin());
                let mut s = 0.0;
                while floor.signed_distance(p + (s + 0.05) * d) >= delta {
                    s += 0.05;
                }
                let (mut a, mut b) = (s, s + 0.05);
                for _ in 0..50 {
                    let m = 0.5 * (a + b);
                    if floor.signed_distance(p + m * d) >= delta {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                out.push(p + a * d);
            }
        }
    }
    out
}

fn check(field: &FloorField, what: &str) -> f64 {
    let level = field.certify_layer_level(&LevelOptions::default());
    assert!(level.phi_certified.is_finite(), "{what}: {level:?}");
    assert!(
        level.phi_certified <= level.phi_sampled,
        "{what}: {level:?}"
    );
    let points = edge_points(field.floor());
    assert!(points.len() > 500, "{what}: {} edge points", points.len());
    let mut least = f64::INFINITY;
    for &p in &points {
        let e = field.eval(p).unwrap();
        assert!(
            e.phi >= level.phi_certified,
            "{what}: phi_k = {} at {p:?} on ∂W_δ, below the certified {}",
            e.phi,
            level.phi_certified
        );
        least = least.min(e.phi);
    }
    // Tight: within twice the refinement's tolerance of the least value found.
    assert!(
        level.phi_certified >= least - 2.0 * LevelOptions::default().tolerance,
        "{what}: certified {} far below the least value found {least}",
        level.phi_certified
    );
    assert_eq!(
        level.certified(),
        harmonav_potential::sigma(level.phi_certified)
    );
    level.phi_certified
}

#[test]
fn no_point_of_the_layer_edge_lies_below_the_certified_level() {
    let goal = v(5.2, 2.0);
    for centre in [CentrePolicy::Solve, CentrePolicy::Goal] {
        let field = FloorField::new(u_trap(centre), goal, KPolicy::default()).unwrap();
        let walls = check(&field, &format!("{centre:?}"));
        // A sensed disc whose band comes close to ∂W_δ: cells that may meet the band are
        // split until they do not.
        let disc = StarShape::circle(v(1.0, 3.0), 0.25).unwrap();
        let sensed = field.with_obstacle(disc).unwrap();
        let with_disc = check(&sensed, &format!("{centre:?} with a sensed disc"));
        assert!(with_disc != walls, "the sensed disc changed nothing");
    }
}

#[test]
fn a_start_is_certified_exactly_when_its_level_is_below_c_delta() {
    let field =
        FloorField::new(u_trap(CentrePolicy::Solve), v(5.2, 2.0), KPolicy::default()).unwrap();
    let level = field.certify_layer_level(&LevelOptions::default());
    let near = field.eval(v(4.9, 2.0)).unwrap();
    let far = field.eval(v(0.6, 0.6)).unwrap();
    assert!(
        level.holds(near.phi),
        "{level:?}, near the goal phi {}",
        near.phi
    );
    assert!(
        !level.holds(far.phi),
        "{level:?}, far corner phi {}",
        far.phi
    );
    assert_eq!(level.holds(near.phi), near.value < level.certified());
}

/// Brute force over a fine polar grid of the sector: the closed forms are the grid's extremes
/// to within the grid's spacing, and never beyond them the wrong way.
#[test]
fn sector_distances_match_brute_force() {
    let mut seed = 7_u64;
    let mut rand = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..300 {
        let lo = 3.0 * rand();
        let a = Sector {
            radii: (lo, lo + 3.0 * rand()),
            angle: 7.0 * rand() - 3.5,
            half_width: 3.3 * rand(),
        };
        let p = v(10.0 * rand() - 5.0, 10.0 * rand() - 5.0);
        let (mut near, mut far) = (f64::INFINITY, 0.0_f64);
        let n = 400;
        for i in 0..=n {
            let r = a.radii.0 + (a.radii.1 - a.radii.0) * i as f64 / n as f64;
            for j in 0..=n {
                let t = a.angle
                    + a.half_width.min(std::f64::consts::PI) * (2.0 * j as f64 / n as f64 - 1.0);
                let d = (v(r * t.cos(), r * t.sin()) - p).norm();
                near = near.min(d);
                far = far.max(d);
            }
        }
        let step = 2.0 * (a.radii.1 - a.radii.0) / n as f64 + a.radii.1 * 2.0 * 3.3 / n as f64;
        let (dmin, dmax) = (a.min_distance(p), a.max_distance(p));
        assert!(
            dmin <= near + 1e-12 && dmin >= near - step,
            "{a:?} {p:?}: {dmin} vs {near}"
        );
        assert!(
            dmax >= far - 1e-12 && dmax <= far + step,
            "{a:?} {p:?}: {dmax} vs {far}"
        );
    }
}

/// `Phi(B(x, ρ))` lies in the sector [`harmonav_floorplan::FloorTransform::enclose`] gives: 300
/// points of each of a set of discs near the walls, the U's corners and in the open, under
/// both centre policies (the second with the exact image of the disc under `M_a`).
#[test]
fn the_sector_holds_the_image_of_its_disc() {
    let goal = v(5.2, 2.0);
    for centre in [CentrePolicy::Solve, CentrePolicy::Goal] {
        let field = FloorField::new(u_trap(centre), goal, KPolicy::default()).unwrap();
        let floor = field.floor().clone();
        let (mut discs, mut points) = (0, 0);
        for &(x, y) in &[
            (0.45, 0.45),
            (1.7, 3.3),
            (3.0, 1.9),
            (4.4, 0.6),
            (5.55, 3.5),
            (1.0, 2.0),
            (3.0, 3.6),
        ] {
            let c = v(x, y);
            for rho in [0.02, 0.05, 0.1] {
                let Ok(a) = field.transform().enclose(c, rho) else {
                    continue;
                };
                discs += 1;
                for i in 0..300 {
                    let t = i as f64 * 2.399_963_229_728_653;
                    let r = rho * ((i % 30) as f64 / 29.0);
                    let p = c + v(r * t.cos(), r * t.sin());
                    if floor.signed_distance(p) < floor.delta() {
                        continue;
                    }
                    let h = field.transform().nav_transform(p).unwrap().h;
                    let (n, off) = (h.norm(), {
                        let d = h.y.atan2(h.x) - a.angle;
                        d.sin().atan2(d.cos()).abs()
                    });
                    let tol = 1e-9 * a.radii.1.max(1.0);
                    assert!(
                        n >= a.radii.0 - tol && n <= a.radii.1 + tol,
                        "{centre:?}: |Phi| = {n} at {p:?} outside {a:?}"
                    );
                    assert!(
                        a.half_width >= std::f64::consts::PI || off <= a.half_width + 1e-9,
                        "{centre:?}: angle off by {off} at {p:?}, {a:?}"
                    );
                    points += 1;
                }
            }
        }
        assert!(
            discs >= 12 && points > 3000,
            "{discs} discs, {points} points"
        );
    }
}

/// A goal just behind a long bar: under the default `k` (12) the hole's barrier is a thin shell
/// inside the layer, so below the bar `−∇Θ` points into the layer and the projected descent
/// has attracting rest points on `∂W_δ` (spurious local minima of `Θ` on `W_δ`,
/// docs/maths.md §13.5); with the paper's `k = n + 1 = 2` the barrier reaches `∂W_δ` and there
/// are none; the U room has none either.
#[test]
fn a_thin_hole_barrier_makes_rest_points_of_the_slide_and_the_papers_k_removes_them() {
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let bar = vec![v(1.0, 1.8), v(5.0, 1.8), v(5.0, 2.2), v(1.0, 2.2)];
    let floor = Arc::new(FloorMap::new(room, vec![bar], &FloorOptions::new(0.1, 0.2)).unwrap());
    let auto = FloorField::new(floor.clone(), v(3.0, 2.6), KPolicy::default()).unwrap();
    let slide = auto.layer_slide();
    assert!(auto.k() > 2.0, "k = {}", auto.k());
    // Under the bar, towards its ends (the flow along the edge turns back there).
    assert!(
        slide
            .attracting
            .iter()
            .any(|p| (1.0..5.0).contains(&p.x) && p.y < 1.8),
        "{slide:?}"
    );
    let paper = FloorField::new(floor, v(3.0, 2.6), KPolicy::Paper).unwrap();
    let slide = paper.layer_slide();
    assert!(
        slide.samples > 100 && slide.attracting.is_empty(),
        "{slide:?}"
    );
    let u = FloorField::new(u_trap(CentrePolicy::Solve), v(5.2, 2.0), KPolicy::default())
        .unwrap()
        .layer_slide();
    assert!(u.samples > 100 && u.attracting.is_empty(), "{u:?}");
}

/// Issue 56, D13: far from the origin (1e7 m, where the coordinates' ulp is 1.9e-9 m) the edge
/// samples' nudge of `EDGE_NUDGE·δ` = 2e-10 m was lost to rounding, every sample failed to
/// evaluate, and the sampled least `Θ` was `+∞` (printed "1.000000"). Scaled to the
/// coordinates, every sample is evaluated there as at the origin, and the level agrees.
#[test]
fn the_layer_level_is_sampled_far_from_the_origin_as_at_it() {
    let room = |o: Vector2<f64>| {
        let p = |x: f64, y: f64| o + v(x, y);
        let outer = vec![p(0.0, 0.0), p(3.0, 0.0), p(3.0, 2.0), p(0.0, 2.0)];
        let hole = vec![p(1.2, 0.8), p(1.2, 1.2), p(1.8, 1.2), p(1.8, 0.8)];
        let options = FloorOptions::new(0.2, 0.2);
        let floor = Arc::new(FloorMap::new(outer, vec![hole], &options).unwrap());
        FloorField::new(floor, o + v(2.5, 1.5), KPolicy::default()).unwrap()
    };
    let options = LevelOptions {
        max_evaluations: 20_000,
        ..LevelOptions::default()
    };
    let near = room(v(0.0, 0.0)).certify_layer_level(&options);
    let far_field = room(v(1e7, 1e7));
    let far = far_field.certify_layer_level(&options);
    assert_eq!((near.skipped, far.skipped), (0, 0), "{near:?} {far:?}");
    assert!(far.phi_sampled.is_finite(), "{far:?}");
    assert!(
        (far.phi_sampled - near.phi_sampled).abs() < 1e-3 * near.phi_sampled.abs().max(1.0),
        "{near:?} {far:?}"
    );
}
