//! Segmentation of an ordered scan at range jumps, with the ends classified.
//!
//! Two neighbouring beams `i`, `j = i + 1` (and the last and first beams of a full turn) lie in
//! one segment when both are usable hits (returns not explained by a known shape) and
//!
//! ```text
//! |p_i − p_j| ≤ d0 + max(r_i, r_j)·Δθ                                   (eq. jump)
//! ```
//!
//! (`r·Δθ` is the spacing of the hits on a surface facing the sensor at range `r`; `d0` absorbs
//! the noise, `2·range_noise` at least, and oblique surfaces). A segment's end beside a *closer*
//! return (or a `−∞` reading) is [`End::Occluded`]: the obstacle may continue behind the
//! occluder. Beside a farther return or a no-return it is [`End::Free`]; beside an invalid
//! reading or the scan's edge, [`End::Unknown`].

use nalgebra::Vector2;

use crate::scan::{LaserScan, Pose, Reading};

/// The most consecutive invalid readings (NaN, below `range_min`) a segment bridges: the hits on
/// either side are then neighbours for eq. jump (with the wider angle) and for (A2).
pub const MAX_BRIDGE: usize = 2;

/// What lies beyond one end of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// The neighbouring beam returns farther or not at all: the silhouette ends here.
    Free,
    /// The neighbouring beam returns closer (or `−∞`): the obstacle may continue behind it.
    Occluded,
    /// No information: an invalid reading, or the edge of a scan that is not a full turn.
    Unknown,
}

impl End {
    /// A stable name for reports.
    #[must_use]
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Free => "free",
            Self::Occluded => "occluded",
            Self::Unknown => "unknown",
        }
    }
}

/// A run of neighbouring usable hits, in angular order.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Beam indices in angular order (they wrap past the last beam of a full turn).
    pub beams: Vec<usize>,
    /// Beyond the first beam.
    pub start: End,
    /// Beyond the last beam.
    pub end: End,
}

/// The hit point `p_i = s + r_i u_i` of beam `i`, if it is a hit.
#[must_use]
pub fn hit_point(scan: &LaserScan, pose: &Pose, i: usize) -> Option<Vector2<f64>> {
    match scan.reading(i) {
        Reading::Hit(r) => Some(pose.position() + r * scan.direction(pose, i)),
        _ => None,
    }
}

/// Splits the usable hits (`usable[i]`: beam `i` is a hit the caller keeps; `Perception`
/// keeps those the boundary and the map obstacles do not explain) into
/// segments by eq. jump with `d0 = jump_distance`. The scan must be valid
/// ([`LaserScan::validate`]) and `usable.len()` must equal the number of beams.
#[must_use]
pub fn segment(scan: &LaserScan, pose: &Pose, usable: &[bool], jump_distance: f64) -> Vec<Segment> {
    let n = scan.ranges.len();
    assert_eq!(usable.len(), n, "one usable flag per beam");
    let wrap = scan.full_turn() && n > 1;
    let points: Vec<Option<Vector2<f64>>> = (0..n)
        .map(|i| usable[i].then(|| hit_point(scan, pose, i)).flatten())
        .collect();
    let range = |i: usize| match scan.reading(i) {
        Reading::Hit(r) => r,
        _ => f64::NAN,
    };
    // linked[i]: beam i and the next usable beam j (across at most MAX_BRIDGE invalid
    // readings) are in one segment; eq. jump with the angle (j − i)·Δθ.
    let mut linked = vec![false; n];
    let mut next_usable: Vec<Option<usize>> = vec![None; n];
    for i in 0..n {
        let Some(a) = points[i] else { continue };
        for k in 1..=MAX_BRIDGE + 1 {
            if i + k >= n && !wrap {
                break;
            }
            let j = (i + k) % n;
            if j == i {
                break;
            }
            if let Some(b) = points[j] {
                let gap = jump_distance + range(i).max(range(j)) * k as f64 * scan.angle_increment;
                if (a - b).norm() <= gap {
                    linked[i] = true;
                    next_usable[i] = Some(j);
                }
                break;
            }
            if scan.reading(j) != Reading::Invalid {
                break;
            }
        }
    }
    let end_beside = |here: usize, neighbour: Option<usize>| -> End {
        let Some(k) = neighbour else {
            return End::Unknown;
        };
        match scan.reading(k) {
            Reading::Hit(r) if r < range(here) => End::Occluded,
            Reading::Hit(_) | Reading::NoReturn => End::Free,
            Reading::TooClose => End::Occluded,
            Reading::Invalid => End::Unknown,
        }
    };
    let prev = |i: usize| {
        if i > 0 {
            Some(i - 1)
        } else if wrap {
            Some(n - 1)
        } else {
            None
        }
    };
    let next = |i: usize| {
        if i + 1 < n {
            Some(i + 1)
        } else if wrap {
            Some(0)
        } else {
            None
        }
    };
    // Start at a hit no link arrives at, so that no segment straddles the start of the loop.
    let mut target = vec![false; n];
    for i in 0..n {
        if let (true, Some(j)) = (linked[i], next_usable[i]) {
            target[j] = true;
        }
    }
    let Some(first) = (0..n).find(|&i| points[i].is_some() && !target[i]) else {
        let beams: Vec<usize> = (0..n).filter(|&i| points[i].is_some()).collect();
        if beams.is_empty() {
            return Vec::new();
        }
        // Every hit linked to the next: one closed ring of hits.
        return vec![Segment {
            beams,
            start: End::Unknown,
            end: End::Unknown,
        }];
    };
    let mut segments = Vec::new();
    let mut current: Vec<usize> = Vec::new();
    let mut seen = vec![false; n];
    for step in 0..n {
        let i = (first + step) % n;
        if points[i].is_none() || seen[i] {
            continue;
        }
        // A segment starts here: follow the links.
        let mut k = i;
        loop {
            seen[k] = true;
            current.push(k);
            match next_usable[k] {
                Some(j) if linked[k] && !seen[j] => k = j,
                _ => break,
            }
        }
        let (a, b) = (current[0], *current.last().expect("not empty"));
        segments.push(Segment {
            beams: std::mem::take(&mut current),
            start: end_beside(a, prev(a)),
            end: end_beside(b, next(b)),
        });
    }
    segments
}
