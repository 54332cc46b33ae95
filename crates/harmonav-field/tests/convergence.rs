//! Following −∇Θ/|∇Θ| from random starts reaches the goal under both k policies and with no
//! tuning. (The 1000-start study per world runs in `cargo xtask verify`.) The tests of the
//! paper's far-field valley (pitfall A) and of the non-Morse arrangement use `k = n + 1`.

use std::sync::Arc;

use harmonav_field::checks;
use harmonav_field::descent::{Ending, FollowOptions, follow};
use harmonav_field::{Field, KPolicy};
use harmonav_transform::random::{self, Kind, Rng};

/// `checks::convergence` from `starts` random starts in a 6-obstacle world: (reached, slowest).
fn study(kinds: &[Kind], outer: Kind, seed: u64, starts: usize, policy: KPolicy) -> (usize, f64) {
    let mut rng = Rng::new(seed);
    let ws = Arc::new(random::workspace(&mut rng, 6, kinds, outer, 0.2));
    let field = Field::all_known_with(ws.clone(), policy).unwrap();
    assert_eq!(field.k(), policy.k(6));
    let starts = (0..starts).map(|_| random::free_point(&mut rng, &ws, 1e-3));
    let c = checks::convergence(&field, starts, &FollowOptions::default());
    assert_eq!(c.collisions, 0, "collision from {:?}", c.first_collision);
    (c.reached, c.slowest())
}

#[test]
fn sphere_world_converges() {
    for policy in KPolicy::ALL {
        let (reached, worst) = study(&[Kind::Circle], Kind::Circle, 1, 150, policy);
        assert_eq!(reached, 150, "{policy}: slowest arrival {worst} s");
    }
}

#[test]
fn mixed_star_world_converges() {
    let all = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    for policy in KPolicy::ALL {
        let (reached, worst) = study(&all, Kind::Star, 2, 150, policy);
        assert_eq!(reached, 150, "{policy}: slowest arrival {worst} s");
    }
}

/// With no obstacle and `Phi` the identity between start and goal, the descent is the straight
/// segment at unit speed: the arrival time is the distance less the goal tolerance.
#[test]
fn empty_world_descent_is_the_straight_segment() {
    use harmonav_transform::{StarShape, Workspace};
    use nalgebra::Vector2;
    // ε_0 = 0.45·2·d(x_d, ∂O_0) ≈ 89: the outer band starts about 11 from the centre.
    let boundary = StarShape::circle(Vector2::zeros(), 100.0).unwrap();
    let goal = Vector2::new(1.0, -0.5);
    let ws = Arc::new(Workspace::new(boundary, vec![], goal).unwrap());
    let field = Field::all_known(ws).unwrap();
    let options = FollowOptions::default();
    for start in [Vector2::new(-3.0, 2.0), Vector2::new(2.5, 0.3)] {
        let d = follow(&field, start, &options);
        assert_eq!(d.ending, Ending::Reached);
        let expected = (start - goal).norm() - (d.end - goal).norm();
        assert!((d.time - expected).abs() < 1e-9, "{} vs {expected}", d.time);
        // The end lies on the segment.
        let u = (goal - start).normalize();
        let off = (d.end - start) - (d.end - start).dot(&u) * u;
        assert!(off.norm() < 1e-9, "{off:?}");
    }
}

/// The 20-obstacle mixed-shape world of the Monte-Carlo study in `cargo xtask verify`.
fn monte_carlo_world(policy: KPolicy) -> Field {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(20);
    let ws = Arc::new(random::workspace(&mut rng, 20, &kinds, Kind::Star, 0.1));
    Field::all_known_with(ws, policy).unwrap()
}

/// Pitfall A (maths.md §5): from this start the descent runs for about 15 m inside the stretched
/// outer band, along the far-field valley of phi_k, where the normalised field is stiff. The
/// explicit Bogacki–Shampine pair needed 925 618 steps here; the L-stable W-method needs a few
/// ten thousand. (A step count, not a time: deterministic on any machine.) With `k = "auto"`
/// the valley is gone: the same start heads for the goal, within 10 % of the straight line.
#[test]
fn the_valley_in_the_outer_band_does_not_stall_the_descent() {
    use nalgebra::Vector2;
    let field = monte_carlo_world(KPolicy::Paper);
    let start = Vector2::new(4.640534808881151, 2.2683612449290624);
    let wall = -field.workspace().boundary().signed_distance(start);
    assert!(
        wall < 0.02,
        "start in the outer band: {wall} m from the wall"
    );
    let d = follow(&field, start, &FollowOptions::default());
    assert_eq!(d.ending, Ending::Reached);
    assert!(d.collision_free);
    assert!(d.time > 10.0, "the path follows the valley: {} m", d.time);
    let attempts = d.steps + d.rejected;
    assert!(attempts < 60_000, "{attempts} steps");
    let auto = follow(
        &monte_carlo_world(KPolicy::Auto),
        start,
        &FollowOptions::default(),
    );
    assert_eq!(auto.ending, Ending::Reached);
    assert!(auto.collision_free);
    let straight = (start - field.workspace().destination()).norm();
    assert!(
        auto.time < 1.1 * straight && d.time > 1.5 * straight,
        "auto {} m, paper {} m, straight line {straight} m",
        auto.time,
        d.time
    );
}

/// The one start in 10⁴ of the Monte-Carlo study that the stiff band squeezes onto the stable
/// manifold of a far-field saddle of phi_k: it chatters on the valley floor next to the saddle,
/// and the stall window ends the descent as `Stuck` (without it: 10⁸ step attempts until
/// `max_time`).
#[test]
fn a_path_squeezed_onto_a_saddle_ends_stuck_next_to_it() {
    use nalgebra::Vector2;
    let field = monte_carlo_world(KPolicy::Paper);
    let start = Vector2::new(4.255529293381624, 1.7363527519050335);
    let d = follow(&field, start, &FollowOptions::default());
    assert_eq!(d.ending, Ending::Stuck);
    assert!(d.time < 2.0, "stopped after {} m", d.time);
    let h = field.eval(d.end).unwrap().h;
    assert!(h.norm() > 40.0, "in the far field: |h| = {}", h.norm());
    // The saddles of Θ are those of phi_k pulled back through Phi⁻¹ (theorem isNF). The valley
    // floor is flat there: the path stalls 8 mm short of the saddle with Θ level with it to
    // 3e-8, where the direction across the 1e-4 m wide floor is lost in rounding.
    let (gap, saddle) = field
        .critical_points()
        .into_iter()
        .filter(|c| c.point_world.is_some())
        .map(|c| ((c.x - d.end).norm(), c.x))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    let level = (field.eval(saddle).unwrap().value - field.eval(d.end).unwrap().value).abs();
    assert!(gap < 0.02, "{gap} m from the nearest saddle of Θ");
    assert!(level < 1e-7, "Θ differs from the saddle's by {level:e}");
}

/// The error control works: over 2 m of curved path in a 6-obstacle world, the default
/// tolerance (1e-6 per step) ends within 1e-4 of a run at 1e-11, and halving the largest step
/// changes nothing beyond that.
#[test]
fn descent_converges_as_the_tolerance_shrinks() {
    let all = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let mut rng = Rng::new(3);
    let ws = Arc::new(random::workspace(&mut rng, 6, &all, Kind::Star, 0.2));
    let field = Field::all_known_with(ws.clone(), KPolicy::Paper).unwrap();
    let at = |tol: f64, max_step: f64, x| {
        let options = FollowOptions {
            max_time: 2.0,
            step_tolerance: tol,
            max_step,
            ..FollowOptions::default()
        };
        follow(&field, x, &options)
    };
    let mut curved = 0;
    for _ in 0..20 {
        let x = random::free_point(&mut rng, &ws, 0.1);
        let reference = at(1e-11, 0.1, x);
        if reference.ending != Ending::TimedOut {
            continue;
        }
        // The path bends: its end is well short of 2 m from the start.
        if (reference.end - x).norm() < 1.95 {
            curved += 1;
        }
        for (tol, max_step) in [(1e-6, 0.1), (1e-6, 0.05)] {
            let d = at(tol, max_step, x);
            let gap = (d.end - reference.end).norm();
            assert!(gap < 1e-4, "from {x:?}: {gap:e} at tol {tol:e}");
        }
    }
    assert!(curved >= 5, "only {curved} curved paths");
}

/// Stall detection: in the non-Morse world of `scenarios/hard/non-morse.toml` a start on the
/// symmetry axis flows into the degenerate critical point at the origin; `follow` reports
/// `Stuck` there soon after arriving instead of chattering until `max_time`, while a start
/// 0.001 m off the axis passes it and arrives.
#[test]
fn a_descent_into_a_critical_point_ends_stuck() {
    use harmonav_transform::{StarShape, Workspace};
    use nalgebra::Vector2;
    let disc = |x: f64, y: f64| StarShape::circle(Vector2::new(x, y), 0.15).unwrap();
    let ws = Workspace::new(
        StarShape::circle(Vector2::zeros(), 4.5).unwrap(),
        vec![disc(-1.0, 0.0), disc(-1.0, -1.0), disc(-1.0, 1.0)],
        Vector2::new(-2.0, 0.0),
    )
    .unwrap();
    let field = Field::all_known_with(Arc::new(ws), KPolicy::Paper).unwrap();
    let options = FollowOptions::default();
    let on_axis = follow(&field, Vector2::new(2.5, 0.0), &options);
    assert_eq!(on_axis.ending, Ending::Stuck);
    assert!(on_axis.end.norm() < 1e-4, "{:?}", on_axis.end);
    assert!(on_axis.time < 2.5 + 0.5, "stopped after {} m", on_axis.time);
    let off_axis = follow(&field, Vector2::new(2.5, 1e-3), &options);
    assert_eq!(off_axis.ending, Ending::Reached);
}

/// A 50:1 ellipse workspace with one disc: the descent round the disc is a detour of radius
/// `≈ |x_d − P_1|/k` in the point world. With `k = 6(n + 1) = 12` that is 3.3 m in a corridor
/// 2 m wide, so the detour runs through the outer band, compressed to millimetres against the
/// wall, and the kinematic run stalled there after 2 million steps. The layer rule of
/// `KPolicy::Auto` raises `k` to `2·layer_ratio` (closed form below), and the descent crosses
/// the 80 m in a few thousand steps, with the paper's `k` still stiff (a step count, not a time).
#[test]
fn an_elongated_workspace_is_crossed_without_stiffness() {
    use harmonav_field::{LAYER_FACTOR, layer_ratio};
    use harmonav_transform::{StarShape, Workspace};
    use nalgebra::Vector2;
    let boundary = StarShape::ellipse(Vector2::zeros(), [50.0, 1.0], 0.0).unwrap();
    let disc = StarShape::circle(Vector2::new(0.0, 0.3), 0.2).unwrap();
    let goal = Vector2::new(40.0, 0.0);
    let ws = Arc::new(Workspace::new(boundary, vec![disc], goal).unwrap());
    let field = Field::all_known(ws.clone()).unwrap();
    // ε_0 = 0.45·min(d(O_1, ∂O_0), 2 d(x_d, ∂O_0)) = 0.45·0.5; the disc's centre is 0.7 m
    // from the wall, 40.0011 m from the goal (the boundary distances are parry queries
    // refined to ~1e-9).
    let ratio = (goal - Vector2::new(0.0, 0.3)).norm() / (0.7 - 0.45 * 0.5);
    assert!((layer_ratio(&ws, field.transform()) - ratio).abs() < 1e-6 * ratio);
    assert!((field.k() - LAYER_FACTOR * ratio).abs() < 1e-6 * ratio);
    let options = FollowOptions {
        goal_tolerance: 0.01,
        max_time: 200.0,
        ..FollowOptions::default()
    };
    let d = follow(&field, Vector2::new(-40.0, 0.0), &options);
    assert_eq!(d.ending, Ending::Reached);
    assert!(d.collision_free);
    assert!(d.time < 1.05 * 80.0, "path {} m", d.time);
    assert!(
        d.steps + d.rejected < 20_000,
        "{} steps",
        d.steps + d.rejected
    );
    // The outer map is radial about x_d, so its band is no shortcut: starts next to the long
    // walls arrive too (about the ellipse's centre 7 of 20 such starts stalled in the band).
    assert_eq!(field.transform().outer_centre(), goal);
    let mut rng = harmonav_transform::random::Rng::new(5);
    let mut tried = 0;
    while tried < 20 {
        let x = Vector2::new(rng.uniform(-45.0, 30.0), rng.uniform(-1.0, 1.0));
        let wall = -ws.boundary().signed_distance(x);
        if wall < 0.01 || ws.obstacles()[0].signed_distance(x) < 0.01 {
            continue;
        }
        tried += 1;
        let d = follow(&field, x, &options);
        assert_eq!(
            d.ending,
            Ending::Reached,
            "from {x:?}, {wall} m from the wall"
        );
        assert!(d.collision_free);
        let attempts = d.steps + d.rejected;
        assert!(attempts < 20_000, "{attempts} steps from {x:?}");
        // J_Phi against central differences, in the band as elsewhere.
        let fd = checks::fd_errors(&field, x).unwrap();
        assert!(
            fd.jacobian <= 1e-5,
            "J − FD: {:e} of |J| at {x:?}",
            fd.jacobian
        );
    }
}
