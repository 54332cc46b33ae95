//! Movers in a star-world file (issue 54, item 4; `docs/movers.md` §8): people and other robots
//! on scripted trajectories, the `[[movers]]` array.
//!
//! ```toml
//! [[movers]]
//! radius = 0.25                 # the body's radius, m
//! speed_bound = 0.8             # V: its speed never exceeds it, m/s
//! error = 0.05                  # ε: the report is within this of the truth, m (default 0)
//! kind = "noncooperative"       # or "reciprocal" (then share, default 0.5)
//! start = [2.0, -3.0]
//! velocity = [0.0, 0.6]         # one of: velocity (constant, at most speed_bound),
//! # waypoints = [[0, 0], [1, 1]] #   waypoints (at speed_bound, looping over them),
//! # random_walk = { seed = 3 }   #   random_walk (seed, turn_every = 1 s, speed = the bound,
//! #                                 area = [[x0, y0], [x1, y1]] to stay in, optional)
//! ```
//!
//! A mover is a ghost to the world: its script is not obstructed by walls or the robot. What a
//! run does with them is harmonav-sim's (the held-command loop, the monitor of contacts).

use harmonav_transform::random::Rng;
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// The most movers a file may have.
pub const MAX_MOVERS: usize = 1000;

/// How a mover takes part in avoidance (`kind`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MoverKindSpec {
    /// A person, or a robot of another stack (the default).
    #[default]
    Noncooperative,
    /// Another harmonav robot taking `share` of the avoidance.
    Reciprocal,
}

/// `random_walk = { seed = …, turn_every = …, speed = …, area = … }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomWalkSpec {
    /// The seed of the directions.
    pub seed: u64,
    /// A new direction, uniform, every this many seconds (at the first control period at or
    /// after), s; default 1.
    #[serde(default = "one_second")]
    pub turn_every: f64,
    /// The speed, m/s (default: the mover's `speed_bound`; at most it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// A box `[[x0, y0], [x1, y1]]` the walk heads back into: a mover outside it turns towards
    /// its centre at the next period.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub area: Option<[[f64; 2]; 2]>,
}

fn one_second() -> f64 {
    1.0
}

/// One `[[movers]]` entry as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MoverSpec {
    /// The body's radius `r_j`, m.
    pub radius: f64,
    /// `V_j`, m/s.
    pub speed_bound: f64,
    /// `ε_j`, m: reports are offset from the truth by a seeded vector of at most this length
    /// (default 0: the report is the truth).
    #[serde(default)]
    pub error: f64,
    /// The seed of the report offsets (default 0; only with `error > 0`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub report_seed: Option<u64>,
    /// `"noncooperative"` (default) or `"reciprocal"`.
    #[serde(default)]
    pub kind: MoverKindSpec,
    /// A reciprocal mover's share of the avoidance taken by the robot (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub share: Option<f64>,
    /// Where it is at `t = 0`.
    #[serde(deserialize_with = "crate::points::point")]
    pub start: [f64; 2],
    /// A constant velocity, m/s.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "optional_point"
    )]
    pub velocity: Option<[f64; 2]>,
    /// Waypoints, visited in order at `speed_bound`, then again from the first.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "optional_ring"
    )]
    pub waypoints: Option<Vec<[f64; 2]>>,
    /// A seeded random walk.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random_walk: Option<RandomWalkSpec>,
}

fn optional_point<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    crate::points::point(d).map(Some)
}

fn optional_ring<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    crate::points::ring(d).map(Some)
}

impl MoverSpec {
    /// The robot's share of a reciprocal mover's avoidance (`share`, default ½); `None` for a
    /// non-cooperative one.
    #[must_use]
    pub fn share(&self) -> Option<f64> {
        (self.kind == MoverKindSpec::Reciprocal).then(|| self.share.unwrap_or(0.5))
    }

    /// The entry checked, the robot's disc of radius `robot` at `robot_start`: on error the key
    /// under `movers[i]` (`speed_bound`, `random_walk.turn_every`, …) and the problem.
    pub fn check(&self, robot_start: [f64; 2], robot: f64) -> Result<(), (String, String)> {
        let bad = |key: &str, p: String| Err((key.to_string(), p));
        let hi = harmonav_transform::MAX_LENGTH;
        let length = |v: f64| v.is_finite() && (0.0..=hi).contains(&v);
        let finite = |p: [f64; 2]| p.iter().all(|c| c.is_finite() && c.abs() <= hi);
        if !length(self.radius) {
            return bad(
                "radius",
                format!("must be finite and in [0, {hi:e}] m, got {:e}", self.radius),
            );
        }
        if !(self.speed_bound.is_finite() && (0.0..=1e6).contains(&self.speed_bound)) {
            return bad(
                "speed_bound",
                format!(
                    "must be finite and in [0, 1e6] m/s, got {:e}",
                    self.speed_bound
                ),
            );
        }
        if !length(self.error) {
            return bad(
                "error",
                format!("must be finite and in [0, {hi:e}] m, got {:e}", self.error),
            );
        }
        if self.report_seed.is_some() && self.error == 0.0 {
            return bad(
                "report_seed",
                "seeds the report's offsets, which only a mover with error > 0 has".into(),
            );
        }
        match (self.kind, self.share) {
            (MoverKindSpec::Noncooperative, Some(_)) => {
                return bad(
                    "share",
                    "only a reciprocal mover takes it (kind = \"reciprocal\")".into(),
                );
            }
            (MoverKindSpec::Reciprocal, Some(s))
                if !(s.is_finite() && (0.0..=1.0).contains(&s)) =>
            {
                return bad("share", format!("must be in [0, 1], got {s:e}"));
            }
            _ => {}
        }
        if !finite(self.start) {
            return bad(
                "start",
                format!("NaN, infinite or beyond {hi:e} m: {:?}", self.start),
            );
        }
        let gap = (Vector2::from(self.start) - Vector2::from(robot_start)).norm()
            - robot
            - self.radius
            - self.error;
        if gap <= 0.0 {
            return bad(
                "start",
                format!(
                    "the mover's disc (grown by its error) overlaps the robot's at robot.start \
                     (gap {gap:e} m)"
                ),
            );
        }
        let scripts = [
            self.velocity.is_some(),
            self.waypoints.is_some(),
            self.random_walk.is_some(),
        ];
        if scripts.iter().filter(|s| **s).count() != 1 {
            return bad(
                "",
                "give exactly one of velocity, waypoints, random_walk".into(),
            );
        }
        if let Some(v) = self.velocity {
            if !finite(v) {
                return bad("velocity", format!("NaN or infinite: {v:?}"));
            }
            let speed = Vector2::from(v).norm();
            if speed > self.speed_bound {
                return bad(
                    "velocity",
                    format!(
                        "its speed {speed:e} m/s exceeds speed_bound = {:e} m/s",
                        self.speed_bound
                    ),
                );
            }
        }
        if let Some(w) = &self.waypoints {
            if w.is_empty() {
                return bad("waypoints", "at least one waypoint".into());
            }
            if let Some(p) = w.iter().find(|p| !finite(**p)) {
                return bad("waypoints", format!("NaN, infinite or too far: {p:?}"));
            }
        }
        if let Some(r) = &self.random_walk {
            let (lo, hi) = harmonav::tuning::PARAMETER_RANGE;
            if !(r.turn_every.is_finite() && (lo..=hi).contains(&r.turn_every)) {
                return bad(
                    "random_walk.turn_every",
                    format!(
                        "must be finite and in [{lo:e}, {hi:e}] s, got {:e}",
                        r.turn_every
                    ),
                );
            }
            if let Some(s) = r.speed
                && !(s.is_finite() && (0.0..=self.speed_bound).contains(&s))
            {
                return bad(
                    "random_walk.speed",
                    format!(
                        "must be in [0, speed_bound = {:e}] m/s, got {s:e}",
                        self.speed_bound
                    ),
                );
            }
            if let Some([a, b]) = r.area
                && !(finite(a) && finite(b) && a[0] < b[0] && a[1] < b[1])
            {
                return bad(
                    "random_walk.area",
                    format!(
                        "must be [[x0, y0], [x1, y1]] with x0 < x1, y0 < y1, got {:?}",
                        [a, b]
                    ),
                );
            }
        }
        Ok(())
    }

    /// The mover's script at `t = 0`.
    #[must_use]
    pub fn script(&self) -> Script {
        let start = Vector2::from(self.start);
        let motion = if let Some(v) = self.velocity {
            Motion::Constant(Vector2::from(v))
        } else if let Some(w) = &self.waypoints {
            Motion::Waypoints {
                points: w.iter().map(|p| Vector2::from(*p)).collect(),
                next: 0,
                speed: self.speed_bound,
            }
        } else if let Some(r) = &self.random_walk {
            Motion::Walk {
                rng: Rng::new(r.seed),
                every: r.turn_every,
                speed: r.speed.unwrap_or(self.speed_bound),
                area: r.area.map(|[a, b]| (Vector2::from(a), Vector2::from(b))),
                velocity: Vector2::zeros(),
                until: 0.0,
            }
        } else {
            Motion::Constant(Vector2::zeros())
        };
        Script {
            position: start,
            time: 0.0,
            motion,
            breaks: Vec::new(),
        }
    }
}

/// How a script moves.
#[derive(Clone, Debug)]
enum Motion {
    Constant(Vector2<f64>),
    Waypoints {
        points: Vec<Vector2<f64>>,
        /// The waypoint it heads to.
        next: usize,
        speed: f64,
    },
    Walk {
        rng: Rng,
        every: f64,
        speed: f64,
        area: Option<(Vector2<f64>, Vector2<f64>)>,
        velocity: Vector2<f64>,
        /// Its velocity holds until this time.
        until: f64,
    },
}

/// A mover's true motion, advanced one control period at a time: straight within a period
/// except where a waypoint is reached, so that every motion is a chain of straight pieces
/// ([`Script::advance`] gives their ends).
#[derive(Clone, Debug)]
pub struct Script {
    position: Vector2<f64>,
    time: f64,
    motion: Motion,
    breaks: Vec<(f64, Vector2<f64>)>,
}

impl Script {
    /// The true centre now.
    #[must_use]
    pub fn position(&self) -> Vector2<f64> {
        self.position
    }

    /// Advances the script by `h` s: the ends of its straight pieces over the period, as
    /// `(τ, centre)` with `τ` from 0 (the position before) to `h` (after), in order.
    pub fn advance(&mut self, h: f64) -> &[(f64, Vector2<f64>)] {
        self.breaks.clear();
        self.breaks.push((0.0, self.position));
        match &mut self.motion {
            Motion::Constant(v) => self.position += h * *v,
            Motion::Waypoints {
                points,
                next,
                speed,
            } => {
                let mut left = h;
                // At most one lap of the waypoints per piece, so a loop of length 0 parks.
                for _ in 0..=points.len() {
                    if *speed <= 0.0 {
                        break;
                    }
                    let to = points[*next] - self.position;
                    let d = to.norm();
                    if d > *speed * left {
                        self.position += (*speed * left / d) * to;
                        break;
                    }
                    self.position = points[*next];
                    left -= d / *speed;
                    *next = (*next + 1) % points.len();
                    self.breaks.push((h - left, self.position));
                }
            }
            Motion::Walk {
                rng,
                every,
                speed,
                area,
                velocity,
                until,
            } => {
                if self.time >= *until - 1e-12 {
                    let a = rng.uniform(0.0, std::f64::consts::TAU);
                    *velocity = *speed * Vector2::new(a.cos(), a.sin());
                    *until += *every;
                }
                if let Some((lo, hi)) = area {
                    let p = self.position;
                    if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y {
                        let back = 0.5 * (*lo + *hi) - p;
                        *velocity = *speed * back / back.norm().max(f64::MIN_POSITIVE);
                    }
                }
                self.position += h * *velocity;
            }
        }
        self.time += h;
        if self.breaks.last().is_none_or(|b| b.0 < h) {
            self.breaks.push((h, self.position));
        } else if let Some(last) = self.breaks.last_mut() {
            *last = (h, self.position);
        }
        &self.breaks
    }
}

/// A report of a mover with error `ε`: the truth offset by a vector drawn uniformly in the
/// disc of radius `ε` (the truth itself for `ε = 0`).
pub fn report(truth: Vector2<f64>, error: f64, rng: &mut Rng) -> Vector2<f64> {
    if error == 0.0 {
        return truth;
    }
    let (r, a) = (
        error * rng.uniform(0.0, 1.0).sqrt(),
        rng.uniform(0.0, std::f64::consts::TAU),
    );
    truth + Vector2::new(r * a.cos(), r * a.sin())
}

/// Every mover of a file checked against the robot's `start` and `radius` ([`MoverSpec::check`]);
/// on the first bad one, its key (`movers[i]`, or `movers[i].key`) and the problem.
pub(crate) fn check_all(
    movers: &[MoverSpec],
    start: [f64; 2],
    radius: f64,
) -> Result<(), (String, String)> {
    for (i, m) in movers.iter().enumerate() {
        m.check(start, radius).map_err(|(key, p)| {
            let field = if key.is_empty() {
                format!("movers[{i}]")
            } else {
                format!("movers[{i}].{key}")
            };
            (field, p)
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(script: &str) -> MoverSpec {
        toml::from_str(&format!(
            "radius = 0.2\nspeed_bound = 1.0\nstart = [0.0, 0.0]\n{script}"
        ))
        .unwrap()
    }

    #[test]
    fn waypoints_loop_at_the_bound_with_a_break_at_each_waypoint() {
        let mut s = spec("waypoints = [[1.0, 0.0], [1.0, 1.0]]").script();
        let b = s.advance(1.5).to_vec();
        assert_eq!(b.len(), 3);
        assert!((b[1].0 - 1.0).abs() < 1e-12 && (b[1].1 - Vector2::new(1.0, 0.0)).norm() < 1e-12);
        assert!((b[2].1 - Vector2::new(1.0, 0.5)).norm() < 1e-12);
        // Then back towards the first waypoint, the loop.
        s.advance(0.5);
        let p = s.advance(0.5).last().unwrap().1;
        assert!((p - Vector2::new(1.0, 0.5)).norm() < 1e-12, "{p}");
    }

    #[test]
    fn a_random_walk_keeps_its_speed_and_its_area() {
        let mut s =
            spec("random_walk = { seed = 4, turn_every = 0.3, area = [[-1.0, -1.0], [1.0, 1.0]] }")
                .script();
        for _ in 0..2000 {
            let b = s.advance(0.05).to_vec();
            let step = (b[1].1 - b[0].1).norm();
            assert!(step <= 0.05 + 1e-12);
            assert!(s.position().amax() < 1.1, "{}", s.position());
        }
    }

    #[test]
    fn a_zero_length_loop_parks() {
        let mut s = spec("waypoints = [[0.5, 0.0]]").script();
        for _ in 0..10 {
            s.advance(0.4);
        }
        assert!((s.position() - Vector2::new(0.5, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn reports_stay_within_the_error() {
        let mut rng = Rng::new(1);
        for _ in 0..1000 {
            assert!(report(Vector2::zeros(), 0.1, &mut rng).norm() <= 0.1);
        }
        assert_eq!(
            report(Vector2::new(1.0, 2.0), 0.0, &mut rng),
            Vector2::new(1.0, 2.0)
        );
    }
}
