//! Scans of ranges at random (the hostile round of 2026-12-06, D2: rain, dust, glass, a
//! failing lidar): refused after a bounded amount of work, counted ([`harmonav_perception::work`]),
//! never timed. Before, one 360-beam scan cost about 40 s of fits and merges (some 300 fits,
//! each merge 105 certified hulls) before a navigator refused it.

use std::f64::consts::{PI, TAU};

use harmonav_perception::sim::Lidar;
use harmonav_perception::{
    FreeEvidence, LaserScan, Options, Perception, PerceptionError, Pose, StarForm, Work, work,
};
use harmonav_transform::StarShape;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;

/// The options of a navigator's perception (`harmonav::ScanOptions`' defaults) for a robot of
/// radius 0.1 m: radial hulls, the free fan, a 16-scan memory, merge gap `2r`, keep-out `r`.
fn navigator_options() -> Options {
    Options {
        form: StarForm::Hull,
        free_evidence: FreeEvidence::Fan,
        free_memory: 16,
        merge_gap: 0.2,
        keep_out: 0.1,
        ..Options::default()
    }
}

/// The robot's radius, the guard of [`Perception::observe_guarded`].
const RADIUS: f64 = 0.1;

/// A full turn of `beams` ranges uniform in `[lo, hi]` (seed 0), range 3 m: the hostile
/// round's scan for `[0.05, 3]`.
fn random_scan(beams: usize, lo: f64, hi: f64) -> LaserScan {
    let mut rng = Rng::new(0);
    LaserScan {
        angle_min: -PI,
        angle_increment: TAU / beams as f64,
        range_min: 0.0,
        range_max: 3.0,
        ranges: (0..beams).map(|_| rng.uniform(lo, hi)).collect(),
    }
}

/// The hostile round's perception: a disc of radius 10 m, the sensor at (−3, 0).
fn perception() -> (Perception, Pose) {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let p = Perception::new(navigator_options(), Some(boundary), Vec::new()).unwrap();
    (p, Pose::new(-3.0, 0.0, 0.0))
}

/// One update of a fresh perception with `guard`, and the work it counted.
fn observe(scan: &LaserScan, guard: f64) -> (Result<usize, PerceptionError>, Work) {
    let (mut p, pose) = perception();
    let before = work();
    let r = p.observe_guarded(pose, scan, guard);
    let spent = work().since(before);
    if r.is_err() {
        assert!(p.perceived().is_empty(), "a refused update changes nothing");
        assert_eq!(p.remembered(), 0);
    }
    (r.map(|o| o.segments.len()), spent)
}

/// The hostile scan and its kin (45 to 10 000 beams, uniform in [0.05, 3] m) are refused
/// after a few fits and no merge, whatever the beams: the nearest segment's fit, `D` = 1 m
/// closed behind a hit centimetres from the sensor, comes within the robot's radius of it
/// (eq. guard). Before, the work grew with the beams: one fit per segment (0.8 per beam) and
/// one merge of 9 to 105 certified hulls per fit.
#[test]
fn a_scan_of_random_ranges_is_refused_after_a_few_fits() {
    for beams in [45, 90, 180, 360, 1000, 3600, 10_000] {
        let (r, spent) = observe(&random_scan(beams, 0.05, 3.0), RADIUS);
        match r {
            Err(PerceptionError::HoldsSensor { beam, guard }) => {
                assert!(beam < beams);
                assert_eq!(guard, RADIUS);
            }
            other => panic!("{beams} beams: {other:?}"),
        }
        assert!(spent.fits <= 4, "{beams} beams: {spent:?}");
        assert_eq!(spent.merges, 0, "{beams} beams: {spent:?}");
        assert_eq!(spent.certifications, spent.fits, "{beams} beams: {spent:?}");
    }
}

/// Without a robot (`guard` 0, [`Perception::observe`]) the same scan is refused when a fit
/// holds the sensor itself: at 360 beams the fourth nearest does; the work stays a few fits.
#[test]
fn without_a_guard_a_fit_over_the_sensor_refuses_the_scan() {
    let (mut p, pose) = perception();
    let before = work();
    let r = p.observe(pose, &random_scan(360, 0.05, 3.0));
    let spent = work().since(before);
    assert!(
        matches!(r, Err(PerceptionError::HoldsSensor { guard: 0.0, .. })),
        "{r:?}"
    );
    assert!(spent.fits <= 8 && spent.merges == 0, "{spent:?}");
    assert!(p.perceived().is_empty());
    let message = r.unwrap_err().to_string();
    assert!(message.contains("inside a perceived obstacle"), "{message}");
}

/// Ranges in a band about 2 m (no hit near the sensor): the fits, 1 m deep behind a ring of
/// hits, overlap all round the sensor, so the star that would hold them holds it (eq.
/// surround); refused before any merge. At 360 beams the fits' union leaves a gap (a
/// segment wider than `D` is not fitted), and the merges that close it are made: the scan is
/// refused at the merge that comes within the guard.
#[test]
fn a_ring_of_random_ranges_is_refused_before_its_merges() {
    for beams in [1000, 3600] {
        let (r, spent) = observe(&random_scan(beams, 1.9, 2.1), RADIUS);
        assert!(
            matches!(r, Err(PerceptionError::HoldsSensor { .. })),
            "{beams}: {r:?}"
        );
        assert_eq!(spent.merges, 0, "{beams}: {spent:?}");
        assert!(spent.fits <= 64, "{beams}: {spent:?}");
    }
    let (r, spent) = observe(&random_scan(360, 1.9, 2.1), RADIUS);
    assert!(
        matches!(r, Err(PerceptionError::HoldsSensor { .. })),
        "{r:?}"
    );
    assert!(spent.merges >= 1, "{spent:?}");
}

/// A coherent scan (a disc seen by a dense noise-free lidar) is one fit and no merge; the
/// guard changes nothing when nothing comes near it (the same shape, to the bit).
#[test]
fn a_coherent_scan_costs_one_fit_and_the_guard_keeps_its_shape() {
    let disc = StarShape::circle(Vector2::new(-1.0, 0.5), 0.4).unwrap();
    let scan = Lidar::full_turn(3600, 3.0).scan(
        &Pose::new(-3.0, 0.0, 0.0),
        std::slice::from_ref(&disc),
        None,
        &mut Rng::new(1),
    );
    let (mut guarded, pose) = perception();
    let before = work();
    let obs = guarded.observe_guarded(pose, &scan, RADIUS).unwrap();
    let spent = work().since(before);
    assert_eq!((obs.added.len(), spent.fits, spent.merges), (1, 1, 0));
    let (mut plain, _) = perception();
    plain.observe(pose, &scan).unwrap();
    let (a, b) = (&guarded.perceived()[0], &plain.perceived()[0]);
    assert_eq!(a.radii(), b.radii());
    assert_eq!(a.centre(), b.centre());
}

/// A guard that is negative or not finite is a typed error.
#[test]
fn the_guard_is_validated() {
    let (mut p, pose) = perception();
    for g in [-0.1, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            p.observe_guarded(pose, &random_scan(8, 1.0, 2.0), g),
            Err(PerceptionError::InvalidOption { field: "guard", .. })
        ));
    }
}
