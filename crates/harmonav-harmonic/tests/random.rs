//! Property tests on random star-shaped rooms with random polygonal holes (seeded, few cases:
//! each case is a solve).

mod common;

use common::*;
use harmonav_harmonic::{Domain, HarmonicMap, MeshError, MeshOptions, SolveError, sampled_check};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

proptest! {
    // Seeded and not persisted: every run draws the same worlds (the default seed is random,
    // and a world whose graded mesh exceeded MAX_ELEMENTS once failed a clean CI run).
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: RngSeed::Fixed(0x0048_4152_4D4E_4157),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_worlds_satisfy_the_equations_and_do_not_fold((outer, holes) in random_world(1..4)) {
        let domain = Domain::new(outer, holes);
        prop_assume!(domain.is_ok());
        let domain = domain.unwrap();
        // A hole that nearly touches a wall grades the mesh past MAX_ELEMENTS: a typed
        // refusal, not a world for this test.
        let map = HarmonicMap::new(&domain, &MeshOptions::graded(0.1));
        prop_assume!(!matches!(
            map,
            Err(SolveError::Mesh(MeshError::TooManyElements { .. }))
        ));
        let map = map.unwrap();
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
