//! Scan validation and classification, segmentation, occlusion flags, explained hits, merges
//! and the typed errors of the update.

use std::f64::consts::{PI, TAU};

use harmonav_perception::sim::Lidar;
use harmonav_perception::{
    End, Known, LaserScan, Options, Perceived, Perception, PerceptionError, Pose, Reading,
    ScanError, merge, segment,
};
use harmonav_transform::StarShape;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;

fn scan(ranges: Vec<f64>) -> LaserScan {
    LaserScan {
        angle_min: -PI,
        angle_increment: TAU / ranges.len() as f64,
        range_min: 0.1,
        range_max: 10.0,
        ranges,
    }
}

fn check_error(s: LaserScan, expected: ScanError) {
    assert_eq!(s.validate(), Err(expected));
}

#[test]
fn invalid_scans_are_typed_errors() {
    check_error(scan(vec![]), ScanError::Empty);
    check_error(
        LaserScan {
            angle_increment: -0.01,
            ..scan(vec![1.0; 10])
        },
        ScanError::NonPositiveIncrement { value: -0.01 },
    );
    check_error(
        LaserScan {
            angle_increment: f64::NAN,
            ..scan(vec![1.0; 10])
        },
        ScanError::NotFinite {
            field: "angle_increment",
        },
    );
    check_error(
        LaserScan {
            range_max: 0.05,
            ..scan(vec![1.0; 10])
        },
        ScanError::RangeLimits {
            range_min: 0.1,
            range_max: 0.05,
        },
    );
    check_error(
        LaserScan {
            angle_increment: 1.0,
            ..scan(vec![1.0; 10])
        },
        ScanError::Overlapping { aperture: 10.0 },
    );
    // A huge increment is named in scientific notation (it printed 301 digits).
    let huge = LaserScan {
        angle_increment: 1e300,
        ..scan(vec![1.0; 10])
    };
    assert_eq!(
        huge.validate().unwrap_err().to_string(),
        "the beams cover 1.0000e301 rad, more than a full turn: they would overlap"
    );
    assert_eq!(
        Pose::new(f64::NAN, 0.0, 0.0).validate(),
        Err(ScanError::NotFinite { field: "pose.x" })
    );
}

#[test]
fn readings_are_classified_as_ros_does() {
    let s = scan(vec![
        1.0,
        f64::INFINITY,
        10.0,
        12.0,
        f64::NAN,
        0.05,
        f64::NEG_INFINITY,
        -1.0,
    ]);
    let expected = [
        Reading::Hit(1.0),
        Reading::NoReturn,
        Reading::NoReturn,
        Reading::NoReturn,
        Reading::Invalid,
        Reading::Invalid,
        Reading::TooClose,
        Reading::Invalid,
    ];
    for (i, e) in expected.iter().enumerate() {
        assert_eq!(s.reading(i), *e, "beam {i}");
    }
    assert_eq!(s.free_until(0, 0.02), 0.98);
    // A no-return is free to range_max − ε only (A1: a true hit in the last ε may read as one).
    assert_eq!(s.free_until(1, 0.02), 10.0 - 0.02);
    assert_eq!(s.free_until(4, 0.02), 0.0);
}

#[test]
fn all_nan_and_all_inf_scans_give_nothing() {
    let mut p = Perception::new(Options::default(), None, vec![]).unwrap();
    for r in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let obs = p
            .observe(Pose::new(0.0, 0.0, 0.0), &scan(vec![r; 360]))
            .unwrap();
        assert_eq!((obs.hits, obs.segments.len(), obs.added.len()), (0, 0, 0));
    }
    assert!(p.perceived().is_empty());
}

/// Two walls of hits at ranges 2 and 3 on either side of beam 50 of 360.
#[test]
fn segments_split_at_range_jumps_and_flag_occlusion() {
    let mut ranges = vec![f64::INFINITY; 360];
    for r in ranges.iter_mut().take(50).skip(40) {
        *r = 2.0;
    }
    for r in ranges.iter_mut().take(60).skip(50) {
        *r = 3.0;
    }
    let s = scan(ranges);
    let pose = Pose::new(0.0, 0.0, 0.0);
    let usable: Vec<bool> = (0..360)
        .map(|i| matches!(s.reading(i), Reading::Hit(_)))
        .collect();
    let segs = segment(&s, &pose, &usable, 0.1);
    assert_eq!(segs.len(), 2);
    assert_eq!(segs[0].beams, (40..50).collect::<Vec<_>>());
    assert_eq!((segs[0].start, segs[0].end), (End::Free, End::Free));
    assert_eq!(segs[1].beams, (50..60).collect::<Vec<_>>());
    assert_eq!((segs[1].start, segs[1].end), (End::Occluded, End::Free));
    // A larger d0 joins them.
    assert_eq!(segment(&s, &pose, &usable, 1.5).len(), 1);
}

#[test]
fn segments_bridge_two_invalid_readings_and_wrap_a_full_turn() {
    let mut ranges = vec![f64::INFINITY; 360];
    for i in (350..360).chain(0..10) {
        ranges[i] = 2.0;
    }
    ranges[3] = f64::NAN;
    ranges[4] = f64::NAN;
    let s = scan(ranges.clone());
    let pose = Pose::new(0.0, 0.0, 0.0);
    let usable: Vec<bool> = (0..360)
        .map(|i| matches!(s.reading(i), Reading::Hit(_)))
        .collect();
    let segs = segment(&s, &pose, &usable, 0.1);
    assert_eq!(segs.len(), 1, "{segs:?}");
    assert_eq!(segs[0].beams.len(), 18);
    assert_eq!(segs[0].beams[0], 350);
    // Three invalid readings split it.
    ranges[5] = f64::NAN;
    let s = scan(ranges);
    let usable: Vec<bool> = (0..360)
        .map(|i| matches!(s.reading(i), Reading::Hit(_)))
        .collect();
    let segs = segment(&s, &pose, &usable, 0.1);
    assert_eq!(segs.len(), 2);
    let before = segs.iter().find(|g| g.beams[0] == 350).unwrap();
    let after = segs.iter().find(|g| g.beams[0] == 6).unwrap();
    assert_eq!((before.start, before.end), (End::Free, End::Unknown));
    assert_eq!((after.start, after.end), (End::Unknown, End::Free));
}

fn lidar() -> Lidar {
    Lidar {
        noise: 0.02,
        dropout: 0.01,
        ..Lidar::full_turn(720, 8.0)
    }
}

fn options() -> Options {
    Options {
        max_obstacle_depth: 0.8,
        rho_min: 0.3,
        ..Options::default()
    }
}

#[test]
fn hits_on_known_shapes_and_the_boundary_are_explained() {
    let rock = StarShape::circle(Vector2::new(2.0, 0.0), 0.3).unwrap();
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let mut p = Perception::new(options(), Some(boundary.clone()), vec![rock.clone()]).unwrap();
    let mut rng = Rng::new(7);
    let pose = Pose::new(0.0, 0.0, 0.3);
    let s = lidar().scan(
        &pose,
        std::slice::from_ref(&rock),
        Some(&boundary),
        &mut rng,
    );
    let obs = p.observe(pose, &s).unwrap();
    assert!(
        obs.hits > 700 && obs.explained == obs.hits,
        "{} of {}",
        obs.explained,
        obs.hits
    );
    assert!(obs.segments.is_empty() && p.perceived().is_empty());
}

/// Under the wall prior `g_w` (eq. wallgap) a hit less than `g_w − ε` from the boundary lies
/// on the wall: it is explained, not fitted. The same scan without the prior fits a shape, and
/// so does a hit between `g_w − ε` and `g_w` from the wall (its true point may be an obstacle's
/// at `g_w`).
#[test]
fn hits_within_the_wall_prior_of_the_boundary_are_explained() {
    let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
    let pose = Pose::new(0.0, 0.0, 0.0);
    // Five beams read `range`; the rest see nothing. ε = 0.02 (`options()`).
    let scan_at = |range: f64| {
        let mut ranges = vec![f64::INFINITY; 360];
        for r in &mut ranges[100..105] {
            *r = range;
        }
        LaserScan {
            range_max: 6.0,
            ..scan(ranges)
        }
    };
    for (range, wall_gap, fitted) in [(4.7, 0.5, false), (4.7, 0.0, true), (4.51, 0.5, true)] {
        let s = scan_at(range);
        let mut p = Perception::new(
            Options {
                wall_gap,
                ..options()
            },
            Some(boundary.clone()),
            vec![],
        )
        .unwrap();
        let obs = p.observe(pose, &s).unwrap();
        assert_eq!(obs.hits, 5);
        assert_eq!(
            obs.explained == 5,
            !fitted,
            "{range} m, g_w = {wall_gap}: {obs:?}"
        );
        assert_eq!(
            p.perceived().len(),
            usize::from(fitted),
            "{range} m, g_w = {wall_gap}"
        );
    }
}

#[test]
fn repeated_scans_persist_and_nearby_fits_merge() {
    let truth = StarShape::ellipse(Vector2::new(2.0, 0.5), [0.3, 0.2], 0.4).unwrap();
    let mut p = Perception::new(options(), None, vec![]).unwrap();
    let mut rng = Rng::new(3);
    let pose = Pose::new(0.0, 0.0, 0.0);
    let first = p
        .observe(
            pose,
            &lidar().scan(&pose, std::slice::from_ref(&truth), None, &mut rng),
        )
        .unwrap();
    assert_eq!(p.perceived().len(), 1, "{first:?}");
    let before = p.perceived()[0].clone();
    // The same view again: every hit is explained, nothing changes.
    let again = p
        .observe(
            pose,
            &lidar().scan(&pose, std::slice::from_ref(&truth), None, &mut rng),
        )
        .unwrap();
    assert_eq!((again.added.len(), again.grown.len()), (0, 0));
    assert_eq!(again.explained, again.hits);
    // From the other side: hits beyond the first fit make a fit that overlaps it and merges.
    let behind = Pose::new(4.0, 1.2, 0.0);
    let obs = p
        .observe(
            behind,
            &lidar().scan(&behind, std::slice::from_ref(&truth), None, &mut rng),
        )
        .unwrap();
    assert_eq!(p.perceived().len(), 1);
    if !obs.grown.is_empty() {
        let after = p.perceived()[0].shape();
        for x in before.boundary_cover(0.01) {
            assert!(after.contains(x), "shapes only grow");
        }
    }
    for i in 0..2048 {
        assert!(
            p.perceived()[0]
                .shape()
                .contains(truth.boundary_point(TAU * i as f64 / 2048.0))
        );
    }
}

#[test]
fn merge_contains_both_about_a_common_kernel_point() {
    let a = Perceived::new(Vector2::new(0.0, 0.0), 0.5, vec![(2, 0.05, 0.0)]).unwrap();
    let b = Perceived::new(Vector2::new(0.6, 0.0), 0.4, vec![(3, 0.0, 0.04)]).unwrap();
    let (m, cert) = merge(&a, &b, 0.01, 6).unwrap();
    assert!(!cert.disc_fallback);
    for x in a
        .boundary_cover(0.01)
        .into_iter()
        .chain(b.boundary_cover(0.01))
    {
        assert!(m.shape().signed_distance_bounds(x).1 <= 0.0);
    }
    assert!(
        m.area() < 1.6 * (a.area() + b.area()),
        "merged area {}",
        m.area()
    );
    assert!(a.star_about(Vector2::new(0.3, 0.0)) && b.star_about(Vector2::new(0.3, 0.0)));
}

#[test]
fn merge_without_a_common_kernel_point_takes_the_radial_hull() {
    // Two bow ties (R = 0.3 + 0.25 cos 2θ, waist 0.05) overlapping only at their tips: no
    // common kernel point among the candidates between their centres.
    let a = Perceived::new(Vector2::new(0.0, 0.0), 0.3, vec![(2, 0.25, 0.0)]).unwrap();
    let b = Perceived::new(Vector2::new(1.05, 0.0), 0.3, vec![(2, 0.25, 0.0)]).unwrap();
    assert!(a.shape().distance_to(b.shape()) <= 0.0, "they overlap");
    let between = (0..=8).map(|k| Vector2::new(1.05 * k as f64 / 8.0, 0.0));
    assert!(
        between
            .clone()
            .all(|p| !(a.star_about(p) && b.star_about(p)))
    );
    let (m, _) = merge(&a, &b, 0.01, 6).unwrap();
    // It contains both, boundary and interior (eq. hull), on fine covers and a grid.
    for x in a
        .boundary_cover(0.002)
        .into_iter()
        .chain(b.boundary_cover(0.002))
    {
        assert!(m.shape().contains(x), "{x:?} outside the merge");
    }
    for i in 0..200 {
        for j in 0..80 {
            let x = Vector2::new(-0.6 + 2.3 * i as f64 / 199.0, -0.6 + 1.2 * j as f64 / 79.0);
            if a.shape().contains(x) || b.shape().contains(x) {
                assert!(m.shape().contains(x), "{x:?} outside the merge");
            }
        }
    }
    // Of the nine candidates, the least area: no larger than the one about the midpoint.
    let mut samples = a.boundary_cover(0.01);
    samples.extend(b.boundary_cover(0.01));
    let (about_mid, _) =
        harmonav_perception::certified_star(Vector2::new(0.525, 0.0), &samples, 0.01, 6).unwrap();
    assert!(m.area() <= about_mid.area() * (1.0 + 1e-9));
}

#[test]
fn update_errors_are_typed_and_change_nothing() {
    let rock = StarShape::circle(Vector2::new(2.0, 0.0), 0.3).unwrap();
    let mut p = Perception::new(options(), None, vec![rock]).unwrap();
    let good = scan(vec![f64::INFINITY; 360]);
    assert_eq!(
        p.observe(Pose::new(2.0, 0.0, 0.0), &good).unwrap_err(),
        PerceptionError::PoseNotFree {
            inside: Some(Known::Map(0))
        }
    );
    assert!(matches!(
        p.observe(Pose::new(0.0, 0.0, 0.0), &scan(vec![])),
        Err(PerceptionError::Scan(ScanError::Empty))
    ));
    // A fit that overlaps a map obstacle: an unknown disc touching the rock.
    let unknown = StarShape::circle(Vector2::new(2.0, 0.45), 0.12).unwrap();
    let mut rng = Rng::new(1);
    let pose = Pose::new(0.0, 1.5, 0.0);
    let s = lidar().scan(
        &pose,
        &[
            unknown,
            StarShape::circle(Vector2::new(2.0, 0.0), 0.3).unwrap(),
        ],
        None,
        &mut rng,
    );
    match p.observe(pose, &s) {
        Err(
            e @ PerceptionError::NotStarWorld {
                with: Known::Map(0),
            },
        ) => {
            assert!(
                e.to_string()
                    .contains("the world as perceived is not a star world")
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(p.perceived().is_empty(), "a failed update changes nothing");
    assert_eq!(
        Perception::new(
            Options {
                range_noise: -1.0,
                ..options()
            },
            None,
            vec![]
        )
        .unwrap_err(),
        PerceptionError::InvalidOption {
            field: "range_noise",
            value: -1.0
        }
    );
}

#[test]
fn an_obstacle_wider_than_the_depth_prior_is_reported_unfitted() {
    let wall = StarShape::ellipse(Vector2::new(2.0, 0.0), [0.1, 1.5], 0.0).unwrap();
    let mut p = Perception::new(options(), None, vec![]).unwrap();
    let mut rng = Rng::new(2);
    let pose = Pose::new(0.0, 0.0, 0.0);
    let obs = p
        .observe(pose, &lidar().scan(&pose, &[wall], None, &mut rng))
        .unwrap();
    assert!(!obs.unfitted.is_empty());
    assert!(p.perceived().is_empty());
}

/// A small shape merged with a large one (a near fit and a far `D`-closed one): about a point
/// of the small one, the union has sharp features, which a least-squares Fourier sum
/// undershoots and its raise lifts in every direction (merged over union area 1.76–2.35 in
/// these three worlds). The smoothed candidate of eq. fit (`J ∗ G_w`) follows the union: within
/// 1.5 of its area (the merge's exact area over the discs' union's), and the union, on a grid,
/// inside.
#[test]
fn a_small_shape_merged_with_a_large_one_stays_close_to_their_union() {
    for (ra, rb, d) in [(0.3f64, 1.5f64, 1.7f64), (0.2, 1.0, 1.1), (0.5, 1.5, 1.9)] {
        let a = Perceived::new(Vector2::new(0.0, 0.0), ra, vec![]).unwrap();
        let b = Perceived::new(Vector2::new(d, 0.0), rb, vec![]).unwrap();
        let (m, _) = merge(&a, &b, 0.01, 6).unwrap();
        for i in 0..400 {
            for j in 0..400 {
                let x = Vector2::new(-1.0 + 5.0 * i as f64 / 399.0, -2.5 + 5.0 * j as f64 / 399.0);
                if a.shape().contains(x) || b.shape().contains(x) {
                    assert!(
                        m.shape().contains(x),
                        "{x:?} of the union outside the merge"
                    );
                }
            }
        }
        // The union of two overlapping discs: both areas less their lens.
        let lens = ra * ra * ((d * d + ra * ra - rb * rb) / (2.0 * d * ra)).acos()
            + rb * rb * ((d * d + rb * rb - ra * ra) / (2.0 * d * rb)).acos()
            - 0.5 * ((-d + ra + rb) * (d + ra - rb) * (d - ra + rb) * (d + ra + rb)).sqrt();
        let union = PI * (ra * ra + rb * rb) - lens;
        let ratio = m.area() / union;
        assert!(ratio < 1.5, "({ra}, {rb}, {d}): merged over union {ratio}");
    }
}
