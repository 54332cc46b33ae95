//! The certificate: it finds folds when δ is inside the boundary layer, and certifies (or
//! leaves undecided, never wrongly certifies) beyond it.

mod common;

use common::*;
use harmonav_harmonic::{
    CertifyError, CertifyOptions, HarmonicMap, MeshOptions, Verdict, certify, sampled_check,
};
use nalgebra::Vector2;

#[test]
fn a_delta_inside_the_boundary_layer_finds_the_corner_fold() {
    // Uniform elements fold at convex corners within about h/2 (docs/maths.md §11).
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(0.25)).unwrap();
    let s = sampled_check(&map, 0.01, 0.01).unwrap();
    assert!(s.folds > 0 && s.min_det <= 0.0, "{s:?}");
    let c = certify(&map, &CertifyOptions::new(0.01)).unwrap();
    assert!(matches!(c.verdict, Verdict::Fold { .. }), "{c:?}");
}

#[test]
fn beyond_one_element_the_map_is_certified() {
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    let delta = map.max_element_length();
    let c = certify(&map, &CertifyOptions::new(delta)).unwrap();
    assert_eq!(c.verdict, Verdict::Certified, "{c:?}");
    assert_eq!(c.verdict.as_str(), "certified");
    assert!(c.extremes.min_det > 0.0 && c.extremes.max_norm < 1.0);
    // The certified cells cover W_δ: at least its area.
    let inner = (2.0 - 2.0 * delta).powi(2) - (0.4 + 2.0 * delta).powi(2);
    assert!(c.certified_area >= inner, "{} < {inner}", c.certified_area);
}

#[test]
fn a_pocket_is_undecided_rather_than_certified_blind() {
    let d = u_world();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    let delta = map.max_element_length();
    let opts = CertifyOptions {
        max_evaluations: 20_000,
        ..CertifyOptions::new(delta)
    };
    let c = certify(&map, &opts).unwrap();
    assert!(
        matches!(c.verdict, Verdict::Certified | Verdict::Undecided),
        "{c:?}"
    );
    assert!(c.evaluations <= 20_000 && c.extremes.min_det > 0.0);
}

#[test]
fn bad_options_are_typed_errors() {
    let d = square_with_hole();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(0.5)).unwrap();
    for delta in [0.0, -1.0, f64::NAN, 1e9] {
        assert!(matches!(
            certify(&map, &CertifyOptions::new(delta)),
            Err(CertifyError::InvalidOption { name: "delta", .. })
        ));
    }
    assert!(matches!(
        certify(&map, &CertifyOptions::new(1e-5)),
        Err(CertifyError::TooManyCells { .. })
    ));
    assert!(matches!(
        sampled_check(&map, 0.1, 0.0),
        Err(CertifyError::InvalidOption {
            name: "spacing",
            ..
        })
    ));
}

/// 400 points of the disc `B(c, ρ)`: 200 on its rim and a spiral of 200 inside.
fn disc_points(c: Vector2<f64>, rho: f64) -> impl Iterator<Item = Vector2<f64>> {
    (0..400).map(move |i| {
        let t = i as f64 * 0.618_033_988_749_895 * std::f64::consts::TAU;
        let r = if i < 200 {
            rho
        } else {
            rho * (i - 200) as f64 / 200.0
        };
        c + v(r * t.cos(), r * t.sin())
    })
}

/// Eq. jacball: the rows of `J_H` over a disc stay within `gradient_radius` of `J_H(x)` at 400
/// points of each disc, and the bound is not vacuous: somewhere a row moves more than a third
/// of it (so a radius a third of the true one, or the first-order term dropped where it is the
/// smaller, fails here).
#[test]
fn the_jacobian_rows_stay_within_their_radius_over_the_disc() {
    let d = u_world();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    let mut tightest = 0.0_f64;
    for &(x, y) in &[
        (0.6, 1.25),
        (-0.85, 1.2),
        (0.0, 0.0),
        (1.5, -1.5),
        (1.3, 0.3),
    ] {
        let c = v(x, y);
        let sd = d.signed_distance(c);
        for frac in [0.2, 0.5, 0.9] {
            let rho = frac * sd;
            let e = map.enclosure(c, rho).unwrap();
            let j0 = e.eval.jacobian;
            for p in disc_points(c, rho) {
                let j = map.eval(p).unwrap().jacobian;
                for row in 0..2 {
                    let moved = (j.row(row) - j0.row(row)).norm();
                    let bound = e.gradient_radius[row];
                    assert!(
                        moved <= bound,
                        "disc about {c:?}, ρ {rho}, row {row}: {moved} > {bound}"
                    );
                    tightest = tightest.max(moved / bound);
                }
            }
        }
    }
    assert!(
        tightest > 1.0 / 3.0,
        "the bound is loose everywhere: {tightest}"
    );
}

/// `H(B(x, ρ)) ⊂ B(H(x), r)`: 400 points of each disc (its rim and a spiral inside) map within
/// `r` of `H(x)`, for discs about reflex and convex corners of the U world and in the open; the
/// first-order part `ρ‖J_H(x)‖_F` alone is exceeded by some of them, so the curvature term is
/// what makes it hold.
#[test]
fn the_enclosure_holds_the_image_of_its_disc() {
    let d = u_world();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.2)).unwrap();
    let (mut first_order_broken, mut discs) = (0, 0);
    for &(x, y) in &[
        (0.6, 1.25),
        (-0.85, 1.2),
        (0.0, 0.0),
        (1.5, -1.5),
        (0.0, 1.6),
        (1.3, 0.3),
    ] {
        let c = v(x, y);
        let sd = d.signed_distance(c);
        for frac in [0.2, 0.5, 0.9] {
            let rho = frac * sd;
            let e = map.enclosure(c, rho).unwrap();
            assert!(e.radius.is_finite() && e.radius > 0.0, "{e:?}");
            let first = rho * e.eval.jacobian.norm();
            let mut worst = 0.0_f64;
            for p in disc_points(c, rho) {
                worst = worst.max((map.eval(p).unwrap().value - e.eval.value).norm());
            }
            assert!(
                worst <= e.radius,
                "disc about {c:?}, rho {rho}: |H(y) − H(x)| = {worst} > r = {}",
                e.radius
            );
            discs += 1;
            first_order_broken += usize::from(worst > first);
        }
    }
    assert!(
        first_order_broken > 0,
        "{discs} discs, none needed the curvature term"
    );
    // The disc meeting an element has no finite enclosure; bad radii are typed.
    assert!(
        map.enclosure(v(0.0, 1.6), 1.0)
            .unwrap()
            .radius
            .is_infinite()
    );
    for rho in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(map.enclosure(v(0.0, 0.0), rho).is_err());
    }
}

/// The U's pocket, where `det J_H` is 1e-9–1e-6 and the first-order bound left area undecided
/// (docs/maths.md §11), is certified with the second-order cells, every cell of `W_δ` decided.
#[test]
fn the_pocket_is_certified_by_the_second_order_cells() {
    let d = u_world();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.1)).unwrap();
    let delta = map.max_element_length();
    let opts = CertifyOptions {
        max_evaluations: 200_000,
        ..CertifyOptions::new(delta)
    };
    let c = certify(&map, &opts).unwrap();
    assert_eq!(c.verdict, Verdict::Certified, "{c:?}");
    assert!(
        c.undecided_area == 0.0 && c.extremes.min_det < 1e-6,
        "{c:?}"
    );
}
