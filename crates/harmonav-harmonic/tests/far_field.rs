//! The far field (`HarmonicMap::eval` through the multipole tree) against the direct sum
//! (`HarmonicMap::eval_direct`): `H` and `J_H` agree to 1e-12 of the map's scale on dense
//! samples of the test floor plans, within half an element of the walls too, and a loose
//! tolerance breaks that agreement (the negative control).

mod common;

use common::*;
use harmonav_harmonic::{
    Domain, EvalError, FAR_FIELD_MIN_ELEMENTS, FAR_FIELD_TOLERANCE, HarmonicMap, MeshOptions,
    SolveError,
};
use nalgebra::Vector2;

/// The agreement asked for: `|ΔH|∞ ≤ 1e-12` (the disk's scale is 1) and
/// `|ΔJ_H|∞ ≤ 1e-12·max(|J_H|∞, 1/D)` (`1/D` the Jacobian's scale, `D` the box diagonal).
const AGREEMENT: f64 = 1e-12;

/// The worst ratio of the fast-against-direct difference to [`AGREEMENT`]'s allowance over
/// `points`, and the number of points compared. Both paths must fail at the same points.
fn worst_ratio(map: &HarmonicMap, points: &[Vector2<f64>]) -> (f64, usize) {
    let (lo, hi) = map.domain().bounding_box();
    let inv_d = 1.0 / (hi - lo).norm();
    let (mut worst, mut compared) = (0.0_f64, 0);
    for &x in points {
        match (map.eval(x), map.eval_direct(x)) {
            (Ok(a), Ok(b)) => {
                let dh = (a.value - b.value).amax() / AGREEMENT;
                let scale = b.jacobian.amax().max(inv_d);
                let dj = (a.jacobian - b.jacobian).amax() / (AGREEMENT * scale);
                worst = worst.max(dh).max(dj);
                compared += 1;
            }
            (a, b) => assert_eq!(a.err(), b.err(), "at {x:?}"),
        }
    }
    (worst, compared)
}

fn far(d: &Domain, h: f64, tolerance: f64) -> HarmonicMap {
    HarmonicMap::new(d, &MeshOptions::graded(h))
        .unwrap()
        .with_far_field(Some(tolerance))
        .unwrap()
}

#[test]
fn far_field_matches_the_direct_sum_to_1e_12_also_half_an_element_from_the_walls() {
    for (name, d, h, stride) in [
        ("U", u_world(), 0.03, 1),
        ("two rooms", two_rooms(), 0.03, 1),
        ("pillars", pillared_room(), 0.028, 2),
    ] {
        let map = far(&d, h, FAR_FIELD_TOLERANCE);
        assert!(map.has_far_field());
        let mut points = dense_samples(&map, 2.0 * h * stride as f64, stride);
        // Outside the tree's root box (a walk over the boxes' multipoles). Not much farther:
        // there the direct closed form cancels (`(xo ± a) ln r±²`, relative error ~ε·r/|E_j|;
        // measured 1.4e-11 at 50 diameters), and the comparison would measure the direct sum.
        let (lo, hi) = d.bounding_box();
        points.extend([hi + (hi - lo) * 0.3, lo - (hi - lo) * 0.5]);
        let (worst, compared) = worst_ratio(&map, &points);
        println!(
            "{name}: N = {}, {compared} points, worst {:.1e} of the map's scale",
            map.elements().len(),
            worst * AGREEMENT
        );
        assert!(compared > 10_000, "{name}: {compared} points");
        assert!(worst <= 1.0, "{name}: {worst:.2} × the 1e-12 allowance");
        // The stated truncation bound is within the target too.
        assert!(map.far_field_bound().unwrap() < AGREEMENT, "{name}");
    }
}

#[test]
fn a_loose_tolerance_breaks_the_agreement() {
    // Negative control: the check above sees a far field of tolerance 1e-4 (order 18). (At
    // 1e-8, order 33, the worst sample was still 0.23 of the allowance: the stated tolerance is
    // a bound, the uniform tree's error is smaller.)
    let d = u_world();
    let map = far(&d, 0.03, 1e-4);
    let points = dense_samples(&map, 0.1, 4);
    let (worst, _) = worst_ratio(&map, &points);
    println!(
        "tolerance 1e-4: worst {:.1e} of the map's scale",
        worst * AGREEMENT
    );
    assert!(worst > 1.0, "{worst}");
}

#[test]
fn element_ends_and_bad_points_fail_as_in_the_direct_sum() {
    // An element's end is singular only where the local frame puts the point exactly on it
    // (`r±² = 0`); elsewhere a rounding away, both paths give the same finite values.
    let d = two_rooms();
    let map = far(&d, 0.05, FAR_FIELD_TOLERANCE);
    let mut singular = 0;
    for e in map.elements() {
        for x in [e.a, e.a * 0.7 + e.b * 0.3] {
            match (map.eval(x), map.eval_direct(x)) {
                (Ok(a), Ok(b)) => assert!((a.value - b.value).amax() < AGREEMENT, "{x:?}"),
                (a, b) => {
                    assert_eq!(a.err(), Some(EvalError::AtElementEnd), "{x:?}");
                    assert_eq!(b.err(), Some(EvalError::AtElementEnd), "{x:?}");
                    singular += 1;
                }
            }
        }
    }
    assert!(singular > 10, "{singular}");
    // A vertex of the square (an exact element end), with the far field forced on.
    let square = HarmonicMap::new(&square_with_hole(), &MeshOptions::uniform(0.5))
        .unwrap()
        .with_far_field(Some(FAR_FIELD_TOLERANCE))
        .unwrap();
    assert_eq!(square.eval(v(1.0, 1.0)), Err(EvalError::AtElementEnd));
    assert_eq!(map.eval(v(f64::NAN, 1.0)), Err(EvalError::NonFinite));
    assert_eq!(map.eval(v(1.0, f64::INFINITY)), Err(EvalError::NonFinite));
}

#[test]
fn the_far_field_is_chosen_by_the_element_count_and_can_be_set() {
    let d = square_with_hole();
    let small = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    assert!(small.elements().len() < FAR_FIELD_MIN_ELEMENTS && !small.has_far_field());
    assert_eq!(small.far_field_bound(), None);
    let big = HarmonicMap::new(&d, &MeshOptions::graded(0.008)).unwrap();
    assert!(big.elements().len() >= FAR_FIELD_MIN_ELEMENTS && big.has_far_field());
    let cost = big.setup_cost();
    assert!(cost.far_field > std::time::Duration::ZERO && cost.total() >= cost.factor);
    let direct = big.with_far_field(None).unwrap();
    assert!(!direct.has_far_field());
    assert_eq!(direct.setup_cost().far_field, std::time::Duration::ZERO);
    for bad in [0.0, 1e-16, 0.5, f64::NAN] {
        assert!(matches!(
            small.clone().with_far_field(Some(bad)),
            Err(SolveError::FarField(_))
        ));
    }
}
