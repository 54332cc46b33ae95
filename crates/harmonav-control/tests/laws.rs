//! The control laws against the properties the paper proves for them.

use std::f64::consts::PI;
use std::sync::Arc;

use harmonav_control::checks::{
    energy_run, energy_run_from, energy_run_toward, goal_damping, theta_rate,
};
use harmonav_control::{
    BRAKING_TIME, Branch, DampingPolicy, Dynamic, GOVERNOR_BAND, HEADING_CONE_DEG, HeadingPolicy,
    Kinematic, PULL_GAIN, SpeedPolicy, TURN_FADE, TURN_TIME, UPHILL_GAIN, steer, turn_fade,
};
use harmonav_field::Field;
use harmonav_transform::random::{self, Kind, Rng};
use harmonav_transform::{StarShape, Workspace};
use nalgebra::{Matrix2, Matrix4, Vector2};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

fn world(seed: u64) -> (Field, Rng) {
    let mut rng = Rng::new(seed);
    let (m, outer) = (1 + rng.below(6), KINDS[rng.below(4)]);
    let ws = random::workspace(&mut rng, m, &KINDS, outer, 0.2);
    (Field::all_known(Arc::new(ws)).unwrap(), rng)
}

/// Corollary critdamp: the closed loop linearised at the goal, with the Hessian of the law's
/// potential (Θ, or Ψ under "auto") taken by finite differences of its gradient (independent of
/// the closed form, `checks::goal_damping`), has damping ratio 1: a double real eigenvalue per
/// direction.
#[test]
fn critical_damping_at_the_goal() {
    for seed in 0..40 {
        let (field, _) = world(seed);
        let law = Dynamic::new(1.0 + seed as f64 * 0.1, 10.0, 0.05)
            .unwrap()
            .with_damping(DampingPolicy::ALL[seed as usize % DampingPolicy::ALL.len()]);
        let g = goal_damping(&field, &law).unwrap();
        assert!(
            g.worst_deviation() < 1e-6,
            "seed {seed}: damping ratios {:?}",
            g.zeta
        );
        // The 4×4 closed-loop matrix has the double eigenvalue −λ_c/(2m).
        let (m, mu, lc) = (law.mass(), law.pull(), g.lambda_c);
        let mut a = Matrix4::zeros();
        a.fixed_view_mut::<2, 2>(0, 2)
            .copy_from(&Matrix2::identity());
        a.fixed_view_mut::<2, 2>(2, 0)
            .copy_from(&(-mu / m * g.hessian));
        a.fixed_view_mut::<2, 2>(2, 2)
            .copy_from(&(-lc / m * Matrix2::identity()));
        let target = -lc / (2.0 * m);
        for e in a.complex_eigenvalues().iter() {
            assert!(
                (e.re - target).abs() < 1e-3 * target.abs() && e.im.abs() < 1e-3 * target.abs(),
                "seed {seed}: {e} vs {target}"
            );
        }
    }
}

/// Eq. (totalenergy): between discoveries V = μΘ + ½m|ẋ|² does not increase along the closed
/// loop (V̇ = −λ|ẋ|², RK4 by `checks::energy_run`), and the speed stays below √(2μ/m), under
/// every damping policy.
#[test]
fn energy_decreases_and_speed_is_bounded() {
    for seed in 0..20 {
        let (field, mut rng) = world(100 + seed);
        let policy = DampingPolicy::ALL[seed as usize % DampingPolicy::ALL.len()];
        let law = Dynamic::new(1.0, 10.0, 0.05).unwrap().with_damping(policy);
        let start = random::free_point(&mut rng, field.workspace(), 0.2);
        let run = energy_run(&field, &law, start, 1e-3, 3000).unwrap();
        assert!(
            run.worst_rise <= 1e-9,
            "seed {seed} ({policy}): V rose by {:e} of itself",
            run.worst_rise
        );
        assert!(run.max_speed < law.speed_bound(), "{}", run.max_speed);
    }
}

/// The dynamic law's heading (`docs/maths.md` §13.4): the gyroscopic force `m·ω·Jẋ`,
/// `ω = χ(Θ)·∠(ẋ, d)/τ`, is perpendicular to the velocity with that magnitude; under `"paper"`, or
/// with no nominal heading, the force is eq. `dynctrllocal`'s exactly; and the held turn keeps
/// the speed and turns by `χ(Θ)·min(1, h/τ)` of the angle.
#[test]
fn the_heading_force_is_gyroscopic_and_the_held_turn_keeps_the_speed() {
    let cos = HEADING_CONE_DEG.to_radians().cos();
    for seed in 0..10 {
        let (field, mut rng) = world(700 + seed);
        let law = Dynamic::new(1.5, 10.0, 0.05).unwrap();
        let calibration = (field.destination_stiffness(), law.scale_shift(&field));
        let x = random::free_point(&mut rng, field.workspace(), 0.2);
        let e = field.eval(x).unwrap();
        let a = rng.uniform(-PI, PI);
        let v = rng.uniform(0.1, 1.0) * Vector2::new(a.cos(), a.sin());
        let b = rng.uniform(-PI, PI);
        let g = Vector2::new(b.cos(), b.sin());
        let d = law.damping(&field, &e, v, 0.0);
        let plain = law.force_for(calibration, &e, v, &d);
        let fg = law.force_toward(calibration, &e, v, &d, Some(g)) - plain;
        let target = steer(e.direction.unwrap(), g, cos);
        let angle = (v.x * target.y - v.y * target.x).atan2(v.dot(&target));
        assert!(
            fg.dot(&v).abs() <= 1e-12 * fg.norm() * v.norm(),
            "seed {seed}"
        );
        let want = law.mass() * v.norm() * angle.abs() * turn_fade(e.value) / TURN_TIME;
        assert!(
            (fg.norm() - want).abs() <= 1e-12 * want.max(1.0),
            "seed {seed}"
        );
        // Counter-clockwise for a positive angle.
        assert!(angle * (v.x * fg.y - v.y * fg.x) >= 0.0, "seed {seed}");
        assert_eq!(law.force_toward(calibration, &e, v, &d, None), plain);
        let paper = law.with_heading(HeadingPolicy::Paper);
        assert_eq!(paper.force_toward(calibration, &e, v, &d, Some(g)), plain);
        for h in [0.01, 0.1, TURN_TIME, 2.0] {
            let w = law.turned(&e, v, Some(g), h);
            assert!((w.norm() - v.norm()).abs() <= 1e-12 * v.norm());
            let turned = (v.x * w.y - v.y * w.x).atan2(v.dot(&w));
            let share = turn_fade(e.value) * (h / TURN_TIME).min(1.0);
            assert!((turned - share * angle).abs() < 1e-9, "seed {seed} h {h}");
        }
        assert_eq!(paper.turned(&e, v, Some(g), 0.1), v);
        // At the goal the force fades as Θ/Θ₀ (of higher order: the linearisation of
        // corollary critdamp is the paper's), and it is whole above Θ₀.
        let goal = field.workspace().destination();
        let mut faded = 0;
        for r in [1e-1, 1e-2, 1e-3] {
            let near = goal + Vector2::new(r, 0.0);
            let Ok(en) = field.eval(near) else { continue };
            faded += usize::from(en.value < TURN_FADE);
            let dn = law.damping(&field, &en, v, 0.0);
            let fgn = law.force_toward(calibration, &en, v, &dn, Some(g))
                - law.force_for(calibration, &en, v, &dn);
            let most = law.mass() * v.norm() * PI / TURN_TIME * (en.value / TURN_FADE).min(1.0);
            assert!(fgn.norm() <= most * (1.0 + 1e-12), "seed {seed} r {r}");
        }
        assert!(
            faded >= 2,
            "seed {seed}: too few points near the goal in the fade"
        );
    }
    assert_eq!(
        (turn_fade(0.0), turn_fade(-1.0), turn_fade(f64::NAN)),
        (0.0, 0.0, 0.0)
    );
    assert_eq!((turn_fade(TURN_FADE / 4.0), turn_fade(0.5)), (0.25, 1.0));
}

/// The heading force does no work: along the closed loop with a nominal heading that always
/// pulls across the descent (perpendicular to `x − x_d`), `V` still does not increase and the
/// speed stays below `√(2μ/m)` (RK4, as eq. totalenergy), and the path is not the paper's.
#[test]
fn energy_decreases_under_the_heading_force() {
    for seed in 0..10 {
        let (field, mut rng) = world(800 + seed);
        let law = Dynamic::new(1.0, 10.0, 0.05).unwrap();
        let start = random::free_point(&mut rng, field.workspace(), 0.2);
        let goal = field.workspace().destination();
        let swirl = |x: Vector2<f64>| {
            let r = x - goal;
            (r.norm() > 0.0).then(|| Vector2::new(-r.y, r.x) / r.norm())
        };
        let state = (start, Vector2::zeros());
        let run = energy_run_toward(&field, &law, state, swirl, 1e-3, 3000).unwrap();
        // 0.3 s in, before both can have settled at the goal, the paths differ.
        let early = energy_run_toward(&field, &law, state, swirl, 1e-3, 300).unwrap();
        let plain = energy_run_from(&field, &law, state, 1e-3, 300).unwrap();
        assert!(
            run.worst_rise <= 1e-9,
            "seed {seed}: V rose by {:e} of itself",
            run.worst_rise
        );
        assert!(run.max_speed < law.speed_bound(), "{}", run.max_speed);
        assert!(
            (early.end.0 - plain.end.0).norm() > 1e-3,
            "seed {seed}: no turn"
        );
    }
}

/// Eq. (kinctrl): dΘ/dt = ∇Θ·u = −K√(2Θ)|∇Θ| ≤ 0 (`checks::theta_rate`), also by a finite
/// step along u.
#[test]
fn kinematic_law_decreases_theta() {
    let law = Kinematic::new(1.5).unwrap().with_speed(SpeedPolicy::Paper);
    for seed in 0..40 {
        let (field, mut rng) = world(200 + seed);
        for _ in 0..20 {
            let x = random::free_point(&mut rng, field.workspace(), 0.05);
            let r = theta_rate(&field, &law, x).unwrap();
            assert!(r.rate <= 0.0 && r.relative_error() <= 1e-12, "{r:?}");
            let dt = 1e-7;
            let fd = (field.eval(x + dt * r.velocity).unwrap().value - r.eval.value) / dt;
            assert!(
                (fd - r.rate).abs() <= 1e-4 * r.rate.abs() + 1e-12,
                "fd {fd} vs {}",
                r.rate
            );
        }
        // At the goal the command is zero.
        let goal = field.eval(field.workspace().destination()).unwrap();
        assert_eq!(law.velocity(&goal, 0.0), Vector2::zeros());
    }
}

/// Every speed policy moves along the paper law's direction `−∇Θ/|∇Θ|` (the same flow lines,
/// hence the same guarantees), at a speed in `(0, v_max]` that vanishes only at the goal; under
/// `"auto"` it is `v_max` beyond the braking distance and `v_max√(r/d_b)` within it.
#[test]
fn every_speed_policy_follows_the_paper_direction_within_v_max() {
    let paper = Kinematic::new(1.5).unwrap().with_speed(SpeedPolicy::Paper);
    let auto = Kinematic::new(1.5).unwrap();
    assert_eq!(auto.speed_policy(), SpeedPolicy::Auto);
    assert!((auto.v_max() - 1.5 * 2f64.sqrt()).abs() < 1e-15);
    assert!((auto.braking_distance() - 0.5 * auto.v_max() * BRAKING_TIME).abs() < 1e-15);
    let slow = auto.with_v_max(0.3).unwrap();
    let capped_paper = paper.with_v_max(0.3).unwrap();
    let (mut near, mut far) = (0, 0);
    for seed in 0..40 {
        let (field, mut rng) = world(900 + seed);
        let goal = field.workspace().destination();
        for i in 0..40 {
            // Half the points near the goal, to cover the braking zone.
            let x = if i % 2 == 0 {
                random::free_point(&mut rng, field.workspace(), 1e-3)
            } else {
                let a = rng.uniform(0.0, std::f64::consts::TAU);
                let r = rng.uniform(1e-6, 1.5 * auto.braking_distance());
                let x = goal + r * Vector2::new(a.cos(), a.sin());
                if field.eval(x).is_err() {
                    continue;
                }
                x
            };
            let e = field.eval(x).unwrap();
            let r = (x - goal).norm();
            let up = paper.velocity(&e, r);
            let d = up / up.norm();
            for law in [auto, slow, capped_paper] {
                let u = law.velocity(&e, r);
                let s = u.norm();
                assert!(s > 0.0 && s <= law.v_max() * (1.0 + 1e-15), "{s} at {x:?}");
                assert!((u / s - d).norm() < 1e-12, "direction {:?} vs {d:?}", u / s);
                assert!(e.gradient.dot(&u) <= 0.0);
            }
            let (d_b, r_0) = (auto.braking_distance(), auto.linear_core());
            let expected = if r < r_0 {
                auto.v_max() * r / (r_0 * d_b).sqrt()
            } else {
                auto.v_max() * (r / d_b).sqrt().min(1.0)
            };
            assert!((auto.speed(&e, r) - expected).abs() <= 1e-14 * expected);
            if r < auto.braking_distance() {
                near += 1;
            } else {
                far += 1;
                assert_eq!(auto.speed(&e, r), auto.v_max());
            }
            assert!((capped_paper.speed(&e, r) - paper.speed(&e, r).min(0.3)).abs() < 1e-15);
        }
        let at_goal = field.eval(goal).unwrap();
        assert_eq!(auto.velocity(&at_goal, 0.0), Vector2::zeros());
    }
    assert!(near > 300 && far > 300, "near {near}, far {far}");
    assert!(auto.with_v_max(0.0).is_err());
    let e = auto.with_v_max(f64::NAN).unwrap_err();
    assert_eq!(e.field, "controller.v_max");
}

/// Integrates `ẋ = u` with classical RK4 at step `dt` from `x` until `|x − x_d| < tolerance`;
/// the arrival time, or `None` after `max_time`.
fn arrival_time(
    field: &Field,
    law: &Kinematic,
    mut x: Vector2<f64>,
    tolerance: f64,
    dt: f64,
    max_time: f64,
) -> Option<f64> {
    let goal = field.workspace().destination();
    let u = |y: Vector2<f64>| law.velocity(&field.eval(y).unwrap(), (y - goal).norm());
    let mut t = 0.0;
    while t < max_time {
        if (x - goal).norm() < tolerance {
            return Some(t);
        }
        let k1 = u(x);
        let k2 = u(x + 0.5 * dt * k1);
        let k3 = u(x + 0.5 * dt * k2);
        let k4 = u(x + dt * k3);
        x += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += dt;
    }
    None
}

/// The arrival time of `"auto"` within `ε` along a straight ray from `D` (`docs/maths.md` §6):
/// `(D − d_b)⁺/v_max` at full speed, `2√d_b(√min(D, d_b) − √max(ε, r_0))/v_max` braking, and
/// `ln(r_0/ε)/λ_0` in the linear core (`λ_0 = v_max/√(r_0 d_b)`) if `ε < r_0`.
fn closed_form_arrival(law: &Kinematic, distance: f64, eps: f64) -> f64 {
    let (v, d_b, r_0) = (law.v_max(), law.braking_distance(), law.linear_core());
    let full = (distance - d_b).max(0.0) / v;
    let braking = 2.0 * d_b.sqrt() * (distance.min(d_b).sqrt() - eps.max(r_0).sqrt()) / v;
    let core = (r_0 / eps).ln().max(0.0) / (v / (r_0 * d_b).sqrt());
    full + braking + core
}

/// The speed profile of `"auto"` is continuous and Lipschitz in `r = |x − x_d|` with the
/// constant `λ_0 = v_max/√(r_0 d_b)` of its linear core, so solutions of the closed loop are
/// unique and the goal is approached as by a linear law: sampled on both sides of `d_b` and
/// `r_0` and across six decades.
#[test]
fn auto_speed_is_continuous_and_lipschitz_in_the_distance() {
    let ws = Workspace::new(
        StarShape::circle(Vector2::zeros(), 5.0).unwrap(),
        Vec::new(),
        Vector2::zeros(),
    )
    .unwrap();
    let field = Field::all_known(Arc::new(ws)).unwrap();
    let e = field.eval(Vector2::new(1.0, 0.0)).unwrap();
    for v_max in [0.2, 2f64.sqrt(), 7.0] {
        let law = Kinematic::new(1.0).unwrap().with_v_max(v_max).unwrap();
        let (d_b, r_0) = (law.braking_distance(), law.linear_core());
        let lipschitz = v_max / (r_0 * d_b).sqrt();
        for edge in [d_b, r_0] {
            let (below, above) = (law.speed(&e, edge * (1.0 - 1e-12)), law.speed(&e, edge));
            assert!((above - below).abs() <= 1e-10 * above, "jump at {edge}");
        }
        let mut rng = Rng::new(77);
        for _ in 0..2000 {
            let r1 = r_0 * 10f64.powf(rng.uniform(-3.0, 4.0));
            let r2 = r1 * rng.uniform(0.5, 2.0);
            let (s1, s2) = (law.speed(&e, r1), law.speed(&e, r2));
            assert!(s1 > 0.0 && s1 <= v_max);
            assert!((s1 - s2).abs() <= lipschitz * (r1 - r2).abs() * (1.0 + 1e-12));
            assert!(
                (s1 < s2) == (r1 < r2) || s1 == s2,
                "not increasing at {r1}, {r2}"
            );
        }
    }
}

/// Finite-time arrival under `"auto"`: with the goal at the centre of a disc world the flow
/// lines are straight rays, and the arrival time within `ε` from a distance `D ≥ d_b` is the
/// closed form of [`closed_form_arrival`] (`docs/maths.md` §6), bounded by
/// `(D + d_b)/v_max + ln(r_0/ε)⁺/λ_0` for every `ε`. The paper's law needs `~ln(D/ε)/(K√σ)`.
#[test]
fn auto_speed_arrives_in_the_closed_form_time() {
    let ws = Workspace::new(
        StarShape::circle(Vector2::zeros(), 5.0).unwrap(),
        Vec::new(),
        Vector2::zeros(),
    )
    .unwrap();
    let field = Field::all_known(Arc::new(ws)).unwrap();
    let law = Kinematic::new(1.0).unwrap();
    let (v, db, r_0) = (law.v_max(), law.braking_distance(), law.linear_core());
    let lambda = v / (r_0 * db).sqrt();
    let start = Vector2::new(2.0, 1.0);
    let d = start.norm();
    for eps in [1e-2, 1e-4, 1e-6, 1e-9] {
        let closed = closed_form_arrival(&law, d, eps);
        let t = arrival_time(&field, &law, start, eps, 1e-4, 10.0).unwrap();
        assert!((t - closed).abs() < 2e-3, "ε = {eps}: {t} s vs {closed} s");
        let bound = (d + db) / v + (r_0 / eps).ln().max(0.0) / lambda;
        assert!(t <= bound + 1e-3, "ε = {eps}: {t} s > {bound} s");
    }
    // The paper's law is slower, and ever slower as the tolerance shrinks.
    let paper = law.with_speed(SpeedPolicy::Paper);
    let t2 = arrival_time(&field, &paper, start, 1e-2, 1e-3, 100.0).unwrap();
    let t4 = arrival_time(&field, &paper, start, 1e-4, 1e-3, 100.0).unwrap();
    let auto = arrival_time(&field, &law, start, 1e-2, 1e-3, 100.0).unwrap();
    assert!(
        t2 > 1.5 * auto && t4 > t2 + 1.0,
        "paper {t2} s, {t4} s; auto {auto} s"
    );
}

/// Finite-time arrival in random worlds: from a point `D < d_b` from the goal the approach
/// takes at most `2(√(D d_b) − √(ε d_b))/(c·v_max)` (`ε ≥ r_0`), where `c` bounds `−d·(x − x_d)/r`
/// from below (`Phi` is the identity near the goal and its Hessian is `σI`, so `c → 1`;
/// `c = 0.9` here). Integrated, the time is within that bound.
#[test]
fn auto_speed_arrives_within_the_finite_time_bound_in_random_worlds() {
    let law = Kinematic::new(1.0).unwrap();
    let (v, db) = (law.v_max(), law.braking_distance());
    let eps = 1e-4;
    let mut tested = 0;
    for seed in 0..30 {
        let (field, mut rng) = world(1300 + seed);
        let goal = field.workspace().destination();
        let a = rng.uniform(0.0, std::f64::consts::TAU);
        let start = 0.5 * db;
        let x = goal + start * Vector2::new(a.cos(), a.sin());
        if field.eval(x).is_err() {
            continue;
        }
        assert!(eps >= law.linear_core());
        let bound = 2.0 * ((start * db).sqrt() - (eps * db).sqrt()) / (0.9 * v);
        let t = arrival_time(&field, &law, x, eps, 1e-4, 10.0)
            .unwrap_or_else(|| panic!("seed {seed}: no arrival"));
        assert!(t <= bound, "seed {seed}: {t} s > bound {bound} s");
        tested += 1;
    }
    assert!(tested >= 20, "{tested}");
}

/// Eq. (dissipationfun): the damping switches to (m/d_min)|ẋ(T_n)| once V ≥ μ_p (μ_p the law's
/// pull: μ, 4μ under "governed"); under "auto" and "governed" it is never below that.
#[test]
fn damping_switches_on_energy() {
    let (field, mut rng) = world(7);
    let paper = Dynamic::new(2.0, 10.0, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Paper);
    let auto = paper.with_damping(DampingPolicy::Auto);
    let governed = paper.with_damping(DampingPolicy::Governed);
    assert_eq!(governed.pull(), PULL_GAIN * 10.0);
    for _ in 0..50 {
        let x = random::free_point(&mut rng, field.workspace(), 0.05);
        let e = field.eval(x).unwrap();
        // Speeds that put V just below and at μ_p: ½m|v|² = μ_p(1 − Ψ) ∓ ε.
        for law in [paper, auto, governed] {
            let (psi, mu_p) = (law.potential(&field, &e).value, law.pull());
            let speed = |target: f64| Vector2::new((2.0 * (target - mu_p * psi) / 2.0).sqrt(), 0.0);
            let (below, at) = (speed(mu_p * 0.9999), speed(mu_p * (1.0 + 1e-10)));
            assert!(law.energy(&field, &e, below) < mu_p && law.energy(&field, &e, at) >= mu_p);
            let d = law.damping(&field, &e, below, 3.0);
            assert_eq!(d.branch, Branch::Critical);
            let d = law.damping(&field, &e, at, 3.0);
            assert_eq!(d.branch, Branch::Switched);
            if law == governed {
                // The governor adds to the switched damping as to the critical one.
                let own = law.lambda_auto(&field, &e);
                let g = law.governor(law.potential(&field, &e).gradient.norm(), at);
                assert_eq!(d.lambda, (2.0 / 0.05 * 3.0f64).max(own) + g);
            }
        }
        let psi = paper.potential(&field, &e).value;
        let speed = |target: f64| Vector2::new((2.0 * (target - 10.0 * psi) / 2.0).sqrt(), 0.0);
        let (below, at) = (speed(9.999), speed(10.0 + 1e-9));
        let d = paper.damping(&field, &e, below, 3.0);
        assert_eq!(
            (d.lambda, d.branch),
            (paper.lambda_c(&field), Branch::Critical)
        );
        let d = paper.damping(&field, &e, at, 3.0);
        assert_eq!((d.lambda, d.branch), (2.0 / 0.05 * 3.0, Branch::Switched));
        let psi = auto.potential(&field, &e).value;
        let speed = |target: f64| Vector2::new((2.0 * (target - 10.0 * psi) / 2.0).sqrt(), 0.0);
        let (below, at) = (speed(9.999), speed(10.0 + 1e-9));
        let own = auto.lambda_auto(&field, &e);
        let d = auto.damping(&field, &e, below, 3.0);
        assert_eq!((d.lambda, d.branch), (own, Branch::Critical));
        assert_eq!(d.uphill, UPHILL_GAIN * own);
        let d = auto.damping(&field, &e, at, 3.0);
        assert_eq!(d.branch, Branch::Switched);
        assert_eq!(d.lambda, (2.0 / 0.05 * 3.0f64).max(own));
        assert!(auto.damping(&field, &e, at, 1e-3).lambda >= own);
        assert_eq!(paper.damping(&field, &e, at, 3.0).uphill, 0.0);
        // The uphill brake acts on the climbing component only: −Λẋ with Λ = λI + λ_up·nnᵀ
        // uphill, λI downhill and across.
        let g = auto.potential(&field, &e).gradient;
        let n = g / g.norm();
        let across = Vector2::new(-n.y, n.x);
        let d = auto.damping(&field, &e, Vector2::zeros(), 0.0);
        let brake = |v: Vector2<f64>| {
            auto.force(&field, &e, v, &d) - auto.force(&field, &e, Vector2::zeros(), &d)
        };
        assert!((brake(-n) - d.lambda * n).norm() < 1e-9 * d.lambda);
        assert!((brake(across) + d.lambda * across).norm() < 1e-9 * d.lambda);
        let up = -(d.lambda + d.uphill) * n;
        assert!((brake(n) - up).norm() < 1e-9 * (d.lambda + d.uphill));
        let v = 0.6 * n + 0.8 * across;
        assert!((brake(v) - (-d.lambda * v - d.uphill * 0.6 * n)).norm() < 1e-9 * d.uphill);
        assert!(brake(v).dot(&v) <= 0.0);
    }
    // λ_c = 2√(2μm) Π|P_d − P_i|^{−1/k} (eq. critdamp), evaluated directly.
    let pw = field.point_world();
    let prod: f64 = pw
        .obstacles()
        .iter()
        .map(|p| (pw.destination() - p).norm().powf(-1.0 / pw.k()))
        .product();
    let direct = 2.0 * (2.0 * 10.0 * 2.0f64).sqrt() * prod;
    assert!((paper.lambda_c(&field) - direct).abs() < 1e-12 * direct);
    assert!(Dynamic::new(0.0, 1.0, 1.0).is_err() && Dynamic::new(1.0, f64::NAN, 1.0).is_err());
    // A μ whose pull 4μ would overflow is refused, naming `controller.mu`.
    let e = Dynamic::new(1.0, f64::MAX / 2.0, 1.0).unwrap_err();
    assert_eq!((e.field, e.value), ("controller.mu", f64::MAX / 2.0));
    assert!(Dynamic::new(1.0, f64::MAX / 8.0, 1.0).is_ok());
    assert!(Kinematic::new(-1.0).is_err());
}

/// The "auto" damping is `2√(mμ)|∇√(2Ψ)|`: against central differences of `√(2Ψ)` (independent
/// of `∇Ψ`) at random points, and equal to `λ_c` in the limit at the goal, where its damping
/// ratio is therefore 1 (corollary critdamp).
#[test]
fn auto_damping_is_the_gradient_of_root_two_theta_and_lambda_c_at_the_goal() {
    for seed in 0..30 {
        let (field, mut rng) = world(300 + seed);
        // "auto" (pull μ) and the default "governed" (pull 4μ) on alternate seeds.
        let policy = [DampingPolicy::Auto, DampingPolicy::Governed][seed as usize % 2];
        let law = Dynamic::new(1.0 + 0.2 * seed as f64, 10.0, 0.05)
            .unwrap()
            .with_damping(policy);
        let root =
            |x: Vector2<f64>| (2.0 * law.potential(&field, &field.eval(x).unwrap()).value).sqrt();
        for _ in 0..20 {
            let x = random::free_point(&mut rng, field.workspace(), 0.05);
            let h = 1e-6;
            let fd = Vector2::new(
                root(x + Vector2::new(h, 0.0)) - root(x - Vector2::new(h, 0.0)),
                root(x + Vector2::new(0.0, h)) - root(x - Vector2::new(0.0, h)),
            ) / (2.0 * h);
            // "governed" is "auto" with the pull μ_p for μ.
            let want = 2.0 * (law.mass() * law.pull()).sqrt() * fd.norm();
            let got = law.lambda_auto(&field, &field.eval(x).unwrap());
            assert!(
                (got - want).abs() <= 1e-5 * want + 1e-9,
                "seed {seed} at {x:?}: {got} vs {want}"
            );
            // The terminal speed μ_p|∇Ψ|/λ is ½√(μ_p/m)·√(2Ψ), which is √(2μ/m)·√Ψ at
            // μ_p = 4μ ("governed"): the speed bound of corollary boundedvel times √Ψ; half
            // that under "auto".
            let p = law.potential(&field, &field.eval(x).unwrap());
            let terminal = law.pull() * p.gradient.norm() / got;
            let closed = 0.5 * (law.pull() / law.mass()).sqrt() * (2.0 * p.value).sqrt();
            let share = if policy == DampingPolicy::Governed {
                1.0
            } else {
                0.5
            };
            let spans = share * law.speed_bound() * p.value.sqrt();
            assert!(
                (terminal - closed).abs() <= 1e-12 * closed
                    && (terminal - spans).abs() <= 1e-12 * spans,
                "{terminal} vs {closed}, {spans}"
            );
        }
        let xd = field.workspace().destination();
        let lc = law.lambda_c(&field);
        assert_eq!(law.lambda_auto(&field, &field.eval(xd).unwrap()), lc);
        for r in [1e-3, 1e-5, 1e-7] {
            let a = rng.uniform(0.0, std::f64::consts::TAU);
            let e = field.eval(xd + r * Vector2::new(a.cos(), a.sin())).unwrap();
            let rel = (law.lambda_auto(&field, &e) - lc).abs() / lc;
            assert!(
                rel < 20.0 * r,
                "seed {seed}, r = {r}: λ/λ_c − 1 = {rel:.2e}"
            );
        }
    }
}

/// The shaped potential of "shaped": `Ψ = 1 − √(1 − Θ)` (the naive formula where it is
/// accurate), `∇Ψ` against central differences of `Ψ`, values in [0, 1], `Ψ ≈ Θ/2` at the
/// goal, and a finite, non-zero gradient at 1e-9 m from an obstacle, where `1 − Θ` is below
/// 1e-2.
#[test]
fn shaped_potential_is_a_function_of_theta_with_the_chain_rule_gradient() {
    let law = Dynamic::new(1.0, 10.0, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Shaped);
    let paper = law.with_damping(DampingPolicy::Paper);
    for seed in 0..30 {
        let (field, mut rng) = world(400 + seed);
        for _ in 0..20 {
            let x = random::free_point(&mut rng, field.workspace(), 0.05);
            let e = field.eval(x).unwrap();
            assert_eq!(paper.potential(&field, &e).value, e.value);
            let p = law.potential(&field, &e);
            let naive = 1.0 - (1.0 - e.value).sqrt();
            assert!((p.value - naive).abs() <= 1e-12, "{} vs {naive}", p.value);
            assert!((0.0..=1.0).contains(&p.value));
            let h = 1e-6;
            let psi = |d: Vector2<f64>| law.potential(&field, &field.eval(x + d).unwrap()).value;
            let fd = Vector2::new(
                psi(Vector2::new(h, 0.0)) - psi(Vector2::new(-h, 0.0)),
                psi(Vector2::new(0.0, h)) - psi(Vector2::new(0.0, -h)),
            ) / (2.0 * h);
            assert!(
                (fd - p.gradient).norm() <= 1e-5 * p.gradient.norm() + 1e-9,
                "seed {seed}: {fd:?} vs {:?}",
                p.gradient
            );
        }
        let xd = field.workspace().destination();
        let e = field.eval(xd + Vector2::new(1e-4, 0.0)).unwrap();
        assert!((law.potential(&field, &e).value / e.value - 0.5).abs() < 1e-6);
        assert_eq!(law.potential(&field, &field.eval(xd).unwrap()).value, 0.0);
        // Just outside an obstacle: the gradient is finite and points away from it.
        let o = &field.workspace().obstacles()[0];
        let dir: Vector2<f64> = Vector2::new(1.0, 0.3).normalize();
        let b = o.boundary_point(dir.y.atan2(dir.x));
        if let Ok(e) = field.eval(b + 1e-9 * (b - o.centre()).normalize()) {
            let g = law.potential(&field, &e).gradient;
            assert!(g.iter().all(|v| v.is_finite()) && g.norm() > 0.0, "{g:?}");
            assert!(g.norm() >= e.gradient.norm() / 2.0);
        }
    }
}

/// A world of three shapes scaled by `alpha` (outer radius 5·alpha m).
fn scaled_world(alpha: f64) -> Field {
    let v = |x: f64, y: f64| alpha * Vector2::new(x, y);
    let ws = Workspace::new(
        StarShape::circle(v(0.0, 0.0), 5.0 * alpha).unwrap(),
        vec![
            StarShape::circle(v(1.0, 0.5), 0.5 * alpha).unwrap(),
            StarShape::ellipse(v(-2.0, 1.0), [0.8 * alpha, 0.3 * alpha], 0.5).unwrap(),
            StarShape::circle(v(0.5, -2.0), 0.4 * alpha).unwrap(),
        ],
        v(4.0, 0.0),
    )
    .unwrap();
    Field::all_known(Arc::new(ws)).unwrap()
}

/// "auto" is free of the world's scale: in a copy of a world scaled by `α`, `Ψ(αx) = Ψ(x)`
/// and `∇Ψ(αx) = ∇Ψ(x)/α`, and `λ_c` scales by `1/α`, so the closed loop `m ẍ = −μ∇Ψ − λẋ`
/// is the same at `α` times the length and time scale. "shaped" is not (its `Ψ` saturates in
/// the larger world). At the reference radius "auto" is "shaped". `∇Ψ` of "auto" against
/// central differences, and `Ψ ≈ e^{−s}Θ/2` at the goal.
#[test]
fn auto_potential_is_free_of_the_worlds_scale() {
    let auto = Dynamic::new(1.0, 10.0, 0.05).unwrap();
    let shaped = auto.with_damping(DampingPolicy::Shaped);
    let base = scaled_world(1.0);
    let points = [
        Vector2::new(-4.0, 0.1),
        Vector2::new(0.0, 0.0),
        Vector2::new(2.0, 2.0),
        Vector2::new(3.9, 0.0),
        Vector2::new(-4.95, 0.0),
        Vector2::new(1.0, 1.0005),
    ];
    assert_eq!(auto.scale_shift(&base), 0.0, "5 m is the reference radius");
    for alpha in [1e-3, 0.1, 4.0, 20.0, 1e4] {
        let field = scaled_world(alpha);
        assert!(auto.scale_shift(&field).abs() > 0.0);
        for x in points {
            let (e0, e1) = (base.eval(x).unwrap(), field.eval(alpha * x).unwrap());
            let (p0, p1) = (auto.potential(&base, &e0), auto.potential(&field, &e1));
            assert!(
                (p1.value - p0.value).abs() <= 1e-9 * p0.value,
                "α = {alpha}, x = {x:?}: Ψ {} vs {}",
                p1.value,
                p0.value
            );
            let g = alpha * p1.gradient;
            assert!(
                (g - p0.gradient).norm() <= 1e-8 * p0.gradient.norm(),
                "α = {alpha}, x = {x:?}: {g:?} vs {:?}",
                p0.gradient
            );
            // Shaped Ψ saturates towards 1 in the larger world, or falls towards 0 in the
            // smaller: it differs from the 5 m world's.
            let s1 = shaped.potential(&field, &e1).value;
            assert!((s1 - p0.value).abs() > 1e-3 * p0.value, "α = {alpha}: {s1}");
            // The gradient against central differences of Ψ, at the world's scale.
            let h = 1e-6 * alpha;
            let psi = |d: Vector2<f64>| {
                auto.potential(&field, &field.eval(alpha * x + d).unwrap())
                    .value
            };
            let fd = Vector2::new(
                psi(Vector2::new(h, 0.0)) - psi(Vector2::new(-h, 0.0)),
                psi(Vector2::new(0.0, h)) - psi(Vector2::new(0.0, -h)),
            ) / (2.0 * h);
            assert!(
                (fd - p1.gradient).norm() <= 1e-5 * p1.gradient.norm(),
                "α = {alpha}: {fd:?} vs {:?}",
                p1.gradient
            );
        }
        let rel = auto.lambda_c(&field) * alpha / auto.lambda_c(&base) - 1.0;
        assert!(rel.abs() < 1e-9, "α = {alpha}: λ_c·α off by {rel:e}");
        let xd = field.workspace().destination();
        let e = field.eval(xd + alpha * Vector2::new(1e-7, 0.0)).unwrap();
        let expected = 0.5 * (-auto.scale_shift(&field)).exp();
        let got = auto.potential(&field, &e).value / e.value;
        assert!((got / expected - 1.0).abs() < 1e-3, "{got} vs {expected}");
        assert_eq!(auto.potential(&field, &field.eval(xd).unwrap()).value, 0.0);
    }
    // At the reference radius "auto" and "shaped" agree exactly.
    for x in points {
        let e = base.eval(x).unwrap();
        assert_eq!(auto.potential(&base, &e), shaped.potential(&base, &e));
    }
}

/// `"fast"`: `∇Ψ` against central differences of `Ψ` in random worlds, at random free points
/// and at points 1 cm to 1 µm from the goal (the bowl's core) and in the scaled worlds
/// (1 mm to 10 km), where its goal bowl is in metres.
#[test]
fn fast_potential_gradient_matches_finite_differences() {
    let fast = Dynamic::new(1.0, 10.0, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Fast);
    let check = |field: &Field, x: Vector2<f64>, h: f64| {
        let p = fast.potential(field, &field.eval(x).unwrap());
        assert!(
            p.value.is_finite() && (0.0..1.0).contains(&p.value),
            "{p:?}"
        );
        let psi = |d: Vector2<f64>| fast.potential(field, &field.eval(x + d).unwrap()).value;
        let fd = Vector2::new(
            psi(Vector2::new(h, 0.0)) - psi(Vector2::new(-h, 0.0)),
            psi(Vector2::new(0.0, h)) - psi(Vector2::new(0.0, -h)),
        ) / (2.0 * h);
        assert!(
            (fd - p.gradient).norm() <= 1e-5 * p.gradient.norm() + 1e-12,
            "x = {x:?}: {fd:?} vs {:?}",
            p.gradient
        );
    };
    for seed in 0..30 {
        let (field, mut rng) = world(1300 + seed);
        for _ in 0..10 {
            let x = random::free_point(&mut rng, field.workspace(), 0.05);
            check(&field, x, 1e-6);
        }
        let xd = field.workspace().destination();
        for r in [1e-2, 1e-4, 1e-6] {
            check(&field, xd + Vector2::new(0.6 * r, 0.8 * r), 1e-3 * r);
        }
    }
    for alpha in [1e-3, 1.0, 20.0, 1e4] {
        let field = scaled_world(alpha);
        for x in [
            Vector2::new(-4.0, 0.1),
            Vector2::new(2.0, 2.0),
            Vector2::new(3.9, 0.0),
        ] {
            check(&field, alpha * x, 1e-6 * alpha);
        }
    }
}

/// `"fast"`: `Ψ = g(Θ)` with `g` strictly increasing from `g(0) = 0` to `g(1) = 1`, and finite
/// with a finite gradient from the goal (`phi = −∞`) to far past saturation (`phi = 1e300`),
/// where it must not produce a NaN. The evaluations are synthetic: `Θ = sigma(phi)` and
/// `∇Θ = sigma'(phi)·e_x`, so `∇Ψ = g'(Θ)·∇Θ`, which is also checked against the slope of `g`.
#[test]
fn fast_shaping_is_strictly_increasing_and_finite_from_the_goal_to_saturation() {
    use harmonav_field::FieldEval;
    use harmonav_potential::{sigma, sigma_prime};
    let fast = Dynamic::new(1.0, 10.0, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Fast);
    let eval = |phi: f64| FieldEval {
        value: sigma(phi),
        gradient: Vector2::new(sigma_prime(phi), 0.0),
        direction: Some(Vector2::new(-1.0, 0.0)),
        h: Vector2::zeros(),
        phi,
    };
    for (sigma_d, shift) in [(1.0, 0.0), (0.02, 3.0), (50.0, -2.0)] {
        let psi = |phi: f64| fast.potential_for((sigma_d, shift), &eval(phi));
        assert_eq!(psi(f64::NEG_INFINITY).value, 0.0);
        assert_eq!(psi(f64::NEG_INFINITY).gradient, Vector2::zeros());
        for phi in [800.0, 1e4, 1e300, f64::INFINITY] {
            let p = psi(phi);
            assert!((p.value - 1.0).abs() < 1e-12, "phi {phi}: {p:?}");
            assert!(p.gradient.iter().all(|c| c.is_finite()), "phi {phi}: {p:?}");
        }
        let mut last = psi(-800.0);
        let mut phi = -800.0;
        while phi < 800.0 {
            phi += 0.25;
            let p = psi(phi);
            assert!(p.value.is_finite() && p.gradient.iter().all(|c| c.is_finite()));
            // Non-decreasing to rounding (the two terms' sum may lose an ulp where Ψ ≈ 1).
            assert!(
                p.value >= last.value - 4.0 * f64::EPSILON,
                "phi {phi}: {} < {}",
                p.value,
                last.value
            );
            // Strictly, wherever the values are apart from rounding.
            if (-60.0..40.0).contains(&phi) {
                assert!(
                    p.value > last.value,
                    "phi {phi}: {} ≤ {}",
                    p.value,
                    last.value
                );
                // ∇Ψ = g'(Θ)∇Θ with g' > 0: along +e_x, and equal to the slope dΨ/dphi.
                // (Central differences of step 1e-4: truncation ~1e-8 relative, rounding
                // ~1e-12 absolute.)
                let d = 1e-4;
                let slope = (psi(phi + d).value - psi(phi - d).value) / (2.0 * d);
                assert!(p.gradient.x > 0.0 && p.gradient.y == 0.0);
                assert!(
                    (p.gradient.x - slope).abs() <= 1e-6 * slope + 1e-11,
                    "phi {phi}: {} vs {slope}",
                    p.gradient.x
                );
            }
            last = p;
        }
    }
}

/// `"fast"`: the bowl is in metres. Near the goal `Ψ ≈ ½H|x − x_d|²` with
/// `H = (w/L + (1 − w)/L_A)/b` (`Dynamic::goal_stiffness`) in worlds of 5 mm to 50 km, so the
/// critical damping `2√(mμH)` is the policy's `λ(x)` in the limit (damping ratio 1; the
/// finite-difference check of every policy is `critical_damping_at_the_goal`).
#[test]
fn fast_bowl_is_in_metres_and_critically_damped_at_the_goal() {
    let fast = Dynamic::new(2.0, 10.0, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Fast);
    for alpha in [1e-3, 1.0, 20.0, 1e4] {
        let field = scaled_world(alpha);
        let xd = field.workspace().destination();
        let h = fast.goal_stiffness(&field);
        let r = 1e-6 * alpha.min(1.0);
        let e = field.eval(xd + Vector2::new(0.0, r)).unwrap();
        let p = fast.potential(&field, &e);
        assert!(
            (p.value / (0.5 * h * r * r) - 1.0).abs() < 1e-3,
            "α = {alpha}"
        );
        let lambda = fast.lambda_auto(&field, &e);
        let lc = fast.lambda_c(&field);
        assert!(
            (lambda / lc - 1.0).abs() < 1e-3,
            "α = {alpha}: {lambda} vs {lc}"
        );
        assert!((lc - 2.0 * (2.0 * 10.0 * h).sqrt()).abs() < 1e-12 * lc);
        // The bowl's part does not depend on the world: at α ≥ 1 it dominates H.
        if alpha >= 1.0 {
            let (w, b, l) = (
                harmonav_control::FAST_BOWL_WEIGHT,
                harmonav_control::FAST_BOWL_CORE,
                harmonav_control::FAST_BRAKING_LENGTH,
            );
            assert!(
                h >= w / (b * l) && h < 1.5 * w / (b * l),
                "α = {alpha}: {h}"
            );
        }
    }
}

/// The governor of "governed" (the default; `docs/maths.md` §9, part 5): at every state whose
/// speed is at least `s₂·√(2μ/m)` the force does no positive work, `f·ẋ ≤ 0`, so the speed
/// cannot grow past `s₂·√(2μ/m) < √(2μ/m)` although the energy `V < μ_p = 4μ` alone allows
/// `2√(2μ/m)`; below `s₁·√(2μ/m)` it is off and the law is exactly "auto" with `μ_p` for `μ`.
/// Negative control: that same law without the governor does positive work at some of these
/// states, so the check bites.
#[test]
fn the_governor_takes_the_power_of_the_pull_above_nine_tenths_of_the_speed_bound() {
    let (s1, s2) = GOVERNOR_BAND;
    let mut ungoverned_gains = 0;
    for seed in 0..20 {
        let (field, mut rng) = world(700 + seed);
        let law = Dynamic::new(0.5 + 0.2 * seed as f64, 10.0, 0.05).unwrap();
        assert_eq!(law.damping_policy(), DampingPolicy::Governed);
        assert_eq!(law.pull(), PULL_GAIN * law.mu());
        let bare = Dynamic::new(law.mass(), law.pull(), 0.05)
            .unwrap()
            .with_damping(DampingPolicy::Auto);
        let vb = law.speed_bound();
        for i in 0..60 {
            let x = random::free_point(&mut rng, field.workspace(), 0.02);
            let e = field.eval(x).unwrap();
            let angle = rng.uniform(0.0, std::f64::consts::TAU);
            let gradient = law.potential(&field, &e).gradient;
            // Half the states at or above s₂ (half of them downhill, where an ungoverned pull
            // can still accelerate: below its terminal speed √(2μ/m)·√Ψ), a quarter in the
            // band (s₁, s₂) where the governor rises, a quarter below s₁.
            let dir = if i % 4 == 0 {
                -gradient.normalize()
            } else {
                Vector2::new(angle.cos(), angle.sin())
            };
            let speed = match i % 4 {
                0 => vb * rng.uniform(s2, 1.0),
                2 => vb * rng.uniform(s2, 1.5),
                1 => vb * rng.uniform(0.0, s1),
                _ => vb * rng.uniform(s1 + 1e-3, s2 - 1e-3),
            };
            let v = speed * dir;
            let force = |l: &Dynamic| l.force(&field, &e, v, &l.damping(&field, &e, v, 0.0));
            let (f, f_bare) = (force(&law), force(&bare));
            let pull = law.pull() * gradient.norm() * speed;
            if i % 2 == 0 {
                assert!(
                    f.dot(&v) <= 1e-12 * pull,
                    "seed {seed} at {x:?}, |v| = {speed}: power {} of {pull}",
                    f.dot(&v)
                );
                ungoverned_gains += usize::from(f_bare.dot(&v) > 1e-9 * pull);
            } else if i % 4 == 1 {
                assert_eq!(f, f_bare, "seed {seed}: the governor acts below s₁");
            } else {
                // In the band: λ_g = χ·μ_p|∇Ψ|/|ẋ| with 0 < χ < 1, on top of "auto"'s λ.
                let g = law.governor(gradient.norm(), v);
                let full = law.pull() * gradient.norm() / speed;
                assert!(g > 0.0 && g < full, "seed {seed}: λ_g = {g} of {full}");
                let added = law.damping(&field, &e, v, 0.0).lambda
                    - bare.damping(&field, &e, v, 0.0).lambda;
                assert!(
                    (added - g).abs() <= 1e-12 * (g + added.abs()),
                    "{added} vs {g}"
                );
            }
        }
    }
    assert!(
        ungoverned_gains >= 5,
        "the pull without the governor accelerated in only {ungoverned_gains} of the 600 states at or above s₂"
    );
}

/// The governor along trajectories (`checks::energy_run_from`, RK4): from a start at or above
/// `s₂·√(2μ/m)` the speed never rises while it is there, and `V` never rises. Two starts per
/// world, at a point where `Ψ > 0.85` moving downhill: one at 1.2 times the bound (above the
/// precondition `|ẋ(0)| < √(2μ/m)`: the governor still never speeds the robot up), one between
/// `s₂·√(2μ/m)` and the terminal speed `√(2μ/m)·√Ψ` of the ungoverned pull. Negative control:
/// from that second start the same law without the governor speeds up.
#[test]
fn a_governed_trajectory_never_speeds_up_above_nine_tenths_of_the_speed_bound() {
    let s2 = GOVERNOR_BAND.1;
    let mut bare_rises = 0;
    for seed in 0..20 {
        let (field, mut rng) = world(800 + seed);
        let law = Dynamic::new(0.5 + 0.1 * seed as f64, 10.0, 0.05).unwrap();
        let bare = Dynamic::new(law.mass(), law.pull(), 0.05)
            .unwrap()
            .with_damping(DampingPolicy::Auto);
        let vb = law.speed_bound();
        let (x, p) = (0..100_000)
            .map(|_| random::free_point(&mut rng, field.workspace(), 0.002))
            .map(|x| (x, law.potential(&field, &field.eval(x).unwrap())))
            .find(|(_, p)| p.value > 0.85 && p.gradient.norm() > 0.0)
            .expect("a point with Ψ > 0.85");
        let down = -p.gradient.normalize();
        let between = 0.5 * (s2 + p.value.sqrt());
        for (start, l) in [(1.2, &law), (between, &law), (between, &bare)] {
            let run = energy_run_from(&field, l, (x, start * vb * down), 1e-4, 300).unwrap();
            assert!(
                run.worst_rise <= 1e-9,
                "seed {seed}: V rose by {:e}",
                run.worst_rise
            );
            if l == &bare {
                // (Its own s₂ is that of its bound √(2·4μ/m), so its top speed tells.)
                bare_rises += usize::from(run.max_speed > start * vb * (1.0 + 1e-9));
                continue;
            }
            assert!(
                run.worst_fast_speed_rise <= 1e-12 * vb,
                "seed {seed}, |ẋ(0)| = {start}·v_b: the speed rose by {:e} m/s above s₂",
                run.worst_fast_speed_rise
            );
            assert!(run.max_speed <= start * vb * (1.0 + 1e-12));
        }
    }
    assert!(
        bare_rises == 20,
        "without the governor the speed rose above s₂ in {bare_rises} of 20 worlds only"
    );
}

/// The pull of "governed" grows with the world, `μ_p = 4μ·max(1, ρ/5 m)`, and only under
/// "governed"; a world size or a pull that is not finite and positive is refused, naming
/// `world_radius`, and the speed bound stays `√(2μ/m)` whatever the pull.
#[test]
fn the_governed_pull_grows_with_the_world_radius() {
    let law = Dynamic::new(2.0, 10.0, 0.05).unwrap();
    assert_eq!(law.world_radius(), harmonav_control::REFERENCE_RADIUS);
    for (rho, want) in [
        (1.0, 40.0),
        (5.0, 40.0),
        (7.5, 60.0),
        (50.0, 400.0),
        (500.0, 4000.0),
    ] {
        let grown = law.with_world_radius(rho).unwrap();
        assert!((grown.pull() - want).abs() <= 1e-12 * want, "ρ = {rho}");
        assert_eq!(grown.speed_bound(), law.speed_bound());
        for policy in [
            DampingPolicy::Paper,
            DampingPolicy::Auto,
            DampingPolicy::Fast,
        ] {
            assert_eq!(grown.with_damping(policy).pull(), 10.0);
        }
    }
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = law.with_world_radius(bad).unwrap_err();
        assert_eq!(e.field, "world_radius");
    }
    let e = Dynamic::new(1.0, 1e300, 0.05)
        .unwrap()
        .with_world_radius(1e300)
        .unwrap_err();
    assert_eq!((e.field, e.value), ("world_radius", 1e300));
    // Refused under any policy: `with_damping` could switch to "governed" afterwards.
    let auto = Dynamic::new(1.0, 1e300, 0.05)
        .unwrap()
        .with_damping(DampingPolicy::Auto);
    assert!(auto.with_world_radius(1e300).is_err());
}

/// The governor where it matters: in a large world (`ρ` = 50 m, pull `40μ`) the law from rest
/// runs into the governor's band in the critical branch (`V < μ_p`), and the speed stays below
/// `0.9·√(2μ/m)` (RK4 over 3 s, the integrator's 0.1 %). Negative control: the same pull
/// without the governor ("auto" with `μ = 40μ`) exceeds the user's bound `√(2μ/m)`.
#[test]
fn in_a_large_world_the_governor_holds_a_robot_started_at_rest() {
    let s2 = GOVERNOR_BAND.1;
    let (mut governed_in_band, mut bare_over) = (0, 0);
    for seed in 0..12 {
        let (field, mut rng) = world(900 + seed);
        let law = Dynamic::new(1.0, 10.0, 0.05)
            .unwrap()
            .with_world_radius(50.0)
            .unwrap();
        assert_eq!(law.pull(), 400.0);
        let bare = Dynamic::new(1.0, law.pull(), 0.05)
            .unwrap()
            .with_damping(DampingPolicy::Auto);
        let vb = law.speed_bound();
        let start = random::free_point(&mut rng, field.workspace(), 0.2);
        let run = energy_run(&field, &law, start, 1e-4, 30_000).unwrap();
        assert!(
            run.worst_rise <= 1e-9,
            "seed {seed}: V rose by {:e}",
            run.worst_rise
        );
        assert!(
            run.max_speed <= s2 * vb * 1.001,
            "seed {seed}: {} of the bound",
            run.max_speed / vb
        );
        governed_in_band += usize::from(run.max_speed > GOVERNOR_BAND.0 * vb);
        let free = energy_run(&field, &bare, start, 1e-4, 30_000).unwrap();
        bare_over += usize::from(free.max_speed > vb);
    }
    assert!(
        governed_in_band >= 6,
        "the band reached in {governed_in_band} of 12"
    );
    assert!(
        bare_over >= 6,
        "without the governor over the bound in {bare_over} of 12"
    );
}
