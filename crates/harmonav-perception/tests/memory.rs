//! Eq. memory (docs/maths.md §12.11): the free evidence of earlier scans, left out of a later
//! fit's region, cuts the fit and keeps the truth; and the perception's deferral of far
//! segments (`Options::fit_range`) and its memory's spacing and capacity.

mod common;

use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

use common::{params, polygon_area, trial, truth_points, worst_depth};
use harmonav_perception::{
    FreeSpace, FreeUnion, Perception, PerceptionError, Pose, StarForm, fit_in_scan, hit_point,
    segment,
};
use harmonav_transform::StarShape;
use harmonav_transform::random::Rng;

fn area(shape: &StarShape) -> f64 {
    let points: Vec<_> = (0..2048)
        .map(|i| shape.boundary_point(TAU * i as f64 / 2048.0))
        .collect();
    polygon_area(&points)
}

/// Over seeded truths seen from a pose `B`, and earlier from a pose `A` a quarter turn round
/// the obstacle: the fit of `B`'s segment with `A`'s free fan remembered holds the truth (2 048
/// boundary points), is never larger than without it (to the cover's spacing), and is
/// markedly smaller in a quarter of the fits at least. The last assertion fails if the union ignores its past
/// members; the first if a remembered fan were cut into the truth.
#[test]
fn remembered_free_evidence_cuts_later_fits_and_keeps_the_truth() {
    let (mut trials, mut cut) = (0, 0);
    for seed in 0..40 {
        let t = trial(seed, 0.02);
        let options = harmonav_perception::Options {
            form: StarForm::Hull,
            ..t.options
        };
        let p = params(&options);
        let mut rng = Rng::new(1000 + seed);
        let b = t.pose;
        let bearing = b.y.atan2(b.x) + FRAC_PI_2;
        let dist = b.position().norm();
        let a = Pose::new(dist * bearing.cos(), dist * bearing.sin(), 0.0);
        let truth = std::slice::from_ref(&t.truth);
        let scan_a = t.lidar.scan(&a, truth, None, &mut rng);
        let scan_b = t.lidar.scan(&b, truth, None, &mut rng);
        let free_a = Arc::new(FreeSpace::of_scan(&scan_a, &a, p.range_noise, p.rho_min));
        let free_b = FreeSpace::of_scan(&scan_b, &b, p.range_noise, p.rho_min);
        let usable: Vec<bool> = (0..scan_b.ranges.len())
            .map(|i| hit_point(&scan_b, &b, i).is_some())
            .collect();
        let points = truth_points(&t.truth);
        for seg in segment(&scan_b, &b, &usable, options.jump_distance) {
            let (Ok(alone), Ok(remembered)) = (
                fit_in_scan(&scan_b, &b, &seg, &p, &free_b),
                fit_in_scan(
                    &scan_b,
                    &b,
                    &seg,
                    &p,
                    &FreeUnion {
                        now: &free_b,
                        past: std::slice::from_ref(&free_a),
                    },
                ),
            ) else {
                continue;
            };
            trials += 1;
            let depth = worst_depth(remembered.perceived.shape(), &points);
            assert!(depth <= 0.0, "seed {seed}: a truth point {depth} m outside");
            let (a0, a1) = (
                area(alone.perceived.shape()),
                area(remembered.perceived.shape()),
            );
            let h = options.check_spacing;
            let perimeter = TAU * alone.perceived.shape().radius_bounds().1;
            assert!(
                a1 <= a0 + 4.0 * h * perimeter,
                "seed {seed}: {a1} m² with memory, {a0} m² without"
            );
            if a1 < 0.8 * a0 {
                cut += 1;
            }
        }
    }
    assert!(trials >= 30, "{trials} fits");
    assert!(
        4 * cut >= trials,
        "memory cut only {cut} of {trials} fits by a fifth (measured 16 of 44)"
    );
}

/// A segment whose every hit lies beyond `fit_range` is deferred, not fitted; the same scan
/// with the range beyond it fits one shape. A failed option names its field.
#[test]
fn far_segments_are_deferred_to_a_nearer_scan() {
    let t = trial(7, 0.02);
    let mut rng = Rng::new(3);
    let scan = t
        .lidar
        .scan(&t.pose, std::slice::from_ref(&t.truth), None, &mut rng);
    let nearest = (0..scan.ranges.len())
        .filter_map(|i| hit_point(&scan, &t.pose, i))
        .map(|p| (p - t.pose.position()).norm())
        .fold(f64::INFINITY, f64::min);
    let perception = |fit_range: f64| {
        Perception::new(
            harmonav_perception::Options {
                fit_range,
                ..t.options
            },
            None,
            Vec::new(),
        )
    };
    let mut far = perception(0.9 * nearest).unwrap();
    let obs = far.observe(t.pose, &scan).unwrap();
    assert_eq!((obs.deferred, obs.added.len()), (1, 0), "{obs:?}");
    assert!(far.perceived().is_empty());
    let mut near = perception(nearest + 1e-9).unwrap();
    let obs = near.observe(t.pose, &scan).unwrap();
    assert_eq!((obs.deferred, obs.added.len()), (0, 1), "{obs:?}");
    for bad in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            perception(bad),
            Err(PerceptionError::InvalidOption {
                field: "fit_range",
                ..
            })
        ));
    }
}

/// The memory keeps a scan only `memory_spacing` from the last one kept, and at most
/// `free_memory` of them, forgetting the oldest; with `free_memory = 0` it keeps none.
#[test]
fn the_memory_keeps_spaced_scans_up_to_its_capacity() {
    let t = trial(2, 0.02);
    let mut rng = Rng::new(5);
    let make = |free_memory: usize| {
        Perception::new(
            harmonav_perception::Options {
                free_memory,
                memory_spacing: 0.25,
                ..t.options
            },
            None,
            Vec::new(),
        )
        .unwrap()
    };
    let (mut three, mut none) = (make(3), make(0));
    let start = t.pose.position();
    let away = start.normalize();
    // Steps of 0.1 m straight away from the obstacle: one kept every 0.3 m.
    for k in 0..12 {
        let x = start + away * (0.1 * f64::from(k));
        let pose = Pose::new(x.x, x.y, 0.0);
        let scan = t
            .lidar
            .scan(&pose, std::slice::from_ref(&t.truth), None, &mut rng);
        three.observe(pose, &scan).unwrap();
        none.observe(pose, &scan).unwrap();
        let expected = (k / 3 + 1).min(3);
        assert_eq!(three.remembered(), expected as usize, "step {k}");
    }
    assert_eq!(none.remembered(), 0);
    assert!(matches!(
        Perception::new(
            harmonav_perception::Options {
                free_memory: harmonav_perception::perception::MAX_FREE_MEMORY + 1,
                ..t.options
            },
            None,
            Vec::new(),
        ),
        Err(PerceptionError::InvalidOption {
            field: "free_memory",
            ..
        })
    ));
}
