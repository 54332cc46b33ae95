//! The multipole path of `phi_and_grad` (worlds of `FAR_MIN` points or more) against the direct
//! sums of `phi_k` and `grad_phi_k`, near and far from the points, with the exact offset of
//! pitfall C, and the tree extended by `new_after` as if built at once.

use harmonav_potential::far::{FAR_MIN, TOLERANCE};
use harmonav_potential::{PointWorld, Singularity, Vector2};

/// SplitMix64, deterministic and dependency-free.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A 100 m world of `m` scattered points (the obstacles' centres of the many-obstacle suite).
fn scattered(m: usize, seed: u64) -> (Vec<Vector2<f64>>, Rng) {
    let mut rng = Rng(seed);
    let points = (0..m)
        .map(|_| Vector2::new(100.0 * rng.next() - 50.0, 100.0 * rng.next() - 50.0))
        .collect();
    (points, rng)
}

/// `|Δphi| ≤ 4·TOLERANCE` (the far sum's `2·TOLERANCE·M/k` plus rounding) and the gradient
/// within `1e-10` of its size plus the far field's share.
fn assert_close(world: &PointWorld, h: Vector2<f64>, exact: Option<(usize, Vector2<f64>)>) {
    let (phi, g) = world.phi_and_grad(h, exact).unwrap();
    let (phi_d, g_d) = match exact {
        None => (world.phi_k(h), world.grad_phi_k(h).unwrap()),
        // The direct reference of the exact offset: the point world without that point plus
        // its term from the offset.
        Some((j, v)) => {
            let mut rest = world.obstacles().to_vec();
            rest.remove(j);
            let others = PointWorld::new(world.destination(), rest)
                .unwrap()
                .with_k(world.k())
                .unwrap();
            let (gx, r2) = (v / v.norm_squared(), v.norm_squared());
            (
                others.phi_k(h) - r2.ln() / world.k(),
                others.grad_phi_k(h).unwrap() - (2.0 / world.k()) * gx,
            )
        }
    };
    assert!(
        (phi - phi_d).abs() <= 4.0 * TOLERANCE * (1.0 + phi_d.abs() * 1e-3),
        "h = {h:?}: phi {phi} against {phi_d} (Δ {:e})",
        phi - phi_d
    );
    let scale = g_d.norm() + 2.0 * (world.obstacles().len() as f64) / world.k();
    assert!(
        (g - g_d).norm() <= 1e-10 * scale,
        "h = {h:?}: grad {g:?} against {g_d:?}"
    );
}

#[test]
fn the_multipole_path_matches_the_direct_sums() {
    for (m, seed) in [(FAR_MIN, 1u64), (1_000, 2), (3_000, 3)] {
        let (points, mut rng) = scattered(m, seed);
        let world = PointWorld::new(Vector2::new(3.3, -7.1), points.clone()).unwrap();
        assert!(world.has_far_field());
        // Everywhere in the world, far outside it (the outer band sends h far away), and a
        // hair from obstacle points.
        for _ in 0..400 {
            let h = Vector2::new(120.0 * rng.next() - 60.0, 120.0 * rng.next() - 60.0);
            assert_close(&world, h, None);
        }
        for r in [1e3, 1e6, 1e12] {
            assert_close(&world, Vector2::new(r, -0.3 * r), None);
        }
        for p in points.iter().step_by(97) {
            assert_close(&world, p + Vector2::new(1e-9, -2e-9), None);
        }
        // A larger k (KPolicy's layers) scales the far sum the same way.
        let world = world.with_k(3.0 * m as f64).unwrap();
        let h = Vector2::new(1.5, 2.5);
        assert_close(&world, h, None);
    }
    let (points, _) = scattered(FAR_MIN - 1, 4);
    assert!(
        !PointWorld::new(Vector2::zeros(), points)
            .unwrap()
            .has_far_field()
    );
}

#[test]
fn an_exact_offset_whose_point_is_not_near_falls_back_to_the_direct_sum() {
    // `exact` names point 5 while `h` is far from it: the multipole path cannot apply the
    // offset and the direct sum must.
    let (points, _) = scattered(1_000, 7);
    let world = PointWorld::new(Vector2::new(0.5, 0.5), points.clone()).unwrap();
    let h = -points[5] * 0.5 + Vector2::new(0.3, 0.1);
    let offset = h - points[5];
    assert!(offset.norm() > 5.0);
    assert_close(&world, h, Some((5, offset)));
    assert_eq!(
        world.phi_and_grad(h, Some((5, offset))),
        world
            .clone()
            .without_far_field()
            .phi_and_grad(h, Some((5, offset)))
    );
}

#[test]
fn the_batch_path_says_none_where_the_fast_path_does_not_apply() {
    let (points, _) = scattered(300, 8);
    let world = PointWorld::new(Vector2::new(0.5, 0.5), points.clone()).unwrap();
    let hs = [
        Vector2::new(1.0, 2.0),
        Vector2::new(f64::NAN, 0.0),
        Vector2::new(1e200, 0.0),
        points[3],
    ];
    let mut out = [None; 4];
    world.phi_and_grad_many(&hs, &mut out).unwrap();
    assert_eq!(out[0], Some(world.phi_and_grad(hs[0], None).unwrap()));
    assert_eq!(&out[1..], &[None, None, None]);
    // As the direct kernel does.
    let direct = world.without_far_field();
    let mut expected = [None; 4];
    direct.phi_and_grad_many(&hs, &mut expected).unwrap();
    assert_eq!(&expected[1..], &[None, None, None]);
}

#[test]
fn the_exact_offset_is_taken_for_its_point() {
    let (points, _) = scattered(1_000, 5);
    let world = PointWorld::new(Vector2::new(0.5, 0.5), points.clone()).unwrap();
    for j in [0, 17, 999] {
        // h = P_j + ν u with ν so small that h − P_j would lose the direction.
        let offset = Vector2::new(3e-17, -4e-17);
        let h = points[j] + offset;
        assert_close(&world, h, Some((j, offset)));
    }
    // At an obstacle point the singularity is reported, as on the direct path.
    assert_eq!(
        world.phi_and_grad(points[3], None),
        Err(Singularity::Obstacle(3))
    );
}

#[test]
fn a_world_extended_by_new_after_evaluates_as_one_built_at_once() {
    // The first 1 000 points span the 100 m square; the next 200 lie well inside it, so they
    // are pushed into the first tree (a unit test of `far.rs` checks that no rebuild happens).
    let (mut points, mut rng) = scattered(1_200, 6);
    for p in &mut points[1_000..] {
        *p *= 0.9;
    }
    let d = Vector2::new(-1.0, 2.0);
    let first = PointWorld::new(d, points[..1_000].to_vec()).unwrap();
    let mut world = first.clone();
    for n in [1_001, 1_002, 1_200] {
        world = PointWorld::new_after(&world, d, points[..n].to_vec()).unwrap();
    }
    let once = PointWorld::new(d, points.clone()).unwrap();
    assert_eq!(world, once);
    for _ in 0..200 {
        let h = Vector2::new(110.0 * rng.next() - 55.0, 110.0 * rng.next() - 55.0);
        let (a, b) = (
            world.phi_and_grad(h, None).unwrap(),
            once.phi_and_grad(h, None).unwrap(),
        );
        assert!((a.0 - b.0).abs() <= 4.0 * TOLERANCE, "{a:?} {b:?}");
        assert_close(&world, h, None);
    }
    // A point outside the first tree's root box: rebuilt, still right.
    let mut far_points = points.clone();
    far_points.push(Vector2::new(400.0, -300.0));
    let grown = PointWorld::new_after(&once, d, far_points).unwrap();
    assert_close(&grown, Vector2::new(100.0, 10.0), None);
    // Validation is that of `new`: a duplicate is refused.
    let mut dup = points[..1_000].to_vec();
    dup.push(points[10]);
    assert!(PointWorld::new_after(&first, d, dup).is_err());
}
