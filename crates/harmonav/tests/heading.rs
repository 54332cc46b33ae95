//! The kinematic law's heading policy on a floor plan (`docs/maths.md` §13.3): under `"auto"`
//! the robot follows the shortest path within 60° of `−∇Θ`, under `"paper"` the flow line of
//! `Θ`; both keep `Θ` decreasing and the clearance, and `"auto"` is the shorter, close to the
//! geodesic's bounds.

mod common;

use harmonav::{FloorNavigator, HeadingPolicy, Law, Options, Vector2};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// Flies the L room (4 m arms, 1.5 m wide, reflex corner (1.5, 1.5); `h = 0.1`, so `δ = 0.1`
/// and `W_s` is the walls shrunk by 0.1 m) at 100 Hz from `start` to `goal`; returns the path length, after checking at every step that
/// `phi_k` decreased and the robot kept `radius + margin` from the walls, and that it arrived.
fn fly(heading: HeadingPolicy, start: Vector2<f64>, goal: Vector2<f64>) -> f64 {
    let floor = common::l_room();
    let options = Options::default()
        .with_robot(0.1, 0.1)
        .with_heading(heading);
    let mut nav = FloorNavigator::new(floor.clone(), goal, Law::kinematic(1.0), options).unwrap();
    let (mut x, h) = (start, 0.01);
    let mut phi = nav.evaluate(x, Vector2::zeros()).unwrap().field.phi;
    let mut length = 0.0;
    for _ in 0..2000 {
        if (x - goal).norm() < 1e-3 {
            break;
        }
        let step = h * nav.command(x, Vector2::zeros()).unwrap().value;
        x += step;
        length += step.norm();
        let next = nav.evaluate(x, Vector2::zeros()).unwrap().field.phi;
        assert!(next < phi, "{heading}: phi_k rose at {x:?}");
        assert!(floor.wall_distance(x) >= 0.2 - 1e-9, "{heading}: {x:?}");
        phi = next;
    }
    assert!((x - goal).norm() < 1e-3, "{heading}: stopped at {x:?}");
    length
}

#[test]
fn the_auto_heading_goes_round_the_corner_near_the_geodesic_and_the_paper_one_does_not() {
    // From beside the inner wall of one arm to the outer wall of the other.
    let (x, goal, c) = (v(1.2, 3.0), v(3.0, 0.3), v(1.5, 1.5));
    // The geodesic in W_δ (0.2 m from the walls; the mitred W_s puts its corner 0.1 m from
    // (1.4, 1.4)) is at least |x − c| + |c − goal| and at most the path through the circle of
    // radius 0.25 about c (four 22.5° chords, their midpoints 0.245 from c and 0.11 from
    // (1.4, 1.4)).
    // (The lower bound |x − c| + |c − goal| = 3.45 m is not asserted: the clearance checked at
    // every step implies it.)
    let r = 0.25;
    let q = |deg: f64| c + r * v(deg.to_radians().cos(), deg.to_radians().sin());
    let arc: f64 = (0..4)
        .map(|i| (q(180.0 + 22.5 * f64::from(i + 1)) - q(180.0 + 22.5 * f64::from(i))).norm())
        .sum();
    let upper = (x - q(180.0)).norm() + arc + (q(270.0) - goal).norm();
    let auto = fly(HeadingPolicy::Auto, x, goal);
    let paper = fly(HeadingPolicy::Paper, x, goal);
    // Measured: auto 3.75 m, paper 5.09 m; the bounds 3.45 and 3.67 m.
    assert!(
        auto <= 1.05 * upper,
        "auto: {auto} against the geodesic's {upper}"
    );
    // The negative control: the flow line of Θ swings out into the other arm.
    assert!(paper > 1.3 * upper, "paper: {paper} against {upper}");
}

/// Eq. heldwork: the dynamic hold's step dissipates, `v⁺·(v⁺ − w) ≤ 0` with
/// `w = ẋ − hμ_p∇Ψ/m` (the held step's own term of `V' − V`), also where the heading's turn or
/// the slide along `∂W_δ` changed `v⁺`: at 4 000 seeded states of the L room (speeds up to
/// 3 m/s in every direction, goal across the corner, `h` 0.01–0.1 s), every command the law
/// gives (`law` or `capped`) meets it to rounding (measured: 2.9e-16 of `|w|²` at worst).
/// Negative control: before eq. heldwork the turn's exact rotation broke it wherever the
/// damping was weak (`a·cos θ < 1`): 1 129 of the 4 000 states here, by up to 0.28 of `|w|²`;
/// and `V` rose over one period of `map-office-solve.toml`.
#[test]
fn the_dynamic_hold_dissipates_with_the_heading_turned() {
    use harmonav::Controller;
    use harmonav::transform::random::Rng;
    let floor = common::l_room();
    let goal = v(3.6, 0.4);
    let law = Law::Dynamic { mass: 1.0, mu: 2.0 };
    let mut rng = Rng::new(5);
    let (mut judged, mut broken, mut worst) = (0, 0, f64::NEG_INFINITY);
    let mut nav = FloorNavigator::new(floor.clone(), goal, law, Options::default()).unwrap();
    for n in 0..4000 {
        // A navigator (and its geodesic) per 20 states.
        if n % 20 == 0 {
            let options = Options::default()
                .with_robot(0.1, 0.1)
                .with_control_period(rng.uniform(0.01, 0.1));
            nav = FloorNavigator::new(floor.clone(), goal, law, options).unwrap();
        }
        let h = nav.control_period();
        let x = v(rng.uniform(0.2, 1.3), rng.uniform(0.2, 3.8));
        let vel = rng.uniform(0.0, 3.0) * {
            let a = rng.uniform(0.0, std::f64::consts::TAU);
            v(a.cos(), a.sin())
        };
        let Ok(c) = nav.command(x, vel) else { continue };
        if !matches!(c.mode, harmonav::Mode::Law | harmonav::Mode::Capped { .. }) {
            continue;
        }
        let Controller::Dynamic(d) = nav.controller() else {
            unreachable!()
        };
        let e = nav.evaluate(x, vel).unwrap();
        let calibration = (nav.field().destination_stiffness(), 0.0);
        let g = d.potential_for(calibration, &e.field).gradient;
        let w = vel - (h * d.pull() / d.mass()) * g;
        let next = vel + (h / d.mass()) * c.value;
        let work = next.dot(&(next - w)) / w.norm_squared().max(1e-300);
        worst = worst.max(work);
        judged += 1;
        broken += usize::from(work > 1e-12);
    }
    assert!(judged > 2000, "{judged}");
    assert!(broken == 0, "{broken}: v⁺·(v⁺ − w) = {worst:e} of |w|²");
}
