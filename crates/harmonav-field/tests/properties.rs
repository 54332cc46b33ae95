//! Θ = sigma∘phi_k∘Phi on random valid worlds of all four shapes (seeded).

use std::sync::Arc;

use harmonav_field::checks::{self, near_boundaries};
use harmonav_field::{CriticalType, Field, KPolicy};
use harmonav_transform::Active;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x0048_4152_4D4E_4156),
        failure_persistence: None,
        ..Config::default()
    }
}

/// A random world (1–6 obstacles, any boundary kind) with every obstacle known, and an RNG.
fn world(seed: u64) -> (Field, Rng) {
    world_with(seed, KPolicy::default())
}

/// [`world`] with `k` from `policy`.
fn world_with(seed: u64, policy: KPolicy) -> (Field, Rng) {
    let mut rng = Rng::new(seed);
    let m = 1 + rng.below(6);
    let outer = KINDS[rng.below(4)];
    let ws = random::workspace(&mut rng, m, &KINDS, outer, 0.15);
    (
        Field::all_known_with(Arc::new(ws), policy).expect("valid world"),
        rng,
    )
}

proptest! {
    #![proptest_config(config(2500))]

    /// det J_Phi > 0 at random free points and within 1e-9 of every boundary; Phi⁻¹∘Phi = id
    /// (hence Phi injective on the samples); Θ finite in [0, 1] (`checks::{sample, round_trip}`).
    #[test]
    fn phi_is_a_diffeomorphism_on_samples(seed in any::<u64>(), th in -3.1..3.1f64) {
        let (field, mut rng) = world(seed);
        let ws = field.workspace();
        let near = near_boundaries(ws, th, 1e-9);
        let n_near = near.len();
        let mut pts = near;
        pts.extend((0..8).map(|_| random::free_point(&mut rng, ws, 1e-3)));
        let fail = |e: checks::Failure| TestCaseError::fail(e.to_string());
        for (i, x) in pts.into_iter().enumerate() {
            let s = checks::sample(&field, x).map_err(fail)?;
            prop_assert!(s.orientation_preserving(), "det J = {} at {x:?}", s.det);
            prop_assert!(s.is_sound(), "{:?} at {x:?}", s.eval);
            // Round trip: for interior samples only (see `checks::round_trip`).
            if i >= n_near {
                let trip = checks::round_trip(&field, x).map_err(fail)?;
                prop_assert!(trip <= 1e-8 * (1.0 + x.norm()), "round trip {x:?}: {trip:e}");
            }
        }
    }

    /// J_Phi and ∇Θ against central differences at random free points (`checks::fd_errors`).
    #[test]
    fn jacobian_and_gradient_match_finite_differences(seed in any::<u64>()) {
        let (field, mut rng) = world(seed);
        for _ in 0..4 {
            let x = random::free_point(&mut rng, field.workspace(), 0.02);
            let fd = checks::fd_errors(&field, x).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert!(fd.jacobian <= 1e-5, "J − FD: {:e} of |J| at {x:?}", fd.jacobian);
            prop_assert!(fd.gradient <= 1e-5 * fd.gradient_norm + 1e-9, "∇Θ − FD: {:e}, |∇Θ| = {:e}", fd.gradient, fd.gradient_norm);
            let m = field.transform().nav_transform(x).unwrap();
            if matches!(m.active, Active::Identity) {
                prop_assert_eq!(m.h, x);
            }
        }
    }

    /// Θ(x_d) = 0; Θ → 1 at every obstacle boundary and at the outer boundary, under both k
    /// policies (`checks::limits`). At an obstacle `phi_k = logit Θ` grows as `−(2/k)·ln δ` (δ
    /// the distance), so with the paper's `k = n + 1` Θ is above 0.85 at 1e-12, with
    /// `k = "auto"` it gets there only much closer (docs/maths.md §8).
    #[test]
    fn theta_is_zero_at_the_goal_and_one_on_the_boundaries(seed in any::<u64>(), th in -3.1..3.1f64) {
        for policy in KPolicy::ALL {
            let (field, _) = world_with(seed, policy);
            let fail = |e: checks::Failure| TestCaseError::fail(e.to_string());
            let outer = checks::limits(&field, th, 1e-3, 1e-6).map_err(fail)?;
            let inner = checks::limits(&field, th, 1e-6, 1e-12).map_err(fail)?;
            prop_assert_eq!(outer.at_goal, 0.0);
            for (a, b) in outer.approaches.iter().zip(&inner.approaches) {
                let (va, vb, vc) = (a.theta_far, b.theta_far, b.theta_near);
                prop_assert!(a.rises() && b.rises(), "{policy}: not increasing towards the boundary: {va} {vb} {vc}");
                if policy == KPolicy::Paper {
                    prop_assert!(vc > 0.85, "Θ = {vc} at 1e-12 from a boundary");
                }
                if let Some(rise) = b.rise {
                    prop_assert!((rise - 1.0).abs() < 1e-2, "{policy}: phi_k rose {rise} × (2/k)·ln 1e6");
                }
            }
        }
    }

    /// theorem isNF: the critical points of Θ are the destination (a minimum) and M saddles
    /// (pulled back from the point world), each a zero of ∇Θ (`checks::critical_points`) with
    /// index −1 (winding number of the descent direction along a small circle).
    #[test]
    fn critical_points_are_one_minimum_and_m_saddles(seed in any::<u64>()) {
        let (field, _) = world(seed);
        let census = checks::critical_points(&field).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(census.saddles, census.obstacles);
        prop_assert_eq!(census.minimum, field.workspace().destination());
        prop_assert!(census.worst_gradient_ratio < 1e-4, "|∇Θ| at a saddle: {:e} of its value nearby", census.worst_gradient_ratio);
        let cps = field.critical_points();
        for c in &cps[1..] {
            let r = 1e-4;
            let mut turn = 0.0;
            let n = 256;
            let angle = |i: usize| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let d = field.eval(c.x + r * Vector2::new(a.cos(), a.sin())).unwrap().direction.unwrap();
                d.y.atan2(d.x)
            };
            let mut prev = angle(0);
            for i in 1..=n {
                let next = angle(i % n);
                let mut d = next - prev;
                if d > std::f64::consts::PI { d -= std::f64::consts::TAU; }
                if d < -std::f64::consts::PI { d += std::f64::consts::TAU; }
                turn += d;
                prev = next;
            }
            let index = (turn / std::f64::consts::TAU).round() as i64;
            prop_assert_eq!(index, -(c.point_world.unwrap().multiplicity as i64), "at {:?}", c.x);
        }
    }
}

proptest! {
    #![proptest_config(config(300))]
    /// The census types the critical points and its Hessians are right: at the destination
    /// H(Θ) = s·I with the closed-form stiffness s (eq. critdamp); at a non-degenerate saddle
    /// the eigenvalues have opposite signs (lemma saddlep).
    #[test]
    fn census_hessians_match_the_closed_form_and_the_saddle_signs(seed in any::<u64>()) {
        let (field, _) = world(seed);
        let census = field.census();
        prop_assert_eq!((census.minima, census.saddles + census.degenerate), (1, census.points.len() - 1));
        let goal = census.points[0];
        prop_assert_eq!(goal.kind, CriticalType::Minimum);
        let s = field.destination_stiffness();
        let [lo, hi] = goal.eigenvalues.expect("the goal is inside the free space");
        prop_assert!((lo - s).abs() <= 1e-5 * s && (hi - s).abs() <= 1e-5 * s, "{lo}, {hi} vs {s}");
        for p in &census.points[1..] {
            if let (CriticalType::Saddle, Some([lo, hi])) = (p.kind, p.eigenvalues) {
                // sigma' may underflow far from the goal: then both are 0, never of one sign.
                prop_assert!(lo <= 0.0 && hi >= 0.0 && (lo < 0.0) == (hi > 0.0), "{lo}, {hi} at {:?}", p.x);
            }
        }
    }
}

proptest! {
    #![proptest_config(config(200))]
    /// The batched evaluation equals the single-point one bit for bit, for points everywhere:
    /// free, in the obstacle and outer bands, inside obstacles, outside, at the goal, NaN.
    #[test]
    fn eval_many_equals_eval_everywhere(seed in any::<u64>()) {
        let (field, mut rng) = world(seed);
        let ws = field.workspace();
        let mut xs: Vec<Vector2<f64>> = (0..150).map(|_| random::free_point(&mut rng, ws, 1e-3)).collect();
        for (i, th) in [0.3, 1.9, -2.2].into_iter().enumerate() {
            xs.extend(near_boundaries(ws, th, 1e-3 * (i + 1) as f64));
            xs.extend(near_boundaries(ws, th, -1e-3));
        }
        xs.extend([ws.destination(), Vector2::new(f64::NAN, 0.0), Vector2::new(1e300, 0.0)]);
        let mut out = vec![Err(harmonav_field::FieldError::Outside); xs.len()];
        field.eval_many(&xs, &mut out).unwrap();
        for (x, o) in xs.iter().zip(&out) {
            prop_assert_eq!(o, &field.eval(*x), "at {:?}", x);
        }
        prop_assert_eq!(field.eval(Vector2::new(f64::NAN, 0.0)), Err(harmonav_field::FieldError::NotFinite));
        let mut short = vec![Err(harmonav_field::FieldError::Outside); 3];
        prop_assert!(field.eval_many(&xs, &mut short).is_err());
    }
}

/// Discovery: k follows the policy (n + 1 for the paper, 6(n + 1) by default in this roomy world), obstacles are
/// never forgotten, Θ changes only through the known set.
#[test]
fn discovery_increments_k_and_remembers() {
    let mut rng = Rng::new(7);
    let ws = Arc::new(random::workspace(&mut rng, 4, &KINDS, Kind::Circle, 0.2));
    let mut auto = Field::new(ws.clone(), [2]).unwrap();
    assert_eq!((auto.k(), auto.k_policy()), (12.0, KPolicy::Auto));
    assert!(auto.discover(1).unwrap());
    assert_eq!(auto.k(), 18.0);
    let mut field = Field::with_policy(ws.clone(), [2], KPolicy::Paper).unwrap();
    assert_eq!(field.k(), 2.0);
    let x = random::free_point(&mut rng, &ws, 0.1);
    let before = field.eval(x).unwrap().value;
    assert!(field.discover(0).unwrap());
    assert!(!field.discover(2).unwrap(), "already known");
    assert_eq!(field.known(), &[2, 0]);
    assert_eq!(field.k(), 3.0);
    assert_ne!(field.eval(x).unwrap().value, before);
    assert!(field.discover(9).is_err());
    let full = Field::all_known_with(ws.clone(), KPolicy::Paper).unwrap();
    assert_eq!(full.k(), 5.0);
    // The unknown obstacle 1 is not part of Θ: its interior is "free" for the field.
    let inside = ws.obstacles()[1].centre() + Vector2::new(1e-3, 0.0);
    assert!(field.eval(inside).is_ok());
    assert!(full.eval(inside).is_err());
}
