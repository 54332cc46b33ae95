//! What a scan shows free, and the wall prior: the sets a fit may leave out of its region `Y`
//! (docs/maths.md §12.7, eqs. freefan and wallgap).
//!
//! **The free fan** (eq. freefan, **derived**). Take two neighbouring valid beams `i`, `j`
//! (`Δ = ∠(u_i, u_j) < π`, readings without information skipped) free up to `f_i`, `f_j`
//! ([`LaserScan::free_until`]), shortened (below) so that the chord `c = |a − b|` between
//! `a = s + f_i u_i` and `b = s + f_j u_j` is below `2ρ_min`. With `H` the distance from `s` to
//! the chord's line and `n` its unit normal away from `s`:
//!
//! ```text
//! T_ij = { x in the triangle (s, a, b) : n·(x − s) < H − sag(c) },   sag(c) = ρ_min − √(ρ_min² − c²/4)
//! Φ    = int(∪ closure T_ij)                                                      (eq. freefan)
//! ```
//!
//! *Why no obstacle meets `T_ij`.* Under (A4) a point `x` of an obstacle lies in a closed disc
//! `B ⊂ O` of radius `ρ_min`. The open disc `int B` misses the closed beams `[s, a]`, `[s, b]`
//! (a beam is free before the true first hit `r* ≥ f`, A1, and an open disc through the first
//! hit would hold beam points before it). `int(s, a, b)` is a component of the open near
//! half-plane of the chord's line minus the two beams, so `int B ∩ {near side}` (convex,
//! meeting `int(s, a, b)` near `x`) lies in the triangle. If `B`'s centre were on the near side
//! at distance `d ≥ 0` from the line, the triangle's section at that level, narrower than `c`,
//! would have to hold the disc's diameter `2ρ_min > c`: impossible. So the centre is beyond the
//! line, `int B` meets the line inside the open chord (it cannot straddle `a` or `b`: it would
//! hold them, and beam points before them), the chord of `B` on the line is at most `c` long,
//! and the cap of `B` on the near side is at most `sag(c)` deep. Hence `O ∩ T_ij = ∅`, and
//! `O ∩ Φ = ∅` (points of `Φ` on a shared beam or at `s` are free too).
//!
//! *Shortening.* A beam shortened is still free, so any `f'_i ≤ f_i`, `f'_j ≤ f_j` with a chord
//! below `C = 1.998 ρ_min` gives a sound wedge; [`FreeSpace::of_scan`] keeps the largest of a
//! few (the longer beam cut towards the shorter's length `m`, or both at `C/(2 sin(Δ/2))`).
//!
//! **The wall prior** (eq. wallgap, an assumption of its own, [`crate::Options::wall_gap`]):
//! an unknown obstacle keeps at least `g_w` from the workspace boundary `∂W` (star about
//! `c_W`, radius `≤ R_W`). Then `O ⊂ W_{g_w} = {x ∈ W : d(x, ∂W) ≥ g_w} ⊂ B(c_W, R_W − g_w)`
//! (a point of `W` farther than `R_W − g_w` from `c_W` is within `g_w` of the boundary point on
//! its ray), so the outside of that disc may be left out too. For a circular workspace the
//! disc is `W_{g_w}` itself.
//!
//! **How a fit uses them.** With `R = Φ ∪ (ℝ² \ B(c_W, R_W − g_w))` open and `O ∩ R = ∅`, the
//! fit certifies its star over a cover of `∂(Y \ R) ⊂ (∂Y \ R) ∪ (∂R ∩ Y)`: the samples of
//! `∂Y` whose ball of radius `h/2` is not inside `R` ([`FreeSet::contains_ball`]), and the
//! samples of `∂R` at spacing `h` within `h` of `Y` ([`FreeSet::boundary_samples`]). Every
//! point of `∂(Y \ R)` is then within `h/2` of a sample, so eq. certify gives `Y \ R ⊂ F`, and
//! `O ⊂ Y \ R`: the claim `O ⊂ F` stands.

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::scan::{LaserScan, Pose, Reading};
use crate::walls::Walls;

/// `C/(2ρ_min)`: how close to `2ρ_min` a chord of the fan may come.
const CHORD_FRACTION: f64 = 0.999;

/// One triangle of eq. freefan: the directions of its two beams (angles from the first valid
/// beam), its far vertices and its chord line `n·(x − s) = depth`.
#[derive(Clone, Copy, Debug)]
struct Wedge {
    /// Start and end angle, rad, measured from the scan's first valid beam (`end − start < π`).
    start: f64,
    end: f64,
    /// The beam index the wedge ends on (the next wedge starts there when they are adjacent).
    first: usize,
    last: usize,
    /// The far vertices, on the start and end beams.
    a: Vector2<f64>,
    b: Vector2<f64>,
    /// Unit normal of the (moved) chord line, away from `s`.
    n: Vector2<f64>,
    /// `H − sag(c) > 0`: the distance from `s` to the moved chord line.
    depth: f64,
}

/// The wall prior (eq. wallgap): the set a fit keeps to, whose outside no unknown obstacle
/// meets. For a star boundary the disc `B(c_W, R_W − g_w)`; for a floor plan's walls
/// ([`Walls`]) the level set `{sd ≥ g_w}` itself (`g_w = 0`: the free space).
#[derive(Clone, Debug)]
pub enum WallPrior {
    /// `B(c_W, R_W − g_w)` of a star boundary.
    Disc {
        /// `c_W`.
        centre: Vector2<f64>,
        /// `R_W − g_w > 0`, m.
        radius: f64,
    },
    /// `{sd ≥ g_w}` of known walls, `sd` their signed distance (docs/maths.md §12.17).
    Level {
        /// The walls.
        walls: Arc<Walls>,
        /// `g_w ≥ 0`, m.
        gap: f64,
    },
}

impl WallPrior {
    /// The disc of eq. wallgap for the boundary `boundary` and the gap `gap` (`R_W` its certified
    /// largest radius); `None` when the gap is not positive or leaves no disc.
    #[must_use]
    pub fn new(boundary: &StarShape, gap: f64) -> Option<Self> {
        let radius = boundary.radius_bounds().1 - gap;
        (gap > 0.0 && radius > 0.0 && radius.is_finite()).then_some(Self::Disc {
            centre: boundary.centre(),
            radius,
        })
    }

    /// Whether the closed ball `B(x, t)` lies beyond the prior (outside the disc, or in
    /// `{sd < g_w}`: `sd(x) + t < g_w` by the 1-Lipschitz bound).
    fn holds_ball_beyond(&self, x: Vector2<f64>, t: f64) -> bool {
        match self {
            Self::Disc { centre, radius } => (x - centre).norm() - t > *radius,
            Self::Level { walls, gap } => {
                // Quick: a ball farther than the gap from every wall lies on one side.
                let d = walls.distance(x);
                d + t < *gap || (d > t && !walls.contains(x))
            }
        }
    }
}

/// The set `R` a fit may leave out of its region: the scan's free fan (eq. freefan) and the
/// outside of the wall prior's disc (eq. wallgap). No true obstacle meets it under (A1), (A4)
/// and the wall prior (module docs).
#[derive(Clone, Debug)]
pub struct FreeSpace {
    s: Vector2<f64>,
    /// Wedges in angular order.
    wedges: Vec<Wedge>,
    /// The world angle of the first valid beam: the wedges' angles are measured from it.
    origin: f64,
    /// Whether the scan is a full turn (the last valid beam's wedge ends on the first, at `2π`).
    full: bool,
    /// Edges of `∂Φ` (chords and the beam pieces between neighbouring wedges).
    edges: Vec<(Vector2<f64>, Vector2<f64>)>,
    /// The radius of eq. free's disc about `s` (0: none).
    disc: f64,
    wall: Option<WallPrior>,
}

/// Which of the scan's free evidence a fit leaves out of its region (`crate::Options`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FreeEvidence {
    /// The disc about the sensor of eq. free ([`crate::free_radius`]). The default: the closed
    /// loop keeps every seen truth point covered with it (docs/maths.md §12.7).
    #[default]
    Disc,
    /// The whole free fan of eq. freefan. Sound on its own (`tests/free.rs`) and, since eq.
    /// attribution, in closed loop (docs/maths.md §12.9: no seen truth point uncovered in the
    /// suites and the lidar benchmark); not the default, as its arrivals are mixed there.
    Fan,
}

impl FreeSpace {
    /// Nothing known free: a fit contains its whole region `Y`.
    #[must_use]
    pub fn none(s: Vector2<f64>) -> Self {
        Self {
            s,
            wedges: Vec::new(),
            origin: 0.0,
            full: false,
            edges: Vec::new(),
            disc: 0.0,
            wall: None,
        }
    }

    /// The free evidence `kind` of `scan` taken at `pose`: eq. free's disc (when its radius
    /// exceeds `h`, the cover's spacing) or eq. freefan's fan.
    #[must_use]
    pub fn of_kind(
        kind: FreeEvidence,
        scan: &LaserScan,
        pose: &Pose,
        range_noise: f64,
        rho_min: f64,
        h: f64,
    ) -> Self {
        match kind {
            FreeEvidence::Fan => Self::of_scan(scan, pose, range_noise, rho_min),
            FreeEvidence::Disc => {
                let mut out = Self::none(pose.position());
                let r = free_radius(scan, range_noise, rho_min);
                if r > h {
                    out.disc = r;
                }
                out
            }
        }
    }

    /// Eq. freefan for `scan` taken at `pose`, with the noise bound `ε` and the curvature
    /// prior `ρ_min`. Readings with no information are skipped; a gap of `π` or more between
    /// valid beams leaves its wedge out.
    #[must_use]
    pub fn of_scan(scan: &LaserScan, pose: &Pose, range_noise: f64, rho_min: f64) -> Self {
        let s = pose.position();
        let mut out = Self::none(s);
        let n = scan.ranges.len();
        let valid: Vec<usize> = (0..n)
            .filter(|&i| matches!(scan.reading(i), Reading::Hit(_) | Reading::NoReturn))
            .collect();
        if valid.len() < 2 || rho_min.is_nan() || rho_min <= 0.0 {
            return out;
        }
        let full = scan.full_turn();
        let origin = scan.angle(pose, valid[0]);
        (out.origin, out.full) = (origin, full);
        let pairs = valid.len() - usize::from(!full);
        for k in 0..pairs {
            let (i, j) = (valid[k], valid[(k + 1) % valid.len()]);
            let start = scan.angle(pose, i) - origin;
            // The wrapping wedge ends on the first beam, at 2π.
            let end = if j > i {
                scan.angle(pose, j) - origin
            } else {
                TAU
            };
            let delta = end - start;
            if let Some(w) = wedge(
                s,
                (scan.direction(pose, i), scan.free_until(i, range_noise)),
                (scan.direction(pose, j), scan.free_until(j, range_noise)),
                delta,
                rho_min,
            ) {
                out.wedges.push(Wedge {
                    start,
                    end,
                    first: i,
                    last: j,
                    ..w
                });
            }
        }
        out.edges = out.boundary_edges();
        out
    }

    /// The same with the wall prior's disc (eq. wallgap): its outside is left out too.
    #[must_use]
    pub fn with_wall(mut self, wall: Option<WallPrior>) -> Self {
        self.wall = wall;
        self
    }

    /// The sensor position.
    #[must_use]
    pub fn sensor(&self) -> Vector2<f64> {
        self.s
    }

    /// Whether the free fan holds `x` (open: strictly inside a wedge's chord line, within its
    /// beams; for tests of the claim that no obstacle meets it).
    #[must_use]
    pub fn fan_contains(&self, x: Vector2<f64>) -> bool {
        self.fan_contains_ball(x, 0.0)
    }

    fn fan_contains_ball(&self, x: Vector2<f64>, t: f64) -> bool {
        if self.wedges.is_empty() {
            return false;
        }
        let v = x - self.s;
        let d = v.norm();
        let inside = |w: &Wedge| w.n.dot(&v) + t < w.depth;
        if d <= t {
            // The ball holds the sensor: every wedge, closing the turn.
            return self.closed() && self.wedges.iter().all(inside);
        }
        let half = if t > 0.0 { (t / d).asin() } else { 0.0 };
        let phi = (v.y.atan2(v.x) - self.origin).rem_euclid(TAU);
        let (lo, hi) = (phi - half, phi + half);
        // The span as at most two pieces of [0, 2π): wrap below 0 or above 2π (full turns only).
        let turn = if self.full { TAU } else { f64::INFINITY };
        let mut pieces = vec![(lo.max(0.0), hi.min(turn))];
        if lo < 0.0 {
            if !self.closed() {
                return false;
            }
            pieces.push((lo + TAU, TAU));
        }
        if hi > turn {
            if !self.closed() {
                return false;
            }
            pieces.push((0.0, hi - TAU));
        }
        pieces.iter().all(|&(a, b)| self.covers(a, b, &inside))
    }

    /// Whether the wedges from `a` to `b` (angles from the first valid beam) are adjacent and
    /// each satisfies `ok`.
    fn covers(&self, a: f64, b: f64, ok: &dyn Fn(&Wedge) -> bool) -> bool {
        let k0 = self.wedges.partition_point(|w| w.end < a);
        let mut k = k0;
        while k < self.wedges.len() && self.wedges[k].start <= b {
            let w = &self.wedges[k];
            if (k == k0 && w.start > a) || !ok(w) || (k > k0 && self.wedges[k - 1].last != w.first)
            {
                return false;
            }
            if w.end >= b {
                return true;
            }
            k += 1;
        }
        false
    }

    fn contiguous(&self, from: usize, to: usize) -> bool {
        (from + 1..to).all(|k| self.wedges[k - 1].last == self.wedges[k].first)
    }

    /// Whether the fan closes a full turn with no gap.
    fn closed(&self) -> bool {
        self.full
            && !self.wedges.is_empty()
            && self.contiguous(0, self.wedges.len())
            && self.wedges[0].first == self.wedges[self.wedges.len() - 1].last
    }

    /// The edges of `∂Φ`: every chord, and on each beam the piece between its two wedges'
    /// vertices (from `s` where a wedge has no neighbour).
    fn boundary_edges(&self) -> Vec<(Vector2<f64>, Vector2<f64>)> {
        let m = self.wedges.len();
        let mut edges = Vec::with_capacity(2 * m + 2);
        for (k, w) in self.wedges.iter().enumerate() {
            edges.push((w.a, w.b));
            let next = if k + 1 < m {
                Some(&self.wedges[k + 1])
            } else if self.closed() {
                Some(&self.wedges[0])
            } else {
                None
            };
            match next.filter(|nx| nx.first == w.last) {
                Some(nx) => edges.push((w.b, nx.a)),
                None => edges.push((self.s, w.b)),
            }
            let prev_adjacent = if k > 0 {
                self.wedges[k - 1].last == w.first
            } else {
                self.closed()
            };
            if !prev_adjacent {
                edges.push((self.s, w.a));
            }
        }
        edges
    }

    /// How many wedges the fan has (for reports and tests).
    #[must_use]
    pub fn wedges(&self) -> usize {
        self.wedges.len()
    }
}

/// A set that no obstacle meets, which a fit may leave out of its region `Y` (module docs):
/// one scan's [`FreeSpace`], or the [`FreeUnion`] of the current scan's and remembered ones'.
/// The fit's cover needs two things of it: whether a ball lies in it, and samples of its
/// boundary near the region.
pub trait FreeSet {
    /// Whether the closed ball `B(x, t)` lies in the set. Conservative: `false` when unsure.
    fn contains_ball(&self, x: Vector2<f64>, t: f64) -> bool;

    /// Whether `x` lies beyond the wall prior (eq. wallgap: outside its disc), where no unknown
    /// obstacle is. `false` without one.
    fn beyond_wall(&self, x: Vector2<f64>) -> bool;

    /// Points of the set's boundary at spacing at most `h` along it, within `reach` of `near`,
    /// accepted by `keep`.
    fn boundary_samples(
        &self,
        h: f64,
        near: Vector2<f64>,
        reach: f64,
        keep: &dyn Fn(Vector2<f64>) -> bool,
    ) -> Vec<Vector2<f64>>;
}

impl FreeSet for FreeSpace {
    /// Whether the closed ball `B(x, t)` lies in `R` (module docs): in the free fan (every
    /// wedge over the ball's angular span about `s` holds it strictly inside its chord line,
    /// with no gap between them), in eq. free's disc (`|x − s| + t < ρ_s`), or outside the wall
    /// prior's disc (`|x − c_W| − t > R_W − g_w`).
    /// Conservative: `false` when unsure.
    fn contains_ball(&self, x: Vector2<f64>, t: f64) -> bool {
        self.wall
            .as_ref()
            .is_some_and(|w| w.holds_ball_beyond(x, t))
            || (x - self.s).norm() + t < self.disc
            || self.fan_contains_ball(x, t)
    }

    fn beyond_wall(&self, x: Vector2<f64>) -> bool {
        self.wall
            .as_ref()
            .is_some_and(|w| w.holds_ball_beyond(x, 0.0))
    }

    /// Points of `∂R` (module docs) at spacing at most `h` along it, within `reach` of `near`
    /// (a cheap bound on where the region lies) and accepted by `keep`: the fan's edges, eq.
    /// free's circle and the wall prior's circle.
    fn boundary_samples(
        &self,
        h: f64,
        near: Vector2<f64>,
        reach: f64,
        keep: &dyn Fn(Vector2<f64>) -> bool,
    ) -> Vec<Vector2<f64>> {
        let mut out = Vec::new();
        for &(a, b) in &self.edges {
            if segment_distance(a, b, near) > reach + h {
                continue;
            }
            let steps = (((b - a).norm() / h).ceil() as usize).max(1);
            for j in 0..=steps {
                let x = a + (b - a) * (j as f64 / steps as f64);
                if (x - near).norm() <= reach + h && keep(x) {
                    out.push(x);
                }
            }
        }
        if self.disc > 0.0 {
            let count = ((TAU * self.disc / h).ceil() as usize).max(8);
            out.extend((0..count).filter_map(|j| {
                let th = TAU * j as f64 / count as f64;
                let x = self.s + self.disc * Vector2::new(th.cos(), th.sin());
                ((x - near).norm() <= reach + h && keep(x)).then_some(x)
            }));
        }
        match &self.wall {
            Some(WallPrior::Disc { centre, radius })
                if (near - centre).norm() + reach + h >= *radius =>
            {
                let (centre, radius) = (*centre, *radius);
                let count = ((TAU * radius / h).ceil() as usize).max(8);
                // Only the arc within reach of `near`: the angles about c_W it spans.
                let v = near - centre;
                let dist = v.norm();
                let (mid, half) = if dist > 0.0 && dist > reach + h {
                    let c = ((dist * dist + radius * radius - (reach + h).powi(2))
                        / (2.0 * dist * radius))
                        .clamp(-1.0, 1.0);
                    (v.y.atan2(v.x), c.acos())
                } else {
                    (0.0, PI)
                };
                let step = TAU / count as f64;
                let n = (2.0 * half / step).ceil() as usize + 2;
                for j in 0..=n {
                    let th = mid - half - step + j as f64 * step;
                    let x = centre + radius * Vector2::new(th.cos(), th.sin());
                    if (x - near).norm() <= reach + h && keep(x) {
                        out.push(x);
                    }
                }
            }
            Some(WallPrior::Level { walls, gap }) => {
                out.extend(walls.level_samples(*gap, h, near, reach, keep));
            }
            _ => {}
        }
        out
    }
}

/// The union `R = R_0 ∪ R_1 ∪ … ∪ R_m` of several scans' free sets: the current scan's (with the
/// wall prior) and those of earlier scans the perception remembers
/// ([`crate::Options::free_memory`], docs/maths.md §12.11). Sound in a static world under (A1)
/// for every scan: each `R_s` misses every obstacle, so their union does.
///
/// *The cover* (module docs, with `R` the union). `∂R ⊂ ∪ ∂R_s`, so the samples of every
/// `∂R_s` within `h` of `Y` cover `∂R ∩ Y` at spacing `h`. A ball is reported inside `R` only
/// when one `R_s` holds it (a ball that two of them share is missed, which only keeps more
/// samples). A sample whose ball of radius `h/2` lies in `R` is never needed: a point of
/// `∂(Y \ R)` within `h/2` of it would lie in the open set `R`, not in the closed `Y \ R`.
#[derive(Clone, Copy, Debug)]
pub struct FreeUnion<'a> {
    /// The current scan's free set.
    pub now: &'a FreeSpace,
    /// The remembered scans' free sets.
    pub past: &'a [std::sync::Arc<FreeSpace>],
}

impl FreeUnion<'_> {
    fn members(&self) -> impl Iterator<Item = &FreeSpace> {
        std::iter::once(self.now).chain(self.past.iter().map(AsRef::as_ref))
    }
}

impl FreeSet for FreeUnion<'_> {
    fn contains_ball(&self, x: Vector2<f64>, t: f64) -> bool {
        self.members().any(|m| m.contains_ball(x, t))
    }

    fn beyond_wall(&self, x: Vector2<f64>) -> bool {
        self.now.beyond_wall(x)
    }

    fn boundary_samples(
        &self,
        h: f64,
        near: Vector2<f64>,
        reach: f64,
        keep: &dyn Fn(Vector2<f64>) -> bool,
    ) -> Vec<Vector2<f64>> {
        self.members()
            .flat_map(|m| m.boundary_samples(h, near, reach, keep))
            .collect()
    }
}

/// Eq. sagitta: the largest distance between a chord of length `c` and an arc of curvature
/// radius `≥ ρ` on it that turns by less than `π`, `ρ − √(ρ² − c²/4)`, computed as
/// `(c²/4)/(ρ + √(ρ² − c²/4))` (no cancellation for `c ≪ ρ`). `∞` when `c > 2ρ` (no bound).
#[must_use]
pub fn sagitta(c: f64, rho: f64) -> f64 {
    let q = 0.25 * c * c;
    if c > 2.0 * rho {
        f64::INFINITY
    } else {
        q / (rho + (rho * rho - q).max(0.0).sqrt())
    }
}

/// The radius of a disc about the sensor that the scan shows free (eq. free): every point
/// of an obstacle (a union of discs of radius `ρ_min`, A4) is at least this far from the
/// sensor. `0` unless the scan covers a full turn.
///
/// ```text
/// ρ_s = min over consecutive valid beams i, j (Δ apart) of  f cos(Δ/2) − sag(2 f sin(Δ/2)),
/// f = min(f_i, f_j, 0.999·ρ_min / sin(Δ/2))                                           (eq. free)
/// ```
///
/// (`f_i` = [`LaserScan::free_until`]; a beam with no information is skipped, which widens
/// `Δ`.) *Why.* The beams `[s, s + f u_i]`, `[s, s + f u_j]` are free (A1), and the chord
/// between their ends is `c = 2f sin(Δ/2) < 2ρ_min` long. A disc of radius `ρ_min` of the
/// obstacle that reached into the triangle `(s, s + f u_i, s + f u_j)` meets neither beam nor
/// `s`, cannot lie inside it (its inradius is below `c/2 < ρ_min`), so it crosses the chord, and
/// the part of it inside lies within `sag(c)` of the chord's line, which is `f cos(Δ/2)` from
/// `s`.
#[must_use]
pub fn free_radius(scan: &LaserScan, range_noise: f64, rho_min: f64) -> f64 {
    if !scan.full_turn() {
        return 0.0;
    }
    let n = scan.ranges.len();
    let valid: Vec<usize> = (0..n)
        .filter(|&i| matches!(scan.reading(i), Reading::Hit(_) | Reading::NoReturn))
        .collect();
    if valid.len() < 3 {
        return 0.0;
    }
    let mut radius = f64::INFINITY;
    for (k, &i) in valid.iter().enumerate() {
        let j = valid[(k + 1) % valid.len()];
        let gap = (j + n - i) % n;
        let delta = gap as f64 * scan.angle_increment;
        if delta >= 0.5 * PI {
            return 0.0;
        }
        let half = (0.5 * delta).sin();
        let f = scan
            .free_until(i, range_noise)
            .min(scan.free_until(j, range_noise))
            .min(0.999 * rho_min / half);
        let reach = f * (0.5 * delta).cos() - sagitta(2.0 * f * half, rho_min);
        radius = radius.min(reach);
    }
    radius.max(0.0)
}

/// Eq. freefan for one pair of beams `(u_i, f_i)`, `(u_j, f_j)` `Δ` apart: of the shortenings
/// that bring the chord below `C = 1.998ρ_min` (both beams as they are; the longer cut to five
/// lengths between the shorter's `m` and `m cos Δ + √(C² − m² sin² Δ)`; both at
/// `min(m, C/(2 sin(Δ/2)))`), the wedge of largest area, or `None` when all are empty or
/// `Δ ≥ π`. A shortened beam is still free, so every candidate is sound.
fn wedge(
    s: Vector2<f64>,
    (ui, fi): (Vector2<f64>, f64),
    (uj, fj): (Vector2<f64>, f64),
    delta: f64,
    rho: f64,
) -> Option<Wedge> {
    if !(delta > 0.0 && delta < PI && fi > 0.0 && fj > 0.0) {
        return None;
    }
    let cap = 2.0 * CHORD_FRACTION * rho;
    let m = fi.min(fj);
    let mut candidates = vec![(fi, fj)];
    if m * delta.sin() < cap {
        let t = m * delta.cos() + (cap * cap - (m * delta.sin()).powi(2)).sqrt();
        for k in 0..=4 {
            let long = (m + (t - m) * f64::from(k) / 4.0).min(fi.max(fj));
            candidates.push(if fi <= fj { (fi, long) } else { (long, fj) });
        }
    }
    let f = m.min(CHORD_FRACTION * cap / (2.0 * (0.5 * delta).sin()));
    candidates.push((f, f));
    candidates
        .into_iter()
        .filter_map(|(fi, fj)| triangle(s, (ui, fi), (uj, fj), rho, cap))
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(w, _)| w)
}

/// The wedge of eq. freefan for beams free to `f_i`, `f_j` (the chord must be below `cap`),
/// with its area, or `None` when it is empty.
fn triangle(
    s: Vector2<f64>,
    (ui, fi): (Vector2<f64>, f64),
    (uj, fj): (Vector2<f64>, f64),
    rho: f64,
    cap: f64,
) -> Option<(Wedge, f64)> {
    let (a, b) = (s + fi * ui, s + fj * uj);
    let chord = b - a;
    let c = chord.norm();
    if !(c > 0.0 && c < cap) {
        return None;
    }
    let mut n = Vector2::new(chord.y, -chord.x) / c;
    if n.dot(&(a - s)) < 0.0 {
        n = -n;
    }
    let height = n.dot(&(a - s));
    let depth = height - sagitta(c, rho);
    if !(depth > 0.0 && depth.is_finite()) {
        return None;
    }
    let lambda = depth / height;
    let area = 0.5 * lambda * lambda * fi * fj * (ui.x * uj.y - ui.y * uj.x).abs();
    Some((
        Wedge {
            start: 0.0,
            end: 0.0,
            first: 0,
            last: 0,
            a: s + lambda * fi * ui,
            b: s + lambda * fj * uj,
            n,
            depth,
        },
        area,
    ))
}

/// The distance from `x` to the segment `[a, b]` (a point when `a = b`).
pub(crate) fn segment_distance(a: Vector2<f64>, b: Vector2<f64>, x: Vector2<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((x - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + t * ab - x).norm()
}
