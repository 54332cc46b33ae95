//! The spatial index gives the direct loops' answers, bit for bit (docs/maths.md §14): on
//! seeded worlds of many obstacles of the four shapes, `Workspace`, `NavTransform` (its widths,
//! `Phi`, `J_Phi` and `Phi⁻¹`) built with `Lookup::Indexed` equal those built with
//! `Lookup::Direct`, including the errors of overlapping worlds.

use harmonav_transform::random::{self, Kind, Rng};
use harmonav_transform::{Lookup, NavTransform, StarShape, Workspace, WorldError};
use nalgebra::Vector2;

const KINDS: [Kind; 4] = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];

fn both(
    boundary: &StarShape,
    obstacles: &[StarShape],
    goal: Vector2<f64>,
) -> (Result<Workspace, WorldError>, Result<Workspace, WorldError>) {
    let make = |lookup| Workspace::with_lookup(boundary.clone(), obstacles.to_vec(), goal, lookup);
    (make(Lookup::Direct), make(Lookup::Indexed))
}

/// Widths, `Phi` with its Jacobian and band, and `Phi⁻¹` agree bit for bit at points all over
/// the world, a third of them in or next to the obstacles' bands, for all obstacles known and
/// for a random subset (whose widths need the far pairs the index finds).
#[test]
fn indexed_transform_equals_the_direct_loop_on_seeded_worlds() {
    for seed in 0..4u64 {
        let mut rng = Rng::new(100 + seed);
        let m = [60, 150, 250, 40][seed as usize];
        let w = random::scattered(&mut rng, 25.0, m, &KINDS, 0.2).unwrap();
        let (direct, indexed) = both(&w.boundary, &w.obstacles, w.goal);
        let (direct, indexed) = (direct.unwrap(), indexed.unwrap());
        let subset: Vec<usize> = (0..m).filter(|_| rng.below(3) == 0).collect();
        let all: Vec<usize> = (0..m).collect();
        for known in [&all, &subset] {
            let a = NavTransform::new(&direct, known, 7.0).unwrap();
            let b = NavTransform::new(&indexed, known, 7.0).unwrap();
            let (wa, wb): (Vec<f64>, Vec<f64>) = (a.widths().collect(), b.widths().collect());
            assert_eq!(wa, wb, "seed {seed}: widths");
            assert_eq!(a.outer_band(), b.outer_band());
            let mut in_band = 0;
            for n in 0..3000 {
                let x = if n % 3 == 0 {
                    // Near a known obstacle: inside it, in its band or just beyond.
                    let o = &direct.obstacles()[known[rng.below(known.len())]];
                    let r = o.radius_bounds().1;
                    o.centre() + rng.uniform(0.0, 1.6 * r) * unit(rng.uniform(0.0, 6.3))
                } else {
                    rng.point(25.0)
                };
                let (pa, pb) = (a.nav_transform(x), b.nav_transform(x));
                assert_eq!(pa, pb, "seed {seed}, x = {x:?}");
                if let Ok(p) = pa {
                    in_band += usize::from(p.h != x);
                    assert_eq!(a.inverse(p.h), b.inverse(p.h), "seed {seed}, h = {:?}", p.h);
                }
            }
            // The comparison saw the bands, not only the identity region.
            assert!(in_band > 200, "seed {seed}: {in_band} points in bands");
        }
    }
}

fn unit(a: f64) -> Vector2<f64> {
    Vector2::new(a.cos(), a.sin())
}

/// Overlapping and touching obstacles are reported as the same pair by both lookups, and so is
/// the first failing pair of `with_obstacle`; adding the obstacles one at a time gives the
/// widths `Workspace::new` gives.
#[test]
fn indexed_pair_checks_report_the_direct_loops_errors() {
    let mut rng = Rng::new(7);
    let w = random::scattered(&mut rng, 20.0, 120, &KINDS, 0.2).unwrap();
    for trial in 0..12 {
        let mut obstacles = w.obstacles.clone();
        // Copies of a few obstacles, shifted by less than their size: overlaps, in random places
        // of the order.
        for _ in 0..1 + trial % 3 {
            let i = rng.below(obstacles.len());
            let o = &obstacles[i];
            let shift = rng.uniform(0.0, 0.9 * o.radius_bounds().0) * unit(rng.uniform(0.0, 6.3));
            let copy = random::shape(&mut rng, Kind::Circle, o.centre() + shift, 0.4);
            let at = rng.below(obstacles.len() + 1);
            obstacles.insert(at, copy);
        }
        let (direct, indexed) = both(&w.boundary, &obstacles, w.goal);
        assert_eq!(
            direct.as_ref().err(),
            indexed.as_ref().err(),
            "trial {trial}"
        );
        assert!(direct.is_err(), "trial {trial}: the copies overlap");
    }
    // One at a time (Indexed), against all at once (Direct).
    let (direct, _) = both(&w.boundary, &w.obstacles, w.goal);
    let direct = direct.unwrap();
    let mut ws = Workspace::new(w.boundary.clone(), Vec::new(), w.goal).unwrap();
    for o in &w.obstacles {
        ws = ws.with_obstacle(o.clone()).unwrap();
    }
    let all: Vec<usize> = (0..w.obstacles.len()).collect();
    let a = NavTransform::new(&direct, &all, 0.0).unwrap();
    let b = NavTransform::new(&ws, &all, 0.0).unwrap();
    assert_eq!(
        a.widths().collect::<Vec<_>>(),
        b.widths().collect::<Vec<_>>()
    );
    // A new obstacle that overlaps a known one names it, with the index as with the direct loop
    // (the ordering of two overlaps is not exercised here).
    let (p, q) = (&w.obstacles[3], &w.obstacles[90]);
    for (first, o) in [(3, p), (90, q)] {
        let over = StarShape::circle(o.centre(), 0.2).unwrap();
        let direct = Workspace::with_lookup(
            w.boundary.clone(),
            w.obstacles.clone(),
            w.goal,
            Lookup::Direct,
        )
        .unwrap()
        .with_obstacle(over.clone());
        assert_eq!(
            direct.err(),
            Some(WorldError::Overlap { first, second: 120 })
        );
        assert_eq!(
            ws.with_obstacle(over).err(),
            Some(WorldError::Overlap { first, second: 120 })
        );
    }
}
