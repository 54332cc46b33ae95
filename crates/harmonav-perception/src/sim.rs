//! A simulated lidar for tests: rays cast against true shapes ([`StarShape::ray_hit`]; the
//! boundary's exit by a march and bisection on [`StarShape::contains`]), seeded noise uniform in
//! `[−noise, noise]`, seeded dropouts (NaN), `+∞` when nothing is hit within `range_max`.

use std::f64::consts::TAU;

use harmonav_transform::StarShape;
use harmonav_transform::random::Rng;
use nalgebra::Vector2;

use crate::scan::{LaserScan, Pose};
use crate::walls::Walls;

/// A simulated planar lidar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lidar {
    /// Number of beams.
    pub beams: usize,
    /// Aperture, rad (`2π`: a full turn, beams `2π/beams` apart; otherwise `aperture/(beams − 1)`
    /// apart, centred on the heading).
    pub aperture: f64,
    /// `range_min`, m.
    pub range_min: f64,
    /// `range_max`, m.
    pub range_max: f64,
    /// Half-width of the uniform range noise, m (the true noise bound).
    pub noise: f64,
    /// Fraction of beams that return NaN.
    pub dropout: f64,
}

impl Lidar {
    /// A 360° lidar with `beams` beams, range `[0.05, range_max]`, no noise, no dropouts.
    #[must_use]
    pub fn full_turn(beams: usize, range_max: f64) -> Self {
        Self {
            beams,
            aperture: TAU,
            range_min: 0.05,
            range_max,
            noise: 0.0,
            dropout: 0.0,
        }
    }

    /// `(angle_min, angle_increment)` of the scans.
    #[must_use]
    pub fn angles(&self) -> (f64, f64) {
        if (self.aperture - TAU).abs() < 1e-12 {
            (-std::f64::consts::PI, TAU / self.beams as f64)
        } else {
            let inc = self.aperture / (self.beams.max(2) - 1) as f64;
            (-0.5 * self.aperture, inc)
        }
    }

    /// The noise-free first hit along the unit direction `u` from `s`, if within `range_max`.
    #[must_use]
    pub fn true_range(
        &self,
        s: Vector2<f64>,
        u: Vector2<f64>,
        obstacles: &[StarShape],
        boundary: Option<&StarShape>,
    ) -> Option<f64> {
        self.true_range_in(s, u, obstacles, boundary.into())
    }

    /// [`Lidar::true_range`] inside any [`Enclosure`].
    #[must_use]
    pub fn true_range_in(
        &self,
        s: Vector2<f64>,
        u: Vector2<f64>,
        obstacles: &[StarShape],
        enclosure: Enclosure<'_>,
    ) -> Option<f64> {
        let best = obstacles
            .iter()
            .filter_map(|o| o.ray_hit(s, u, self.range_max))
            .fold(f64::INFINITY, f64::min);
        let best = best.min(
            enclosure
                .exit(s, u, self.range_max.min(best))
                .unwrap_or(f64::INFINITY),
        );
        (best <= self.range_max).then_some(best)
    }

    /// The obstacle (its position in `obstacles`) that the noise-free ray along the unit
    /// direction `u` from `s` hits first, and the range, if within `range_max` and not behind
    /// the `boundary` (which is marched only up to the hit).
    #[must_use]
    pub fn first_obstacle_hit<'a>(
        &self,
        s: Vector2<f64>,
        u: Vector2<f64>,
        obstacles: impl IntoIterator<Item = &'a StarShape>,
        boundary: Option<&StarShape>,
    ) -> Option<(usize, f64)> {
        self.first_obstacle_hit_in(s, u, obstacles, boundary.into())
    }

    /// [`Lidar::first_obstacle_hit`] inside any [`Enclosure`].
    #[must_use]
    pub fn first_obstacle_hit_in<'a>(
        &self,
        s: Vector2<f64>,
        u: Vector2<f64>,
        obstacles: impl IntoIterator<Item = &'a StarShape>,
        enclosure: Enclosure<'_>,
    ) -> Option<(usize, f64)> {
        let (i, t) = obstacles
            .into_iter()
            .enumerate()
            .filter_map(|(i, o)| o.ray_hit(s, u, self.range_max).map(|t| (i, t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        let blocked = enclosure.exit(s, u, t).is_some();
        (!blocked).then_some((i, t))
    }

    /// One scan from `pose` of the truth (`obstacles`, and the `boundary` the sensor is inside).
    #[must_use]
    pub fn scan(
        &self,
        pose: &Pose,
        obstacles: &[StarShape],
        boundary: Option<&StarShape>,
        rng: &mut Rng,
    ) -> LaserScan {
        self.scan_in(pose, obstacles, boundary.into(), rng)
    }

    /// [`Lidar::scan`] inside any [`Enclosure`] (a floor plan's [`Walls`]).
    #[must_use]
    pub fn scan_in(
        &self,
        pose: &Pose,
        obstacles: &[StarShape],
        enclosure: Enclosure<'_>,
        rng: &mut Rng,
    ) -> LaserScan {
        let (angle_min, angle_increment) = self.angles();
        let s = pose.position();
        let ranges = (0..self.beams)
            .map(|i| {
                let a = pose.yaw + angle_min + i as f64 * angle_increment;
                let u = Vector2::new(a.cos(), a.sin());
                let noise = rng.uniform(-self.noise, self.noise);
                if rng.uniform(0.0, 1.0) < self.dropout {
                    return f64::NAN;
                }
                match self.true_range_in(s, u, obstacles, enclosure) {
                    Some(t) => {
                        let r = (t + noise).max(self.range_min);
                        if r >= self.range_max {
                            f64::INFINITY
                        } else {
                            r
                        }
                    }
                    None => f64::INFINITY,
                }
            })
            .collect();
        LaserScan {
            angle_min,
            angle_increment,
            range_min: self.range_min,
            range_max: self.range_max,
            ranges,
        }
    }
}

/// What encloses the sensor, besides the obstacles: nothing, a star boundary, or a floor
/// plan's walls.
#[derive(Clone, Copy, Debug)]
pub enum Enclosure<'a> {
    /// An unbounded world.
    Open,
    /// A star boundary the sensor is inside (its exit marched, then bisected).
    Star(&'a StarShape),
    /// Walls (parry's ray cast on their segments).
    Walls(&'a Walls),
}

impl<'a> From<Option<&'a StarShape>> for Enclosure<'a> {
    fn from(b: Option<&'a StarShape>) -> Self {
        b.map_or(Self::Open, Self::Star)
    }
}

impl Enclosure<'_> {
    /// Where the ray `s + t u` (from inside) first meets the enclosure, if at most `max`.
    #[must_use]
    pub fn exit(&self, s: Vector2<f64>, u: Vector2<f64>, max: f64) -> Option<f64> {
        match self {
            Self::Open => None,
            Self::Star(b) => exit(b, s, u, max),
            Self::Walls(w) => w.ray_hit(s, u, max),
        }
    }
}

/// Where the ray `s + t u` (from inside `b`) first leaves `b`, if at most `max`: a march in
/// steps of `min R_b/64`, then 60 bisections.
fn exit(b: &StarShape, s: Vector2<f64>, u: Vector2<f64>, max: f64) -> Option<f64> {
    let step = b.radius_bounds().0 / 64.0;
    let mut t = 0.0;
    while t < max {
        let next = (t + step).min(max);
        if !b.contains(s + next * u) {
            let (mut lo, mut hi) = (t, next);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if b.contains(s + m * u) {
                    lo = m
                } else {
                    hi = m
                }
            }
            return Some(hi);
        }
        t = next;
    }
    None
}
