//! Random valid point worlds for the checks, from the shared seeded generator of
//! `harmonav_transform::random` (so `verify` sees the same worlds on every run).

use harmonav_potential::{PointWorld, Vector2};
pub use harmonav_transform::random::Rng;

/// Point-world sampling on top of the shared seeded generator.
pub trait PointWorlds {
    fn world(&mut self, m: usize) -> PointWorld;
}

impl PointWorlds for Rng {
    /// A valid point world with `m` obstacle points in `[-5, 5]²`, all points (destination
    /// included) at least 0.3 apart, default `k = M + 1`.
    fn world(&mut self, m: usize) -> PointWorld {
        loop {
            let mut all: Vec<Vector2<f64>> = Vec::with_capacity(m + 1);
            while all.len() < m + 1 {
                let p = self.point(5.0);
                if all.iter().all(|q| (p - q).norm() >= 0.3) {
                    all.push(p);
                }
            }
            let destination = all.pop().expect("m + 1 points");
            if let Ok(w) = PointWorld::new(destination, all) {
                return w;
            }
        }
    }
}

/// Smallest distance from `h` to the destination and the obstacle points.
pub fn clearance(w: &PointWorld, h: Vector2<f64>) -> f64 {
    w.obstacles()
        .iter()
        .map(|p| (h - p).norm())
        .fold((h - w.destination()).norm(), f64::min)
}
