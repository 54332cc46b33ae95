//! A small transform buffer (ros2-client has no tf2): the latest transform per edge
//! (parent → child), planar (x, y, yaw; z, roll and pitch are dropped), with stamps checked.
//!
//! - An edge keeps only its latest transform; one whose stamp is older than the stored one's
//!   is dropped (out of order), as is one that is not finite or whose rotation has no yaw.
//! - Static edges (`/tf_static`) never go stale; dynamic ones (`/tf`, `/odom`) are stale once
//!   older than the caller's timeout, measured from their arrival on this machine's steady
//!   clock (stamps are the publisher's clock, which may be simulated or offset).
//! - [`Buffer::lookup`] composes edges from a frame up to an ancestor; where no chain of
//!   edges joins them the caller takes the identity and says so once ([`Lookup::Missing`]).

use std::collections::HashMap;
use std::time::{Duration, Instant};

use crate::msgs::{Time, TransformStamped};

/// A planar rigid transform: `p ↦ R(yaw)·p + (x, y)` (a child's pose in its parent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Se2 {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// yaw, rad.
    pub yaw: f64,
}

impl Se2 {
    /// The identity.
    pub const IDENTITY: Self = Self {
        x: 0.0,
        y: 0.0,
        yaw: 0.0,
    };

    /// The transform `(x, y, yaw)`.
    #[must_use]
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }

    /// `self ∘ other`: `other` expressed in `self`'s parent (a → b then b → c gives a → c).
    #[must_use]
    pub fn compose(&self, other: &Se2) -> Se2 {
        let (s, c) = self.yaw.sin_cos();
        Se2 {
            x: self.x + c * other.x - s * other.y,
            y: self.y + s * other.x + c * other.y,
            yaw: wrap(self.yaw + other.yaw),
        }
    }

    /// The inverse transform.
    #[must_use]
    pub fn inverse(&self) -> Se2 {
        let (s, c) = self.yaw.sin_cos();
        Se2 {
            x: -(c * self.x + s * self.y),
            y: s * self.x - c * self.y,
            yaw: wrap(-self.yaw),
        }
    }

    /// A vector of the child frame in the parent frame (rotation only).
    #[must_use]
    pub fn rotate(&self, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.yaw.sin_cos();
        [c * v[0] - s * v[1], s * v[0] + c * v[1]]
    }

    /// Whether every field is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.yaw.is_finite()
    }
}

/// An angle wrapped into `(−π, π]`.
#[must_use]
pub fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let w = a - t * (a / t).round();
    if w <= -std::f64::consts::PI { w + t } else { w }
}

/// One edge's latest transform.
#[derive(Clone, Debug)]
struct Edge {
    parent: String,
    transform: Se2,
    stamp: Time,
    arrival: Instant,
    is_static: bool,
}

/// Why a transform was not stored.
#[derive(Clone, Debug, PartialEq)]
pub enum Rejected {
    /// A field is not finite, or the rotation has no yaw (zero quaternion).
    NotFinite,
    /// Its stamp is older than the edge's stored transform.
    OutOfOrder,
    /// An empty frame name, or a frame its own parent.
    BadFrames,
    /// The child already has another parent (tf's frames form a tree).
    Reparented {
        /// The parent it has.
        parent: String,
    },
}

impl std::fmt::Display for Rejected {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotFinite => f.write_str("a field is not finite or the rotation is zero"),
            Self::OutOfOrder => f.write_str("stamp older than the edge's latest"),
            Self::BadFrames => f.write_str("empty frame name or a frame its own parent"),
            Self::Reparented { parent } => write!(f, "the child already has parent {parent:?}"),
        }
    }
}

/// The result of [`Buffer::lookup`].
#[derive(Clone, Debug, PartialEq)]
pub enum Lookup {
    /// The transform, and the arrival of its oldest dynamic edge (`None`: all static).
    Found(Se2, Option<Instant>),
    /// No chain of edges from the frame up to the ancestor.
    Missing,
}

/// The latest transform per edge, keyed by child frame.
#[derive(Clone, Debug, Default)]
pub struct Buffer {
    edges: HashMap<String, Edge>,
}

/// Longest chain followed (a loop of edges cannot be built, but a guard costs nothing).
const MAX_DEPTH: usize = 64;

impl Buffer {
    /// An empty buffer.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Stores `parent → child = transform` with its stamp, received at `arrival`.
    ///
    /// # Errors
    /// [`Rejected`]: the buffer is then unchanged.
    pub fn insert(
        &mut self,
        parent: &str,
        child: &str,
        transform: Se2,
        stamp: Time,
        arrival: Instant,
        is_static: bool,
    ) -> Result<(), Rejected> {
        let (parent, child) = (strip(parent), strip(child));
        if parent.is_empty() || child.is_empty() || parent == child {
            return Err(Rejected::BadFrames);
        }
        if !transform.is_finite() {
            return Err(Rejected::NotFinite);
        }
        if let Some(old) = self.edges.get(child) {
            if old.parent != parent {
                return Err(Rejected::Reparented {
                    parent: old.parent.clone(),
                });
            }
            if !old.is_static && !is_static && stamp < old.stamp {
                return Err(Rejected::OutOfOrder);
            }
        }
        // A loop would make `child` an ancestor of `parent`.
        let mut up = parent;
        for _ in 0..MAX_DEPTH {
            if up == child {
                return Err(Rejected::BadFrames);
            }
            match self.edges.get(up) {
                Some(e) => up = &e.parent,
                None => break,
            }
        }
        self.edges.insert(
            child.to_owned(),
            Edge {
                parent: parent.to_owned(),
                transform: Se2 {
                    yaw: wrap(transform.yaw),
                    ..transform
                },
                stamp,
                arrival,
                is_static,
            },
        );
        Ok(())
    }

    /// Stores a `geometry_msgs/TransformStamped`.
    ///
    /// # Errors
    /// [`Rejected`].
    pub fn insert_msg(
        &mut self,
        t: &TransformStamped,
        arrival: Instant,
        is_static: bool,
    ) -> Result<(), Rejected> {
        let tr = &t.transform;
        let yaw = tr.rotation.yaw().ok_or(Rejected::NotFinite)?;
        if !tr.translation.z.is_finite() {
            return Err(Rejected::NotFinite);
        }
        let se2 = Se2::new(tr.translation.x, tr.translation.y, yaw);
        self.insert(
            &t.header.frame_id,
            &t.child_frame_id,
            se2,
            t.header.stamp,
            arrival,
            is_static,
        )
    }

    /// `frame`'s pose in `ancestor` (the composition of the edges up from `frame`).
    #[must_use]
    pub fn lookup(&self, ancestor: &str, frame: &str) -> Lookup {
        let (ancestor, frame) = (strip(ancestor), strip(frame));
        let mut t = Se2::IDENTITY;
        let mut oldest: Option<Instant> = None;
        let mut at = frame;
        for _ in 0..MAX_DEPTH {
            if at == ancestor {
                return Lookup::Found(t, oldest);
            }
            let Some(e) = self.edges.get(at) else {
                return Lookup::Missing;
            };
            t = e.transform.compose(&t);
            if !e.is_static {
                oldest = Some(oldest.map_or(e.arrival, |o| o.min(e.arrival)));
            }
            at = &e.parent;
        }
        Lookup::Missing
    }

    /// Whether a dynamic edge's `arrival` is older than `timeout` at `now`.
    #[must_use]
    pub fn stale(arrival: Option<Instant>, now: Instant, timeout: Duration) -> bool {
        arrival.is_some_and(|a| now.saturating_duration_since(a) > timeout)
    }
}

/// A frame name without tf1's leading slash.
fn strip(frame: &str) -> &str {
    frame.strip_prefix('/').unwrap_or(frame)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msgs::{Header, Quaternion, Transform, Vector3};

    fn close(a: Se2, b: Se2) -> bool {
        (a.x - b.x).abs() < 1e-12 && (a.y - b.y).abs() < 1e-12 && wrap(a.yaw - b.yaw).abs() < 1e-12
    }

    fn t(sec: i32) -> Time {
        Time { sec, nanosec: 0 }
    }

    #[test]
    fn compose_and_inverse() {
        let a = Se2::new(1.0, 2.0, 0.5);
        let b = Se2::new(-0.3, 0.7, -2.0);
        assert!(close(a.compose(&a.inverse()), Se2::IDENTITY));
        assert!(close(a.inverse().compose(&a), Se2::IDENTITY));
        // (a ∘ b) applied to the origin of c is a applied to b's translation.
        let ab = a.compose(&b);
        let p = a.rotate([b.x, b.y]);
        assert!((ab.x - (a.x + p[0])).abs() < 1e-12 && (ab.y - (a.y + p[1])).abs() < 1e-12);
        assert!((wrap(3.5) - (3.5 - std::f64::consts::TAU)).abs() < 1e-15);
        assert_eq!(wrap(std::f64::consts::PI), std::f64::consts::PI);
        assert_eq!(wrap(-std::f64::consts::PI), std::f64::consts::PI);
    }

    #[test]
    fn chain_map_odom_base_laser() {
        let now = Instant::now();
        let mut b = Buffer::new();
        let map_odom = Se2::new(1.0, 0.0, std::f64::consts::FRAC_PI_2);
        let odom_base = Se2::new(2.0, 1.0, 0.1);
        let base_laser = Se2::new(0.2, 0.0, 0.0);
        b.insert("map", "odom", map_odom, t(1), now, false).unwrap();
        b.insert("odom", "base_link", odom_base, t(1), now, false)
            .unwrap();
        b.insert("/base_link", "laser", base_laser, t(0), now, true)
            .unwrap();
        let Lookup::Found(m_l, oldest) = b.lookup("map", "laser") else {
            panic!("missing")
        };
        assert!(close(
            m_l,
            map_odom.compose(&odom_base).compose(&base_laser)
        ));
        assert_eq!(oldest, Some(now));
        // The static edge alone never goes stale.
        assert_eq!(
            b.lookup("base_link", "laser"),
            Lookup::Found(base_laser, None)
        );
        assert_eq!(b.lookup("map", "map"), Lookup::Found(Se2::IDENTITY, None));
        assert_eq!(b.lookup("odom", "map"), Lookup::Missing);
        assert_eq!(b.lookup("map", "camera"), Lookup::Missing);
    }

    #[test]
    fn latest_per_edge_and_stamps_checked() {
        let now = Instant::now();
        let mut b = Buffer::new();
        b.insert(
            "odom",
            "base_link",
            Se2::new(1.0, 0.0, 0.0),
            t(5),
            now,
            false,
        )
        .unwrap();
        // Newer replaces, older is dropped.
        b.insert(
            "odom",
            "base_link",
            Se2::new(2.0, 0.0, 0.0),
            t(6),
            now,
            false,
        )
        .unwrap();
        assert_eq!(
            b.insert(
                "odom",
                "base_link",
                Se2::new(9.0, 0.0, 0.0),
                t(4),
                now,
                false
            ),
            Err(Rejected::OutOfOrder)
        );
        assert!(matches!(b.lookup("odom", "base_link"), Lookup::Found(s, _) if s.x == 2.0));
        // Not finite, bad names, reparenting, loops.
        let nan = Se2::new(f64::NAN, 0.0, 0.0);
        assert_eq!(
            b.insert("odom", "base_link", nan, t(7), now, false),
            Err(Rejected::NotFinite)
        );
        assert_eq!(
            b.insert("", "x", Se2::IDENTITY, t(7), now, false),
            Err(Rejected::BadFrames)
        );
        assert_eq!(
            b.insert("a", "a", Se2::IDENTITY, t(7), now, false),
            Err(Rejected::BadFrames)
        );
        assert!(matches!(
            b.insert("map", "base_link", Se2::IDENTITY, t(7), now, false),
            Err(Rejected::Reparented { .. })
        ));
        assert_eq!(
            b.insert("base_link", "odom", Se2::IDENTITY, t(7), now, false),
            Err(Rejected::BadFrames)
        );
        // A zero quaternion has no yaw.
        let msg = TransformStamped {
            header: Header {
                stamp: t(8),
                frame_id: "odom".into(),
            },
            child_frame_id: "base_link".into(),
            transform: Transform {
                translation: Vector3::default(),
                rotation: Quaternion {
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                    w: 0.0,
                },
            },
        };
        assert_eq!(b.insert_msg(&msg, now, false), Err(Rejected::NotFinite));
    }

    #[test]
    fn staleness_by_arrival() {
        let t0 = Instant::now();
        let later = t0 + Duration::from_millis(600);
        let timeout = Duration::from_millis(500);
        assert!(Buffer::stale(Some(t0), later, timeout));
        assert!(!Buffer::stale(
            Some(t0),
            t0 + Duration::from_millis(400),
            timeout
        ));
        assert!(!Buffer::stale(None, later, timeout));
    }

    #[test]
    fn quaternion_yaw() {
        for yaw in [-3.0, -1.0, 0.0, 0.5, 3.1] {
            let q = Quaternion::from_yaw(yaw);
            assert!((q.yaw().unwrap() - yaw).abs() < 1e-12);
        }
        let q = Quaternion {
            x: 0.0,
            y: 0.0,
            z: 2.0,
            w: 0.0,
        };
        assert!((q.yaw().unwrap() - std::f64::consts::PI).abs() < 1e-12);
        let bad = Quaternion {
            w: f64::NAN,
            ..Quaternion::default()
        };
        assert_eq!(bad.yaw(), None);
    }
}
