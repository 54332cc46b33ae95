//! Distance queries against an independent brute-force reference built from the radial
//! function alone (`boundary_point`, `radius`): signed distances and their certified bounds,
//! gaps between shapes and clearances, for every kind, 200-lobe Fourier stars and offset
//! (table) shapes; and the 200-lobe overlap.

mod common;

use std::f64::consts::TAU;

use common::*;
use harmonav_transform::{DISTANCE_TOLERANCE, StarShape, Workspace, WorldError};
use nalgebra::Vector2;
use proptest::prelude::*;

/// Whether `x` is in the closed region, from the radial function alone (no radius bounds).
fn inside_ref(shape: &StarShape, x: Vector2<f64>) -> bool {
    let v = x - shape.centre();
    v.norm() <= shape.radius(v.y.atan2(v.x)).0
}

/// The boundary sampled at `m` equal angles, with the largest `|p'(θ)| = √(R² + R'²)` and `R`.
struct Samples {
    points: Vec<Vector2<f64>>,
    lip: f64,
    max_r: f64,
}

fn samples(shape: &StarShape, m: usize) -> Samples {
    let (mut lip, mut max_r) = (0.0f64, 0.0f64);
    let points = (0..m)
        .map(|i| {
            let th = TAU * i as f64 / m as f64;
            let (r, dr) = shape.radius(th);
            lip = lip.max(r.hypot(dr));
            max_r = max_r.max(r);
            shape.boundary_point(th)
        })
        .collect();
    Samples { points, lip, max_r }
}

/// Brute force: `(d, err)` with `d − err ≤ d(x, ∂S) ≤ d`. `d` is the nearest of the boundary
/// points at `m` equal angles (step `s`), then at `s/64` over `±s/2` about every sample within
/// `2·lip·s` of the best (the true nearest point is within `s/2` of a sample, which is then
/// within `lip·s/2` of it); `err = lip·s/128`, with `lip` twice the largest sampled `|p'|`.
fn distance_ref(shape: &StarShape, reference: &Samples, x: Vector2<f64>) -> (f64, f64) {
    let m = reference.points.len();
    let s = TAU / m as f64;
    let lip = 2.0 * reference.lip;
    let d: Vec<f64> = reference.points.iter().map(|p| (p - x).norm()).collect();
    let best = d.iter().copied().fold(f64::INFINITY, f64::min);
    let mut fine = best;
    for (i, _) in d
        .iter()
        .enumerate()
        .filter(|(_, di)| **di <= best + 2.0 * lip * s)
    {
        for j in 0..=64 {
            let th = (i as f64 - 0.5 + j as f64 / 64.0) * s;
            fine = fine.min((shape.boundary_point(th) - x).norm());
        }
    }
    (fine, lip * s / 128.0)
}

/// The smallest distance between the two sample sets and whether one holds a sample of the
/// other (or its centre).
fn gap_ref(a: &StarShape, sa: &Samples, b: &StarShape, sb: &Samples) -> (f64, bool) {
    let overlap = sa.points.iter().any(|&p| inside_ref(b, p))
        || sb.points.iter().any(|&p| inside_ref(a, p))
        || inside_ref(a, b.centre())
        || inside_ref(b, a.centre());
    let gap = sa
        .points
        .iter()
        .flat_map(|p| sb.points.iter().map(move |q| (p - q).norm()))
        .fold(f64::INFINITY, f64::min);
    (gap, overlap)
}

/// A Fourier star with `n` lobes of relative depth `depth`, optionally a slow harmonic.
fn lobed_at(c: Vector2<f64>) -> impl Strategy<Value = StarShape> {
    (
        0.6..1.0f64,
        150u32..=200,
        0.01..0.05f64,
        0.0..TAU,
        -0.05..0.05f64,
    )
        .prop_map(move |(r0, n, depth, phase, slow)| {
            let (a, b) = (depth * r0 * phase.cos(), depth * r0 * phase.sin());
            StarShape::fourier_star(c, r0, &[(3, slow * r0, 0.0), (n, a, b)]).unwrap()
        })
}

/// An offset shape (a table): a random shape grown by 0.01–0.3, or shrunk by up to half its
/// smallest curvature radius.
fn offset_at(c: Vector2<f64>, size: f64) -> impl Strategy<Value = StarShape> {
    (shape_at(c, size), 0.01..0.3f64, any::<bool>()).prop_filter_map(
        "offset folds",
        move |(shape, r, grow)| {
            let r = size
                * if grow {
                    r
                } else {
                    -0.5 * r.min(shape.rho_min())
                };
            shape.offset(r).ok()
        },
    )
}

/// A point `s` from the boundary along the ray at `th` (inside for `s < 0`).
fn near_point(shape: &StarShape, th: f64, s: f64) -> Vector2<f64> {
    let p = shape.boundary_point(th);
    p + s * (p - shape.centre()).normalize()
}

/// The claims of `signed_distance_bounds` and `signed_distance` at `x`, against the reference.
fn check_point(shape: &StarShape, reference: &Samples, x: Vector2<f64>) -> Result<(), String> {
    let (lo, hi) = shape.signed_distance_bounds(x);
    let sd = shape.signed_distance(x);
    let (d, err) = distance_ref(shape, reference, x);
    // The true signed distance lies in [t_lo, t_hi].
    let (t_lo, t_hi) = if inside_ref(shape, x) {
        (-d, -(d - err))
    } else {
        (d - err, d)
    };
    let round = 1e-12;
    if !(lo <= t_hi + round && hi >= t_lo - round) {
        return Err(format!(
            "bounds [{lo}, {hi}] miss the truth [{t_lo}, {t_hi}]"
        ));
    }
    let width = DISTANCE_TOLERANCE * reference.max_r;
    if !(hi - lo <= width + round && hi - lo <= shape.distance_tolerance() + round) {
        return Err(format!("bounds [{lo}, {hi}] wider than {width}"));
    }
    if !(lo <= sd && sd <= hi) {
        return Err(format!("signed distance {sd} outside [{lo}, {hi}]"));
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(200))]

    /// Every kind of shape: certified bounds hold the brute-force truth, are no wider than the
    /// tolerance, and hold `signed_distance`.
    #[test]
    fn bounds_hold_the_truth(shape in shape_at(Vector2::new(0.3, -0.2), 1.0), th in -3.2..3.2f64, s in -0.3..0.6f64) {
        let reference = samples(&shape, 1 << 15);
        check_point(&shape, &reference, near_point(&shape, th, s)).map_err(TestCaseError::fail)?;
    }

    /// Offset shapes (the grown obstacles of a disc robot).
    #[test]
    fn bounds_hold_the_truth_for_offset_shapes(shape in offset_at(Vector2::new(-0.1, 0.4), 1.0), th in -3.2..3.2f64, s in -0.2..0.4f64) {
        let reference = samples(&shape, 1 << 15);
        check_point(&shape, &reference, near_point(&shape, th, s)).map_err(TestCaseError::fail)?;
    }
}

/// The claim of `within(x, eps)` against the reference: `true` only when the true signed
/// distance may be at most `eps`, and `true` whenever the certified bounds say so.
fn check_within(
    shape: &StarShape,
    reference: &Samples,
    x: Vector2<f64>,
    eps: f64,
) -> Result<(), String> {
    let w = shape.within(x, eps);
    let (d, err) = distance_ref(shape, reference, x);
    let t_lo = if inside_ref(shape, x) { -d } else { d - err };
    let round = 1e-12;
    if w && t_lo > eps + round {
        return Err(format!(
            "within({eps}) at a true distance of at least {t_lo}"
        ));
    }
    if !w && shape.signed_distance_bounds(x).1 <= eps {
        return Err(format!("not within({eps}) where the bounds certify it"));
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(200))]

    /// `within` at points anywhere about the shape, off the rays of their nearest boundary
    /// points too (where the radial tests cannot decide and the point query must).
    #[test]
    fn within_is_certified(shape in shape_at(Vector2::new(0.3, -0.2), 1.0), x in -1.2..1.8f64, y in -1.7..1.3f64, eps in -0.1..0.3f64) {
        let reference = samples(&shape, 1 << 14);
        check_within(&shape, &reference, Vector2::new(x, y), eps).map_err(TestCaseError::fail)?;
    }

    /// The same for offset shapes (tables: the radial hulls of perception are tables too).
    #[test]
    fn within_is_certified_for_offset_shapes(shape in offset_at(Vector2::new(-0.1, 0.4), 1.0), th in -3.2..3.2f64, s in -0.2..0.5f64, side in -0.3..0.3f64, eps in -0.1..0.3f64) {
        let reference = samples(&shape, 1 << 14);
        let p = near_point(&shape, th, s);
        let r = p - shape.centre();
        let x = p + side * Vector2::new(-r.y, r.x).normalize();
        check_within(&shape, &reference, x, eps).map_err(TestCaseError::fail)?;
    }
}

/// A point beside a thin ellipse: its ray from the centre meets the boundary 0.077 away, but
/// the boundary passes 0.033–0.037 below it. `within` must find the near boundary (the point
/// query), and must not claim 0.01.
#[test]
fn within_looks_beyond_the_ray() {
    let s = StarShape::ellipse(Vector2::zeros(), [1.0, 0.2], 0.0).unwrap();
    let x: Vector2<f64> = Vector2::new(0.5, 0.21);
    let radial = x.norm() - s.radius(x.y.atan2(x.x)).0;
    assert!(radial > 0.07, "{radial}");
    let d = s.signed_distance(x);
    assert!((0.02..0.05).contains(&d), "{d}");
    assert!(s.within(x, 0.05) && !s.within(x, 0.01) && !s.within(x, 0.02));
    // Inside, and on the ray of the minor vertex, whose nearest boundary point is that
    // vertex (curvature radius a²/b = 5): the true distance is 0.01.
    assert!(s.within(Vector2::new(0.5, 0.1), 0.0));
    let y = Vector2::new(0.0, 0.21);
    assert!(s.within(y, 0.0101) && !s.within(y, 0.0099));
    assert!(
        !s.within(Vector2::new(f64::NAN, 0.0), 1.0)
            && !s.within(Vector2::new(f64::INFINITY, 0.0), 1.0)
    );
    // A negative eps asks for depth: 0.005 deep is not 0.1 deep; a NaN eps claims nothing.
    let z = Vector2::new(0.0, 0.195);
    assert!(s.within(z, -0.004) && !s.within(z, -0.1) && !s.within(z, f64::NAN));
}

proptest! {
    #![proptest_config(config(64))]

    /// 150–200-lobe stars, whose tips are sharper than a fixed outline can resolve.
    #[test]
    fn bounds_hold_the_truth_for_200_lobe_stars(shape in lobed_at(Vector2::new(0.2, 0.1)), th in -3.2..3.2f64, s in -0.05..0.05f64) {
        let reference = samples(&shape, 1 << 17);
        check_point(&shape, &reference, near_point(&shape, th, s)).map_err(TestCaseError::fail)?;
    }

    /// Two random shapes at random distances: a gap is reported (positive) only if no sample
    /// of either is inside the other, it is at most 1.1 times the sampled gap, and a sampled
    /// gap clear of the tolerance and of the sampling error is reported.
    #[test]
    fn gaps_are_certified((a, b) in pair()) {
        gap_claims(&a, &b)?;
        gap_claims(&b, &a)?;
    }

    /// A shape in a boundary region (any kind, or a shrunk one): a clearance is reported
    /// (positive) only if every sample of the shape is inside, it is at most 1.1 times the
    /// sampled clearance, and a sampled clearance clear of the errors is reported.
    #[test]
    fn clearances_are_certified((inner, outer) in inside()) {
        let (si, so) = (samples(&inner, 2048), samples(&outer, 2048));
        let leaves = si.points.iter().any(|&p| !inside_ref(&outer, p));
        let (gap, _) = gap_ref(&inner, &si, &outer, &so);
        let err = (si.lip + so.lip) * TAU / 2048.0;
        let tol = inner.distance_tolerance() + outer.distance_tolerance() + 1e-12;
        let c = inner.clearance_inside(&outer);
        if leaves {
            prop_assert!(c <= 0.0, "a shape leaving the region has clearance {c}");
        }
        if c > 0.0 {
            prop_assert!(c <= 1.1 * gap + 1e-12, "clearance {c} above 1.1 × sampled {gap}");
            prop_assert!(c >= gap - err - tol, "clearance {c} far below sampled {gap}");
        }
        if !leaves && gap - err > tol {
            prop_assert!(c > 0.0, "a shape {gap} inside reported crossing ({c})");
        }
    }
}

/// Two shapes of size 0.7, the second (of any kind or an offset one) 0.4–2.2 away: from
/// overlapping to well apart.
fn pair() -> impl Strategy<Value = (StarShape, StarShape)> {
    (0.4..2.2f64, 0.0..TAU, any::<bool>()).prop_flat_map(|(dist, angle, table)| {
        let c = dist * Vector2::new(angle.cos(), angle.sin());
        let b = if table {
            offset_at(c, 0.7).boxed()
        } else {
            shape_at(c, 0.7).boxed()
        };
        (shape_at(Vector2::zeros(), 0.7), b)
    })
}

/// A shape of size 0.5 anywhere within 2.8 of the centre of a region of size 3 (any kind, or
/// shrunk by 0.1).
fn inside() -> impl Strategy<Value = (StarShape, StarShape)> {
    let outer = (shape_at(Vector2::zeros(), 3.0), any::<bool>()).prop_filter_map(
        "offset folds",
        |(shape, shrink)| {
            if shrink {
                shape.offset(-0.1).ok()
            } else {
                Some(shape)
            }
        },
    );
    (0.0..2.8f64, 0.0..TAU, outer).prop_flat_map(|(dist, angle, outer)| {
        let c = dist * Vector2::new(angle.cos(), angle.sin());
        (shape_at(c, 0.5), Just(outer))
    })
}

fn gap_claims(a: &StarShape, b: &StarShape) -> Result<(), TestCaseError> {
    let (sa, sb) = (samples(a, 2048), samples(b, 2048));
    let (gap, overlap) = gap_ref(a, &sa, b, &sb);
    let g = a.distance_to(b);
    // The sampled gap exceeds the true one by at most half a sample spacing on each side.
    let err = (sa.lip + sb.lip) * TAU / 2048.0;
    let tol = a.distance_tolerance() + b.distance_tolerance() + 1e-12;
    if overlap {
        prop_assert!(g <= 0.0, "overlapping shapes reported {g} apart");
    }
    if g > 0.0 {
        prop_assert!(g <= 1.1 * gap + 1e-12, "gap {g} above 1.1 × sampled {gap}");
        prop_assert!(g >= gap - err - tol, "gap {g} far below sampled {gap}");
    }
    if !overlap && gap - err > tol {
        prop_assert!(g > 0.0, "shapes {gap} apart reported overlapping ({g})");
    }
    Ok(())
}

/// A 200-lobe star `R = 1 + 0.05 cos(200(θ − phase))`: a tip at `phase` and every 1.8°, of
/// curvature radius 0.5 mm.
fn lobed(centre: Vector2<f64>, phase: f64) -> StarShape {
    let (c, s) = ((200.0 * phase).cos(), (200.0 * phase).sin());
    StarShape::fourier_star(centre, 1.0, &[(200, 0.05 * c, 0.05 * s)]).unwrap()
}

/// The case: two such stars tip to tip along `phase` (the second's tip at `phase + π`
/// faces the first's), `gap` apart; the tips are the shapes' extreme points along that line,
/// so the true gap is `gap` (negative: the tips overlap by `−gap`). Tips overlapping by
/// 5–20 mm passed the 512-vertex outline in 35 of these 120 cases, and within 1–5 mm in more;
/// now every overlap is refused, by `Workspace::new` and `with_obstacle` alike, gaps of 1 mm
/// (five tolerances) are accepted with a certified lower bound, and gaps of 5 mm are measured
/// exactly.
#[test]
fn the_tips_of_200_lobe_stars_are_measured_exactly() {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let goal = Vector2::new(0.0, 5.0);
    for k in 0..40 {
        let phase = 0.0123 + 0.0017 * k as f64;
        let u = Vector2::new(phase.cos(), phase.sin());
        let a = lobed(Vector2::zeros(), phase);
        let one = Workspace::new(boundary.clone(), vec![a.clone()], goal).unwrap();
        for gap in [-0.02, -0.01, -0.005, -0.001, 0.001, 0.005] {
            let b = lobed((2.1 + gap) * u, phase);
            let d = a.distance_to(&b);
            let both = Workspace::new(boundary.clone(), vec![a.clone(), b.clone()], goal);
            let added = one.with_obstacle(b.clone());
            if gap < 0.0 {
                assert!(d < 0.0, "phase {phase}, overlap {}: distance {d}", -gap);
                let overlap = Some(WorldError::Overlap {
                    first: 0,
                    second: 1,
                });
                assert_eq!(both.err(), overlap, "phase {phase}, overlap {}", -gap);
                assert_eq!(added.err(), overlap, "phase {phase}, overlap {}", -gap);
            } else {
                let tol = 2.0 * a.distance_tolerance();
                assert!(
                    d > 0.0 && d <= gap && d >= gap - tol,
                    "phase {phase}, gap {gap}: {d}"
                );
                if gap > 11.0 * tol {
                    assert!(
                        (d - gap).abs() < 1e-9,
                        "phase {phase}, gap {gap}: distance {d}"
                    );
                }
                assert!(both.is_ok() && added.is_ok(), "phase {phase}, gap {gap}");
            }
        }
    }
}

/// `signed_distance` 1 cm beyond a tip read 4.78 cm (the refinement window missed the
/// lobe); now it is exact and within its certified bounds, which are no wider than the
/// tolerance.
#[test]
fn signed_distance_near_a_tip_of_a_200_lobe_star_is_exact() {
    for k in 0..40 {
        let phase = 0.0123 + 0.0017 * k as f64;
        let u = Vector2::new(phase.cos(), phase.sin());
        let a = lobed(Vector2::zeros(), phase);
        for (x, truth) in [(1.06 * u, 0.01), (1.05 * u, 0.0), (1.25 * u, 0.2)] {
            let d = a.signed_distance(x);
            let (lo, hi) = a.signed_distance_bounds(x);
            assert!((d - truth).abs() < 1e-9, "phase {phase}: {d} for {truth}");
            assert!(
                lo <= truth && truth <= hi,
                "phase {phase}: [{lo}, {hi}] for {truth}"
            );
            assert!(hi - lo <= DISTANCE_TOLERANCE * 1.05, "[{lo}, {hi}]");
        }
    }
}

/// Circles are closed forms: exact gaps, clearances and distances, zero tolerance.
#[test]
fn circles_are_exact() {
    let disc = |x: f64, r: f64| StarShape::circle(Vector2::new(x, 0.0), r).unwrap();
    let (a, b) = (disc(0.0, 1.0), disc(2.5, 0.5));
    assert_eq!(a.distance_to(&b), 1.0);
    assert_eq!(b.clearance_inside(&disc(0.0, 4.0)), 1.0);
    assert_eq!(a.distance_tolerance(), 0.0);
    assert_eq!(a.signed_distance(Vector2::new(0.0, 3.0)), 2.0);
    let (lo, hi) = a.signed_distance_bounds(Vector2::new(0.0, 3.0));
    assert!(lo <= 2.0 && 2.0 <= hi && hi - lo < 1e-12);
    // A disc and an ellipse 0.3 apart along the major axis; the disc 0.25 from the wall of
    // an elliptic region.
    let e = StarShape::ellipse(Vector2::new(-3.0, 0.0), [1.5, 0.5], 0.0).unwrap();
    assert!((a.distance_to(&e) - 0.5).abs() < 1e-12);
    assert!((e.distance_to(&a) - 0.5).abs() < 1e-12);
    let room = StarShape::ellipse(Vector2::zeros(), [4.0, 1.5], 0.0).unwrap();
    assert!((disc(0.0, 1.25).clearance_inside(&room) - 0.25).abs() < 1e-12);
    assert!(disc(0.0, 1.5).clearance_inside(&room) <= 0.0);
}

/// Points that are not finite: NaN in, NaN out; a point at infinity is infinitely far; a
/// huge one is far, never NaN.
#[test]
fn non_finite_points_give_no_panic() {
    let s = StarShape::fourier_star(Vector2::zeros(), 1.0, &[(3, 0.1, 0.0)]).unwrap();
    let (lo, hi) = s.signed_distance_bounds(Vector2::new(f64::NAN, 0.0));
    assert!(lo.is_nan() && hi.is_nan() && s.signed_distance(Vector2::new(0.0, f64::NAN)).is_nan());
    assert_eq!(
        s.signed_distance_bounds(Vector2::new(f64::INFINITY, 0.0)),
        (f64::INFINITY, f64::INFINITY)
    );
    assert_eq!(
        s.signed_distance(Vector2::new(0.0, f64::NEG_INFINITY)),
        f64::INFINITY
    );
    for x in [Vector2::new(1e300, 0.0), Vector2::new(-1e200, 1e200)] {
        let d = s.signed_distance(x);
        let (lo, hi) = s.signed_distance_bounds(x);
        assert!(
            lo <= d && d <= hi && (hi - lo) < 1e-14 * d,
            "{d}, [{lo}, {hi}]"
        );
        assert!((d - x.x.hypot(x.y)).abs() < 1e-14 * d && s.coarse_signed_distance(x) > 0.0);
    }
    // Beyond the proxy distance 1e8·max R the answer is still exact to the tolerance: 1e9 m
    // from the centre along the axis of the tip R(0) = 1.1.
    let x = Vector2::new(1e9, 0.0);
    let (lo, hi) = s.signed_distance_bounds(x);
    assert!(
        lo <= 1e9 - 1.1 && 1e9 - 1.1 <= hi && hi - lo <= DISTANCE_TOLERANCE * 1.1,
        "[{lo}, {hi}]"
    );
    assert!((s.signed_distance(x) - (1e9 - 1.1)).abs() < 1e-6);
}

/// The display outline keeps 512 vertices on the curve for curved shapes (figures and the
/// visibility graph of the shortest-path reference rely on it), whatever the resolution of
/// the certified outline.
#[test]
fn the_display_outline_has_512_vertices_on_the_curve() {
    let s = lobed(Vector2::new(1.0, 2.0), 0.0);
    let outline: Vec<_> = s.outline().collect();
    assert_eq!(outline.len(), 512);
    assert!(outline.iter().all(|&p| s.signed_distance(p).abs() < 1e-9));
}
