//! Following −∇Θ/|∇Θ| from random starts reaches the goal with k = M + 1 and no tuning.
//! (The 1000-start study per world runs in `cargo xtask verify`.)

use std::sync::Arc;

use harmonav_field::Field;
use harmonav_field::descent::{Ending, FollowOptions, follow};
use harmonav_transform::random::{self, Kind, Rng};

fn study(kinds: &[Kind], outer: Kind, seed: u64, starts: usize) -> (usize, f64) {
    let mut rng = Rng::new(seed);
    let ws = Arc::new(random::workspace(&mut rng, 6, kinds, outer, 0.2));
    let field = Field::all_known(ws.clone()).unwrap();
    assert_eq!(field.k(), 7.0);
    let mut reached = 0;
    let mut worst = 0.0f64;
    for _ in 0..starts {
        let x = random::free_point(&mut rng, &ws, 1e-3);
        let d = follow(&field, x, &FollowOptions::default());
        assert!(d.collision_free, "collision from {x:?}");
        if d.ending == Ending::Reached {
            reached += 1;
            worst = worst.max(d.time);
        }
    }
    (reached, worst)
}

#[test]
fn sphere_world_converges() {
    let (reached, worst) = study(&[Kind::Circle], Kind::Circle, 1, 150);
    assert_eq!(reached, 150, "slowest arrival {worst} s");
}

#[test]
fn mixed_star_world_converges() {
    let all = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    let (reached, worst) = study(&all, Kind::Star, 2, 150);
    assert_eq!(reached, 150, "slowest arrival {worst} s");
}
