//! The iterative solve (GMRES with the multipole product, docs/maths/13-harmonic-scaling.md)
//! against the dense LU on small maps: the same map to the solver's tolerance, and the same
//! certificate verdicts (the corner fold of a too-thin δ, the negative control, included).

mod common;

use common::*;
use harmonav_harmonic::{
    CertifyOptions, Domain, HarmonicMap, MeshError, MeshOptions, SolveError, Solver, Verdict,
    certify,
};
use nalgebra::Vector2;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// The bound of `κ(A)` used to turn a residual into an error: the condition numbers measured
/// on the test plans are 1e2–6e3 (docs/maths.md §11), so `|ΔH| ≤ KAPPA·‖r‖/‖b‖` with `H` of
/// order 1.
const KAPPA: f64 = 1e4;

/// Both solves of `domain`; the largest difference of `H` over the midpoints' inward offsets
/// and a grid of the free space, and of the punctures; panics if either exceeds
/// `KAPPA·residual` (the residual of the iterative solve, at least 1e-15).
fn same_map(domain: &Domain, options: &MeshOptions) -> (HarmonicMap, HarmonicMap) {
    let dense = HarmonicMap::new_with(domain, options, Solver::Dense).unwrap();
    let iterative = HarmonicMap::new_with(domain, options, Solver::Iterative).unwrap();
    assert_eq!(dense.setup_cost().iterations, 0);
    assert!(iterative.setup_cost().iterations > 0);
    let residual = iterative.solve_residual();
    assert!(residual <= 1e-10, "{residual:e}");
    let bound = KAPPA * residual.max(1e-15);
    let mut worst = 0.0_f64;
    let delta = dense.max_element_length();
    let mut points = grid(domain, 0.13, delta);
    for e in dense.elements() {
        let t = (e.b - e.a).normalize();
        points.push(e.midpoint() + Vector2::new(-t.y, t.x) * (0.5 * e.length()));
    }
    for x in points {
        let (Ok(a), Ok(b)) = (dense.eval_direct(x), iterative.eval_direct(x)) else {
            continue;
        };
        worst = worst.max((a.value - b.value).amax());
    }
    for (p, q) in dense.punctures().iter().zip(iterative.punctures()) {
        worst = worst.max((p - q).amax());
    }
    assert!(
        worst <= bound,
        "|ΔH| = {worst:e} > {bound:e} (residual {residual:e}, N = {})",
        dense.elements().len()
    );
    (dense, iterative)
}

#[test]
fn the_iterative_solve_is_the_dense_map_on_the_test_plans() {
    for (domain, h) in [
        (square_with_hole(), 0.1),
        (u_world(), 0.1),
        (l_world(), 0.1),
        (two_rooms(), 0.1),
        (pillared_room(), 0.1),
    ] {
        let (dense, iterative) = same_map(&domain, &MeshOptions::graded(h));
        let r = iterative.residuals();
        assert!(
            r.outer < 1e-10 && r.holes < 1e-10 && r.flux < 1e-10,
            "{r:?}"
        );
        assert!(dense.residuals().flux < 1e-10);
    }
}

#[test]
fn the_certificate_decides_the_same_on_both() {
    // The negative control: uniform elements fold at the corners within about h/2, and a δ
    // inside that layer must find the fold on either map.
    let d = square_with_hole();
    let (dense, iterative) = same_map(&d, &MeshOptions::uniform(0.25));
    for map in [&dense, &iterative] {
        let c = certify(map, &CertifyOptions::new(0.01)).unwrap();
        assert!(matches!(c.verdict, Verdict::Fold { .. }), "{c:?}");
    }
    // Beyond one element both are certified, over the same area.
    let (dense, iterative) = same_map(&d, &MeshOptions::graded(0.2));
    let delta = dense.max_element_length();
    let a = certify(&dense, &CertifyOptions::new(delta)).unwrap();
    let b = certify(&iterative, &CertifyOptions::new(delta)).unwrap();
    assert_eq!(a.verdict, Verdict::Certified, "{a:?}");
    assert_eq!(b.verdict, a.verdict);
    assert_eq!(b.certified_area, a.certified_area);
    assert!((b.extremes.min_det - a.extremes.min_det).abs() <= 1e-8 * a.extremes.min_det.abs());
}

/// `Solver::Auto` solves densely up to the crossover (`DENSE_MAX_ELEMENTS`, bit for bit as
/// `Solver::Dense`) and iteratively above it.
#[test]
fn the_default_solves_densely_up_to_the_crossover_and_iteratively_above() {
    let d = pillared_room();
    let map = HarmonicMap::new(&d, &MeshOptions::graded(0.1)).unwrap();
    assert!(map.elements().len() <= harmonav_harmonic::DENSE_MAX_ELEMENTS);
    assert_eq!(map.setup_cost().iterations, 0);
    let dense = HarmonicMap::new_with(&d, &MeshOptions::graded(0.1), Solver::Dense).unwrap();
    assert_eq!(map.punctures(), dense.punctures());
    let fine = HarmonicMap::new(&d, &MeshOptions::graded(0.02)).unwrap();
    assert!(
        fine.elements().len() > harmonav_harmonic::DENSE_MAX_ELEMENTS,
        "{} elements",
        fine.elements().len()
    );
    assert!(fine.setup_cost().iterations > 0);
}

#[test]
fn too_many_elements_names_the_whole_count() {
    // Uniform elements of 2⁻¹⁶: 131 072 per 2 m side, ⌈0.4·65 536⌉ = 26 215 per 0.4 m side.
    let d = square_with_hole();
    let expected = 4 * 131_072 + 4 * 26_215;
    match HarmonicMap::new(&d, &MeshOptions::uniform(1.0 / 65_536.0)) {
        Err(SolveError::Mesh(e @ MeshError::TooManyElements { elements, max })) => {
            assert_eq!(elements, expected);
            assert_eq!(max, harmonav_harmonic::MAX_ELEMENTS);
            let text = e.to_string();
            assert!(text.contains(&expected.to_string()), "{text}");
        }
        other => panic!("{other:?}"),
    }
    // The dense solve on request has its own memory cap, and says so with the count.
    match HarmonicMap::new_with(&d, &MeshOptions::uniform(0.00015), Solver::Dense) {
        Err(SolveError::Mesh(MeshError::TooManyElements { elements, max })) => {
            assert_eq!(max, harmonav_harmonic::DENSE_LIMIT);
            assert!(elements > max);
        }
        other => panic!("{other:?}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 12,
        rng_seed: RngSeed::Fixed(0x0052_4F55_5445_0002),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_polygons_with_holes_give_the_same_map((outer, holes) in random_world(1..5)) {
        let domain = Domain::new(outer, holes);
        prop_assume!(domain.is_ok());
        let domain = domain.unwrap();
        let options = MeshOptions::graded(0.1);
        let n = harmonav_harmonic::mesh::mesh(&domain, &options).map(|m| m.len());
        prop_assume!(matches!(n, Ok(n) if n <= 3000));
        same_map(&domain, &options);
    }
}
