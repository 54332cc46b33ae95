//! The harmonic map's properties, each able to fail: Jacobian, boundary conditions, flux,
//! winding, exact solutions, convergence, folds, invariance.

mod common;

use common::*;
use harmonav_harmonic::{
    Domain, EvalError, HarmonicMap, MeshError, MeshOptions, RingId, SolveError, sampled_check,
};
use nalgebra::Vector2;
use std::f64::consts::{PI, TAU};

#[test]
fn jacobian_matches_central_differences_also_within_half_an_element() {
    let d = square_with_hole();
    let h = 0.1;
    let map = HarmonicMap::new(&d, &MeshOptions::graded(h)).unwrap();
    // Interior points, and points 0.3 h and 0.1 h from an element's midpoint, where a
    // one-argument arctangent loses π.
    let mid = map.elements()[7].midpoint();
    let inward = v(0.0, 1.0); // element 7 lies on the bottom side
    let points = [
        v(0.5, 0.3),
        v(-0.7, -0.1),
        v(0.3, 0.8),
        mid + inward * 0.3 * h,
        mid + inward * 0.1 * h,
        v(0.2 + 0.03 * h, 0.0),
    ];
    for x in points {
        let e = map.eval(x).unwrap();
        let fd = fd_jacobian(&map, x, 1e-6);
        let scale = e.jacobian.amax().max(1.0);
        let err = (e.jacobian - fd).amax() / scale;
        assert!(err < 1e-6, "at {x:?}: {err:e}\n{}\n{fd}", e.jacobian);
    }
}

#[test]
fn boundary_conditions_and_fluxes_hold() {
    for d in [square_with_hole(), u_world(), two_rooms()] {
        let map = HarmonicMap::new(&d, &MeshOptions::graded(0.1)).unwrap();
        let r = map.residuals();
        assert!(r.outer < 1e-10, "{r:?}");
        assert!(r.holes < 1e-10, "{r:?}");
        assert!(r.flux < 1e-10, "{r:?}");
        assert!(map.solve_residual() < 1e-14);
        for p in map.punctures() {
            assert!(p.norm() < 1.0);
        }
        // Between the collocation points the outer boundary stays close to the circle and
        // each hole close to its puncture.
        let mut worst = [0.0_f64; 2];
        for e in map.elements() {
            let q = map.eval(e.a * 0.8 + e.b * 0.2).unwrap().value;
            match e.ring {
                RingId::Outer => worst[0] = worst[0].max((q.norm() - 1.0).abs()),
                RingId::Hole(i) => worst[1] = worst[1].max((q - map.punctures()[i]).norm()),
            }
        }
        assert!(worst[0] < 0.02 && worst[1] < 0.02, "{worst:?}");
    }
}

#[test]
fn flux_through_a_loop_is_zero_and_loops_wind_once() {
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.1)).unwrap();
    let p = map.punctures()[0];
    // A circle about the hole (radius 0.5: between the hole's 0.28 and the wall's 1).
    let k = 2000;
    let (mut fu, mut fv, mut mag) = (0.0, 0.0, 0.0);
    let mut image = Vec::new();
    for i in 0..k {
        let t = TAU * i as f64 / k as f64;
        let n = v(t.cos(), t.sin());
        let e = map.eval(n * 0.5).unwrap();
        let ds = TAU * 0.5 / k as f64;
        fu += e.jacobian.row(0).transpose().dot(&n) * ds;
        fv += e.jacobian.row(1).transpose().dot(&n) * ds;
        mag += e.jacobian.norm() * ds;
        image.push(e.value);
    }
    assert!(
        fu.abs() < 1e-10 * mag && fv.abs() < 1e-10 * mag,
        "{fu:e} {fv:e} / {mag}"
    );
    assert!((winding(&image, p) - 1.0).abs() < 1e-9);
    // A loop parallel to the outer ring (0.9 box) winds once about the puncture too, and a
    // loop not around the hole winds zero times.
    let ring: Vec<_> = (0..400)
        .map(|i| {
            let t = TAU * i as f64 / 400.0;
            map.eval(v(0.9 * t.cos(), 0.9 * t.sin()).map(|c| c.clamp(-0.9, 0.9)))
                .unwrap()
                .value
        })
        .collect();
    assert!((winding(&ring, p) - 1.0).abs() < 1e-9);
    let off: Vec<_> = (0..400)
        .map(|i| {
            let t = TAU * i as f64 / 400.0;
            map.eval(v(0.6 + 0.2 * t.cos(), 0.2 * t.sin()))
                .unwrap()
                .value
        })
        .collect();
    assert!(winding(&off, p).abs() < 1e-9);
}

/// Max |H(x) − x| over |x| ≤ 0.9 for the regular n-gon inscribed in the unit circle (vertex 0
/// at (1, 0), one element per edge): arc-length data on a circle is the identity.
fn disk_error(n: usize) -> f64 {
    let d = Domain::new(ngon(v(0.0, 0.0), 1.0, n, true), vec![]).unwrap();
    let chord = 2.0 * (PI / n as f64).sin();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(chord * 1.001)).unwrap();
    assert_eq!(map.elements().len(), n);
    let mut worst = 0.0_f64;
    for i in 0..=12 {
        for j in 0..24 {
            let r = 0.9 * i as f64 / 12.0;
            let t = TAU * j as f64 / 24.0;
            let x = v(r * t.cos(), r * t.sin());
            let e = map.eval(x).unwrap();
            worst = worst.max((e.value - x).norm());
            if r < 0.5 {
                worst = worst.max((e.jacobian - nalgebra::Matrix2::identity()).amax());
            }
        }
    }
    worst
}

#[test]
fn the_disk_maps_to_itself_and_the_error_falls_as_h_squared() {
    let errors: Vec<f64> = [32, 64, 128].iter().map(|&n| disk_error(n)).collect();
    assert!(errors[2] < 2e-3, "{errors:?}");
    for w in errors.windows(2) {
        // O(h²): halving h divides the error by about 4.
        assert!(w[1] < w[0] / 3.0, "{errors:?}");
    }
}

#[test]
fn the_annulus_matches_its_exact_solution() {
    // H(x) = (x − r²x/|x|²)/(1 − r²), puncture 0, for r < |x| < 1.
    let r = 0.3;
    let n = 256;
    let d = Domain::new(
        ngon(v(0.0, 0.0), 1.0, n, true),
        vec![ngon(v(0.0, 0.0), r, 96, false)],
    )
    .unwrap();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(0.03)).unwrap();
    assert!(map.punctures()[0].norm() < 1e-12);
    let mut worst = 0.0_f64;
    for i in 1..10 {
        for j in 0..16 {
            let rho = r + (0.9 - r) * i as f64 / 10.0;
            let t = TAU * (j as f64 + 0.5) / 16.0;
            let x = v(rho * t.cos(), rho * t.sin());
            let exact = (x - x * (r * r / x.norm_squared())) / (1.0 - r * r);
            worst = worst.max((map.eval(x).unwrap().value - exact).norm());
        }
    }
    assert!(worst < 2e-3, "{worst}");
}

fn min_det(d: &Domain, h: f64) -> (f64, Vector2<f64>, usize) {
    let map = HarmonicMap::new(d, &MeshOptions::graded(h)).unwrap();
    let delta = map.max_element_length();
    let s = sampled_check(&map, delta, h / 2.0).unwrap();
    assert_eq!(s.folds, 0, "{s:?}");
    assert_eq!(s.outside_disk, 0, "{s:?}");
    (s.min_det, s.min_det_at, s.samples)
}

#[test]
fn no_fold_beyond_one_element_in_u_l_and_two_room_worlds() {
    for (name, d, h) in [
        ("U", u_world(), 0.1),
        ("L", l_world(), 0.1),
        ("rooms", two_rooms(), 0.15),
    ] {
        let (m, at, n) = min_det(&d, h);
        assert!(
            m > 0.0 && n > 1000,
            "{name}: min det {m:e} at {at:?} over {n}"
        );
    }
}

#[test]
fn area_of_the_image_is_pi() {
    // ∫ det J dA over the free space = area of the punctured disk (H is onto and one-to-one).
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.05)).unwrap();
    let k = 200;
    let s = 2.0 / k as f64;
    let mut total = 0.0;
    for i in 0..k {
        for j in 0..k {
            let x = v(-1.0 + (i as f64 + 0.5) * s, -1.0 + (j as f64 + 0.5) * s);
            if d.contains(x) {
                total += map.eval(x).unwrap().det() * s * s;
            }
        }
    }
    assert!((total - PI).abs() < 3e-3, "{total}");
}

#[test]
fn rigid_motions_and_scaling_leave_the_map_unchanged() {
    let d = u_world();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    for (angle, scale, shift) in [
        (0.7, 1.0, v(3.0, -2.0)),
        (0.0, 1e-3, v(0.0, 0.0)),
        (-2.0, 1e3, v(1e4, 5.0)),
    ] {
        let (c, s) = (f64::cos(angle), f64::sin(angle));
        let t = |p: Vector2<f64>| v(c * p.x - s * p.y, s * p.x + c * p.y) * scale + shift;
        let moved = Domain::new(
            d.outer().iter().map(|&p| t(p)).collect(),
            d.holes()
                .iter()
                .map(|h| h.iter().map(|&p| t(p)).collect())
                .collect(),
        )
        .unwrap();
        let m2 = HarmonicMap::new(&moved, &MeshOptions::graded(0.2 * scale)).unwrap();
        assert_eq!(m2.elements().len(), map.elements().len());
        for x in [v(0.0, 1.2), v(1.5, -1.5), v(-1.7, 0.3)] {
            let a = map.eval(x).unwrap();
            let b = m2.eval(t(x)).unwrap();
            assert!((a.value - b.value).norm() < 1e-9, "{angle} {scale}");
            assert!(((a.det() - b.det() * scale * scale) / a.det()).abs() < 1e-7);
        }
        assert!((map.punctures()[0] - m2.punctures()[0]).norm() < 1e-9);
    }
}

#[test]
fn evaluation_and_construction_fail_with_typed_errors() {
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(0.5)).unwrap();
    assert_eq!(map.eval(v(f64::NAN, 0.0)), Err(EvalError::NonFinite));
    assert_eq!(map.eval(v(1.0, 1.0)), Err(EvalError::AtElementEnd));
    assert!(matches!(
        HarmonicMap::new(&d, &MeshOptions::uniform(1e-5)),
        Err(SolveError::Mesh(MeshError::TooManyElements { .. }))
    ));
    // Off the vertices the boundary itself evaluates to finite values.
    let e = map.eval(v(1.0, 0.1)).unwrap();
    assert!(e.value.norm().is_finite() && e.det().is_finite());
}
