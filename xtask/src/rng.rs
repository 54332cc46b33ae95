//! A tiny deterministic generator (SplitMix64) and random valid point worlds for the checks.
//! Seeded, so `verify` and `bench` see the same worlds on every run.

use harmonav_potential::{PointWorld, Vector2};

/// SplitMix64 (Steele, Lea & Flood 2014): enough for sampling test worlds.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn point(&mut self, extent: f64) -> Vector2<f64> {
        Vector2::new(self.uniform(-extent, extent), self.uniform(-extent, extent))
    }

    /// A valid point world with `m` obstacle points in `[-5, 5]²`, all points (destination
    /// included) at least 0.3 apart, default `k = M + 1`.
    pub fn world(&mut self, m: usize) -> PointWorld {
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
