//! Property tests on random star-shaped rooms with random polygonal holes (seeded, few cases:
//! each case is a solve).

mod common;

use common::*;
use harmonav_harmonic::{Domain, HarmonicMap, MeshOptions, sampled_check};
use nalgebra::Vector2;
use proptest::prelude::*;
use std::f64::consts::TAU;

fn world() -> impl Strategy<Value = (Vec<Vector2<f64>>, Vec<Vec<Vector2<f64>>>)> {
    let outer = prop::collection::vec((0.0..0.6_f64, 0.8..1.3_f64), 6..11).prop_map(|v| {
        let n = v.len();
        v.iter()
            .enumerate()
            .map(|(i, &(jitter, r))| {
                let t = TAU * (i as f64 + jitter) / n as f64;
                Vector2::new(r * t.cos(), r * t.sin())
            })
            .collect::<Vec<_>>()
    });
    let hole = (
        -0.4..0.4_f64,
        -0.4..0.4_f64,
        0.05..0.15_f64,
        3_usize..6,
        0.0..1.0_f64,
    )
        .prop_map(|(x, y, r, n, phase)| {
            (0..n)
                .map(|i| {
                    let t = -TAU * (i as f64 + phase) / n as f64;
                    Vector2::new(x + r * t.cos(), y + r * t.sin())
                })
                .collect::<Vec<_>>()
        });
    (outer, prop::collection::vec(hole, 1..4))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn random_worlds_satisfy_the_equations_and_do_not_fold((outer, holes) in world()) {
        let domain = Domain::new(outer, holes);
        prop_assume!(domain.is_ok());
        let domain = domain.unwrap();
        let map = HarmonicMap::new(&domain, &MeshOptions::graded(0.1)).unwrap();
        let r = map.residuals();
        prop_assert!(r.outer < 1e-10 && r.holes < 1e-10 && r.flux < 1e-10, "{r:?}");
        let delta = map.max_element_length();
        let s = sampled_check(&map, delta, 0.06).unwrap();
        prop_assert_eq!(s.folds, 0, "{:?}", s);
        prop_assert_eq!(s.outside_disk, 0, "{:?}", s);
        // The Jacobian against differences at a few points of W_δ.
        for x in grid(&domain, 0.37, delta).into_iter().take(6) {
            let e = map.eval(x).unwrap();
            let fd = fd_jacobian(&map, x, 1e-6);
            prop_assert!((e.jacobian - fd).amax() < 1e-6 * e.jacobian.amax().max(1.0));
        }
    }
}
