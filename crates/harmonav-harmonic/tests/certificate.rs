//! The certificate: it finds folds when δ is inside the boundary layer, and certifies (or
//! leaves undecided, never wrongly certifies) beyond it.

mod common;

use common::*;
use harmonav_harmonic::{
    CertifyError, CertifyOptions, HarmonicMap, MeshOptions, Verdict, certify, sampled_check,
};

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
