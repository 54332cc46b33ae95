//! The chain of certified funnels (`FloorField::funnels`, docs/maths.md §13.10, issue 52):
//! each goal lies in an earlier funnel (eq. chain, checked here independently of the
//! builder), the union covers far more of the U room than the goal's own certified level,
//! and the covered count matches an independent evaluation of every funnel's level; the
//! negative control is the goal's level alone.

mod common;

use harmonav_field::KPolicy;
use harmonav_floorplan::{
    CentrePolicy, FUNNEL_MARGIN, FloorField, FunnelOptions, LevelOptions, MAX_AREA_SAMPLES,
};
use nalgebra::Vector2;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

#[test]
fn the_chain_covers_the_u_room_and_each_goal_lies_in_its_parent() {
    let floor = common::u_room(0.1, 0.2, CentrePolicy::Solve);
    let field = FloorField::new(floor, v(5.2, 2.0), KPolicy::default()).unwrap();
    let level = field.certify_level(&LevelOptions::default());
    let start = v(3.0, 2.6); // in the U's pocket
    let alone = field.certified_area(&level, start, 0.2, &[], MAX_AREA_SAMPLES, 2);
    let options = FunnelOptions {
        max_funnels: 12,
        threads: 2,
        ..FunnelOptions::default()
    };
    let chain = field.funnels(Some(level), start, 0.2, &[], &options);
    let n = chain.funnels.len();
    // The negative control: the goal's own level leaves most of the room uncertified
    // (measured: 27.7 %; the chain of 12 funnels, 94.8 %).
    assert!(alone.fraction() < 0.5, "{alone:?}");
    assert!(n > 1 && n <= 12, "{n} funnels");
    assert!(
        chain.fraction() > alone.fraction() + 0.3,
        "{} against {}",
        chain.fraction(),
        alone.fraction()
    );
    assert_eq!(chain.reachable, alone.reachable);
    // Eq. chain, checked from the fields themselves: the goal of every funnel but the first
    // lies in an earlier one, `FUNNEL_MARGIN` below its level.
    assert!(chain.funnels[0].parent.is_none());
    assert_eq!(chain.funnels[0].goal, v(5.2, 2.0));
    for (i, f) in chain.funnels.iter().enumerate().skip(1) {
        let p = f.parent.expect("a parent");
        assert!(p < i, "funnel {i}'s parent {p}");
        let parent = &chain.funnels[p];
        let phi = parent.field.eval(f.goal).unwrap().phi;
        assert!(
            phi < parent.phi_level() - FUNNEL_MARGIN,
            "funnel {i}'s goal {:?}: phi {phi} in funnel {p} of level {}",
            f.goal,
            parent.phi_level()
        );
        assert!(chain.depth(i) >= 1 && chain.depth(i) < n);
        assert!(f.covered > 0, "funnel {i} covers nothing new");
    }
    // The count, independently: every reachable sample of W_δ that some funnel holds.
    let region = field.reachable_region(start, 0.2, &[], MAX_AREA_SAMPLES);
    let (held, free): (Vec<_>, Vec<_>) = region.samples.iter().partition(|&&p| {
        chain.funnels.iter().any(|f| {
            f.field
                .eval(p)
                .is_ok_and(|e| e.phi < f.phi_level() - FUNNEL_MARGIN)
        })
    });
    assert_eq!(held.len(), chain.certified);
    // The uncovered samples are the others, in the region's order.
    let free: Vec<Vector2<f64>> = free.into_iter().copied().collect();
    assert_eq!(chain.uncovered, free);
    assert_eq!(chain.in_region, chain.certified + chain.uncovered.len());
    let covered: usize = chain.funnels.iter().map(|f| f.covered).sum();
    assert_eq!(covered, chain.certified);
    // Behind the U, where the goal's own level does not reach: in a funnel, the least that
    // holds the point.
    for x in [v(0.6, 0.6), v(0.6, 3.4)] {
        let entry = chain.entry(x).expect("covered");
        assert!(entry > 0 && chain.funnels[entry].holds(x), "{x:?}: {entry}");
        assert!(chain.funnels[..entry].iter().all(|f| !f.holds(x)));
    }
}

/// The enclosures of `H` remembered while a chain is built (`FloorMap::remember_enclosures`)
/// are those computed afresh: the levels come out bit for bit the same, the first time (which
/// fills the memo) and the second (which reads it), and after the guard is dropped.
#[test]
fn remembered_enclosures_give_the_same_levels_bit_for_bit() {
    let floor = common::u_room(0.2, 0.2, CentrePolicy::Solve);
    let field = FloorField::new(floor.clone(), v(5.2, 2.0), KPolicy::default()).unwrap();
    let options = LevelOptions::default();
    let plain = field.certify_level(&options);
    let memo = floor.remember_enclosures();
    let filled = field.certify_level(&options);
    let read = field.certify_level(&options);
    drop(memo);
    let after = field.certify_level(&options);
    assert!(
        plain.phi_certified.is_finite() && plain.evaluations > 0,
        "{plain:?}"
    );
    assert_eq!(filled, plain);
    assert_eq!(read, plain);
    assert_eq!(after, plain);
}
