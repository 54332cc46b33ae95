//! A discovery in place (`Workspace::push_obstacle`, `NavTransform::push`) gives the
//! transformation a rebuild over all the obstacles gives, bit for bit; and the comparison is
//! sharp enough to catch a neighbour whose width was not narrowed (the negative control).

use harmonav_transform::random::{self, Kind, Rng, Scattered};
use harmonav_transform::{Active, Lookup, NavTransform, Workspace};
use nalgebra::Vector2;

/// A crowded world: 150 obstacles 0.05 apart in a disc of radius 22 (so that new obstacles
/// often come closer to known ones than those ones' nearest neighbour so far).
fn world() -> Scattered {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    random::scattered(&mut Rng::new(27), 22.0, 150, &kinds, 0.05).unwrap()
}

/// The obstacles added one at a time, in place, to a workspace with `lookup` and to the
/// transformation over all of them; `narrow = false` skips the neighbours' widths.
fn incremental(w: &Scattered, lookup: Lookup, narrow: bool) -> (Workspace, NavTransform) {
    let mut ws = Workspace::with_lookup(w.boundary.clone(), Vec::new(), w.goal, lookup).unwrap();
    let mut phi = NavTransform::new(&ws, &[], 0.0).unwrap();
    for o in &w.obstacles {
        let i = ws.push_obstacle(o.clone()).unwrap();
        phi.push_with(&ws, i, narrow).unwrap();
    }
    (ws, phi)
}

/// The first difference between two transformations: widths, outer band, and `Phi`, `J_Phi`
/// and the active band at `points` (exact comparisons).
fn difference(a: &NavTransform, b: &NavTransform, points: &[Vector2<f64>]) -> Option<String> {
    if a.known() != b.known() {
        return Some("known".into());
    }
    let (wa, wb): (Vec<f64>, Vec<f64>) = (a.widths().collect(), b.widths().collect());
    if let Some(i) = (0..wa.len()).find(|&i| wa[i].to_bits() != wb[i].to_bits()) {
        return Some(format!("width {i}: {} vs {}", wa[i], wb[i]));
    }
    if a.outer_band() != b.outer_band() {
        return Some(format!(
            "outer band {:?} vs {:?}",
            a.outer_band(),
            b.outer_band()
        ));
    }
    for &x in points {
        let (ma, mb) = (a.nav_transform(x), b.nav_transform(x));
        if ma != mb {
            return Some(format!("Phi at {x:?}: {ma:?} vs {mb:?}"));
        }
        if let Ok(m) = ma
            && a.inverse(m.h) != b.inverse(m.h)
        {
            return Some(format!("inverse at {:?}", m.h));
        }
    }
    None
}

/// Free points of `ws`, and how many of them lie in an obstacle band.
fn points(ws: &Workspace, phi: &NavTransform) -> (Vec<Vector2<f64>>, usize) {
    let mut rng = Rng::new(5);
    let xs: Vec<_> = (0..4000)
        .map(|_| random::free_point(&mut rng, ws, 1e-9))
        .collect();
    let banded = xs
        .iter()
        .filter(|&&x| matches!(phi.nav_transform(x), Ok(m) if matches!(m.active, Active::Obstacle { .. })))
        .count();
    (xs, banded)
}

#[test]
fn pushing_obstacles_one_at_a_time_gives_the_rebuilt_transformation_bit_for_bit() {
    let w = world();
    let all: Vec<usize> = (0..w.obstacles.len()).collect();
    for lookup in [Lookup::Indexed, Lookup::Direct] {
        let scratch =
            Workspace::with_lookup(w.boundary.clone(), w.obstacles.clone(), w.goal, lookup)
                .unwrap();
        let rebuilt = NavTransform::new(&scratch, &all, 0.0).unwrap();
        let (ws, pushed) = incremental(&w, lookup, true);
        let (xs, banded) = points(&scratch, &rebuilt);
        assert!(banded > 200, "{lookup:?}: only {banded} points in bands");
        assert_eq!(difference(&pushed, &rebuilt, &xs), None, "{lookup:?}");
        // The workspace grown in place answers as the one built at once.
        let (a, b) = (
            NavTransform::new(&ws, &all, 0.0).unwrap(),
            NavTransform::new(&scratch, &all, 0.0).unwrap(),
        );
        assert_eq!(difference(&a, &b, &xs), None, "{lookup:?}");
    }
}

/// The negative control: without the neighbours' update the widths of the obstacles whose
/// nearest neighbour came later are stale, and the comparison says so (widths and `Phi`).
#[test]
fn a_stale_neighbour_width_is_detected() {
    let w = world();
    let all: Vec<usize> = (0..w.obstacles.len()).collect();
    let scratch = Workspace::new(w.boundary.clone(), w.obstacles.clone(), w.goal).unwrap();
    let rebuilt = NavTransform::new(&scratch, &all, 0.0).unwrap();
    let (_, stale) = incremental(&w, Lookup::Indexed, false);
    let (xs, _) = points(&scratch, &rebuilt);
    let stale_widths = stale
        .widths()
        .zip(rebuilt.widths())
        .filter(|(a, b)| a != b)
        .count();
    assert!(stale_widths > 10, "only {stale_widths} stale widths");
    assert!(difference(&stale, &rebuilt, &xs).is_some());
    // Phi itself differs at some sample point, not just the reported widths.
    assert!(
        xs.iter()
            .any(|&x| stale.nav_transform(x) != rebuilt.nav_transform(x))
    );
}

#[test]
fn a_rejected_obstacle_leaves_the_workspace_unchanged() {
    let w = world();
    let mut ws = Workspace::new(w.boundary.clone(), w.obstacles[..100].to_vec(), w.goal).unwrap();
    let before = ws.clone();
    let over = harmonav_transform::StarShape::circle(w.obstacles[7].centre(), 0.2).unwrap();
    assert!(ws.push_obstacle(over).is_err());
    let all: Vec<usize> = (0..100).collect();
    let (a, b) = (
        NavTransform::new(&ws, &all, 0.0).unwrap(),
        NavTransform::new(&before, &all, 0.0).unwrap(),
    );
    let (xs, _) = points(&before, &b);
    assert_eq!(ws.obstacles().len(), 100);
    assert_eq!(difference(&a, &b, &xs), None);
    // A pushed index that is known already, or not in the workspace, is refused.
    let mut phi = NavTransform::new(&ws, &all, 0.0).unwrap();
    assert!(phi.push(&ws, 3).is_err());
    assert!(phi.push(&ws, 100).is_err());
    assert_eq!(difference(&phi, &b, &xs), None);
}

/// An admission commits only to the state that admitted it: the same workspace (or a clone of
/// it) unchanged since. Another workspace with as many obstacles, or this one after another
/// commit, refuses it (`StaleAdmission`) and is left as it was; before the state token, an
/// admission measured against other obstacles was appended with their distances.
#[test]
fn a_stale_admission_is_refused() {
    use harmonav_transform::WorldError;
    let w = world();
    let ws = Workspace::new(w.boundary.clone(), w.obstacles[..100].to_vec(), w.goal).unwrap();
    let other = Workspace::new(w.boundary.clone(), w.obstacles[1..101].to_vec(), w.goal).unwrap();
    let admitted = ws.admit(w.obstacles[120].clone()).unwrap();
    // Another workspace in the same count of obstacles.
    let mut elsewhere = other.clone();
    assert_eq!(
        elsewhere.commit(admitted.clone()),
        Err(WorldError::StaleAdmission)
    );
    assert_eq!(elsewhere.obstacles().len(), 100);
    // A clone of the admitting state takes it, and then no longer takes a second admission
    // made before that commit.
    let second = ws.admit(w.obstacles[121].clone()).unwrap();
    let mut copy = ws.clone();
    assert_eq!(copy.commit(admitted), Ok(100));
    assert_eq!(copy.commit(second), Err(WorldError::StaleAdmission));
    assert_eq!(copy.obstacles().len(), 101);
}
