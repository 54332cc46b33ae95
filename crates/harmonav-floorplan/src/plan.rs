//! [`FloorMap`]: the static floor plan (walls), its harmonic map `H` onto the punctured disk,
//! and the certified region `W_δ` in which navigation is claimed.

use harmonav_harmonic::{
    Certificate, CertifyError, CertifyOptions, Domain, DomainError, Enclosure, EvalError,
    HarmonicMap, MeshOptions, RingId, SolveError, certify,
};
use harmonav_transform::Shown;
use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::{Polyline, Segment};
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Why a floor plan could not be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FloorError {
    /// The rings do not form a valid polygon with holes (the problem is named).
    Domain(DomainError),
    /// The boundary-element solve failed (too many elements, or a singular system).
    Solve(SolveError),
    /// An option is out of range (`field` names it).
    InvalidOption {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The goal is not in the certified region `W_δ` (closer than `δ` to a wall, or outside).
    GoalNotCertified {
        /// Its signed distance to the walls (positive inside).
        clearance: f64,
        /// `δ`.
        delta: f64,
    },
    /// A sensed obstacle reaches into the boundary layer (closer than `δ` to `∂W_s`,
    /// [`FloorMap::star_room`]): it is not inside `W_δ`.
    ObstacleNearWall {
        /// The sensed obstacle (its index in the order added).
        obstacle: usize,
    },
    /// A sensed obstacle overlaps or touches another sensed obstacle.
    Overlap {
        /// The earlier obstacle.
        first: usize,
        /// The later one.
        second: usize,
    },
    /// The walls shrunk by `radius + margin − δ` are not a valid polygon with holes: a passage
    /// narrower than the robot, a hole that comes to touch a wall, or an edge too short.
    TooNarrow {
        /// The ring (as given) where it showed.
        ring: RingId,
        /// What went wrong.
        problem: String,
    },
    /// A sensed obstacle contains the goal.
    ContainsGoal {
        /// The obstacle.
        obstacle: usize,
    },
    /// The point world could not be formed (two points coincide in the disk, to rounding).
    Potential(harmonav_potential::PotentialError),
    /// The goal maps outside the disk or onto a puncture (a map that failed there).
    Map(harmonav_harmonic::EvalError),
    /// A point of the point world (a puncture, a sensed centre's or the goal's image) lies on
    /// or beyond the unit circle: a map that failed there.
    PointOnCircle,
    /// Obstacles joined to the walls ([`FloorMap::carved`]) would leave `what` (`"goal"` or
    /// `"robot"`) outside the free space that is left (behind them, or inside one).
    CutOff {
        /// What is cut off.
        what: &'static str,
    },
    /// More sensed obstacles would join the walls than a caller allows (each join solves `H`
    /// again).
    TooManyJoined {
        /// How many would.
        count: usize,
        /// The most allowed.
        max: usize,
    },
}

impl std::fmt::Display for FloorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Domain(e) => write!(f, "the floor plan: {e}"),
            Self::Solve(e) => write!(f, "the harmonic map: {e}"),
            // `max_element` is a length; the clearance, the valley radius and the
            // simplification may be 0.
            Self::InvalidOption {
                field: field @ "max_element",
                value,
            } => write!(f, "`{field}` must be finite and positive, got {value:e}"),
            Self::InvalidOption { field, value } => {
                write!(f, "`{field}` must be finite and ≥ 0, got {value:e}")
            }
            Self::GoalNotCertified { clearance, delta } => write!(
                f,
                "the goal is {:.4} m from the walls, not in the certified region \
                 (at least δ = {:.4} m from every wall)",
                Shown(*clearance),
                Shown(*delta)
            ),
            Self::ObstacleNearWall { obstacle } => write!(
                f,
                "sensed obstacle {obstacle} reaches within δ of a wall (it leaves the certified \
                 region)"
            ),
            Self::Overlap { first, second } => {
                write!(f, "sensed obstacles {first} and {second} overlap")
            }
            Self::TooNarrow { ring, problem } => write!(
                f,
                "the free space shrunk by radius + margin − δ is not a valid floor plan at {ring} \
                 (a passage narrower than the robot?): {problem}"
            ),
            Self::ContainsGoal { obstacle } => {
                write!(f, "sensed obstacle {obstacle} contains the goal")
            }
            Self::Potential(e) => write!(f, "the point world: {e}"),
            Self::Map(e) => write!(f, "the harmonic map at the goal: {e}"),
            Self::PointOnCircle => write!(
                f,
                "a point of the point world maps onto or beyond the unit circle"
            ),
            Self::TooManyJoined { count, max } => write!(
                f,
                "{count} sensed obstacles would join the walls; at most {max} may (each join \
                 solves the harmonic map again)"
            ),
            Self::CutOff { what } => write!(
                f,
                "a sensed obstacle reaches the walls and would join them, but the {what} would \
                 then be cut off from the free space (behind the obstacle or in it)"
            ),
        }
    }
}

impl std::error::Error for FloorError {}

impl From<DomainError> for FloorError {
    fn from(e: DomainError) -> Self {
        Self::Domain(e)
    }
}

impl From<SolveError> for FloorError {
    fn from(e: SolveError) -> Self {
        Self::Solve(e)
    }
}

impl From<harmonav_potential::PotentialError> for FloorError {
    fn from(e: harmonav_potential::PotentialError) -> Self {
        Self::Potential(e)
    }
}

/// Where the goal's image lies in the disk (`[floor_plan] centre`, docs/maths.md §13.2).
///
/// - `"solve"` (the default): `H(x_d)` where the solve puts it, `Phi = S ∘ H ∘ B`.
/// - `"goal"`: recentred by the disk automorphism `M_a(w) = (w − a)/(1 − ā w)`, `a = H(x_d)`,
///   so that `M_a(H(x_d)) = 0`: `Phi = S ∘ M_a ∘ H ∘ B`. `M_a` is a conformal diffeomorphism of
///   the open disk onto itself, so `M_a ∘ H` is a diffeomorphism wherever `H` is, with
///   `det J = |M_a'|² det J_H` and `|M_a(w)| < 1 ⇔ |w| < 1`: the certificate of `H` carries over
///   unchanged. Serpentine plans without holes (the maze of `scenarios/floorplans/`) arrive
///   under it and not under `"solve"`; plans with holes far from the goal do worse (measured in
///   §13.2), so it is not the default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CentrePolicy {
    /// `H(x_d)` as solved.
    #[default]
    Solve,
    /// `M_a ∘ H` with `a = H(x_d)`: the goal at the disk's centre.
    Goal,
}

harmonav_potential::named_policy!(
    CentrePolicy,
    UnknownCentrePolicy,
    "disk centre policy",
    [Solve => "solve", Goal => "goal"]
);

/// The component of a floor plan's certified region that holds the goal
/// ([`FloorMap::reach`]).
#[derive(Clone, Debug)]
pub struct Reach(Option<geo::Polygon<f64>>);

impl Reach {
    /// Whether `p` lies in it: a robot there can reach the goal within `W_δ`.
    #[must_use]
    pub fn contains(&self, p: Vector2<f64>) -> bool {
        use geo::Contains;
        self.0
            .as_ref()
            .is_some_and(|part| part.contains(&geo::Point::new(p.x, p.y)))
    }
}

/// Options of [`FloorMap::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorOptions {
    /// Largest boundary element `h` (m), graded toward corners ([`MeshOptions::graded`]).
    pub max_element: f64,
    /// The clearance the robot keeps from every wall: `radius + margin` (m, ≥ 0).
    pub clearance: f64,
    /// Where the goal's image lies in the disk ([`CentrePolicy`]).
    pub centre: CentrePolicy,
}

impl FloorOptions {
    /// Elements of at most `max_element`, the clearance `radius + margin`, and the goal's image
    /// where the solve puts it ([`CentrePolicy::Solve`]).
    #[must_use]
    pub fn new(max_element: f64, clearance: f64) -> Self {
        Self {
            max_element,
            clearance,
            centre: CentrePolicy::Solve,
        }
    }

    /// The same options with the centre policy `centre`.
    #[must_use]
    pub fn with_centre(mut self, centre: CentrePolicy) -> Self {
        self.centre = centre;
        self
    }
}

/// Twice the signed area of a ring (positive counter-clockwise).
fn twice_area(ring: &[Vector2<f64>]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum()
}

/// The ring in the orientation `ccw` (reversed if it has the other one).
pub(crate) fn oriented(mut ring: Vec<Vector2<f64>>, ccw: bool) -> Vec<Vector2<f64>> {
    if (twice_area(&ring) > 0.0) != ccw {
        ring.reverse();
    }
    ring
}

/// A floor plan with its harmonic map: the true walls (an outer polygon and polygonal holes of
/// any shape: U, L, walls on the outer ring); the free space `W_s`, the walls shrunk by
/// `s = max(radius + margin − δ, 0)` (mitred offsets, arcs circumscribed: inside the true
/// erosion); `H` of `W_s`, solved once (docs/maths.md §11); and the certified region
///
/// ```text
/// W_δ = { x : sd(x) ≥ δ },   δ = h (the largest element asked for, ≥ h_max)
/// ```
///
/// with `sd` the signed distance to `∂W_s`. So `W_δ` is the robot's configuration space with
/// its margin (the erosion by `s + δ = radius + margin`), and the walls' barrier (`Θ → 1`) is on
/// `∂W_s`, only `δ` beyond it. When `radius + margin < δ` the robot keeps `δ` from the walls
/// instead, and [`FloorMap::keeps_delta`] says so.
#[derive(Clone, Debug)]
pub struct FloorMap {
    map: HarmonicMap,
    /// Every wall segment (all rings), for parry's distance queries.
    /// The true walls (as given, validated).
    truth: Domain,
    walls: Polyline,
    /// The boundary of the shrunk free space `W_s` on which `H` is built.
    boundary: Polyline,
    delta: f64,
    shrink: f64,
    clearance: f64,
    /// Samples of the edge `∂W_δ = {sd = δ}` of the certified region ([`FloorMap::layer_edge`]).
    edge: Vec<Vector2<f64>>,
    /// `H` at the edge samples where it could be evaluated (`S`'s band after a recentring,
    /// [`crate::FloorTransform`]).
    edge_images: Vec<Vector2<f64>>,
    centre: CentrePolicy,
    /// `H`'s enclosures of discs, remembered while a [`FloorMap::remember_enclosures`] guard
    /// lives.
    memo: Memo,
}

/// `H`'s enclosures of discs by the bits of `(x, y, ρ)`, kept while `users > 0` (a chain of
/// funnels certifies each of its goals over the same cells of `∂W_δ`, and the enclosure of `H`
/// over a cell does not depend on the goal). A clone, and a map whose `H` changes, start empty.
#[derive(Debug, Default)]
struct Memo {
    users: AtomicUsize,
    table: Mutex<HashMap<[u64; 3], Enclosure>>,
}

impl Clone for Memo {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// While it lives, [`FloorMap::enclosure`] remembers what it computed
/// ([`FloorMap::remember_enclosures`]); the last guard dropped forgets it.
#[derive(Debug)]
pub struct RememberEnclosures<'a>(&'a FloorMap);

impl Drop for RememberEnclosures<'_> {
    fn drop(&mut self) {
        if self.0.memo.users.fetch_sub(1, Ordering::SeqCst) == 1
            && let Ok(mut table) = self.0.memo.table.lock()
        {
            table.clear();
        }
    }
}

/// The rings of a domain, outer first.
pub(crate) fn rings(d: &Domain) -> impl Iterator<Item = &[Vector2<f64>]> {
    std::iter::once(d.outer()).chain(d.holes().iter().map(Vec::as_slice))
}

/// Every edge of every ring, for parry.
fn polyline(d: &Domain) -> Polyline {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for ring in rings(d) {
        let base = vertices.len() as u32;
        let n = ring.len() as u32;
        vertices.extend(ring.iter().map(|p| PVector::new(p.x, p.y)));
        indices.extend((0..n).map(|i| [base + i, base + (i + 1) % n]));
    }
    Polyline::new(vertices, Some(indices))
}

/// Beyond [`FAR`] (m) from the origin, `(a − x, |a − x|)` for a vertex `a` of `walls`: the
/// offset to the walls and its length, the distance.
///
/// parry's point queries square the coordinates, so beyond about 1e154 m they overflow (a
/// distance of `∞`, or a projection at `x` itself, so 0 and no direction). Every wall lies
/// within `MAX_COORDINATE` (1e9 m) of the origin, so from `|x|_∞ > FAR` every wall point is
/// `|x − a|` away, in the direction of `a − x`, to a relative `2·1e9/FAR` (below rounding);
/// `hypot` does not overflow.
fn far_offset(walls: &Polyline, x: Vector2<f64>) -> Option<(Vector2<f64>, f64)> {
    let a = walls.vertices().first()?;
    (x.x.abs().max(x.y.abs()) > FAR).then(|| {
        let d = Vector2::new(a.x - x.x, a.y - x.y);
        (d, d.x.hypot(d.y))
    })
}

/// Where [`far_offset`] takes over from parry's queries, m: far below their overflow and far
/// enough that every wall is equally far to rounding.
const FAR: f64 = 1e30;

/// The most a circumscribed arc piece turns (rad).
const ARC_STEP: f64 = std::f64::consts::PI / 8.0;

/// A ring (free side on the left of every edge: the outer ring counter-clockwise, a hole
/// clockwise) moved by `s > 0` into the free space: every edge along its left normal `n_i`;
/// at a left turn (a convex corner of the free space) the two offset edges meet at the mitre
/// `a + s(n₁ + n₂)/(1 + n₁·n₂)`, exactly the erosion's corner; at a right turn (a wall's convex
/// corner, where the erosion has an arc of radius `s`) the arc is replaced by its circumscribed
/// polyline (pieces of at most [`ARC_STEP`], corners at `s/cos(Δ/2)`), which lies outside the
/// arc: the result is inside the true erosion, so it is conservative. `None` when an offset
/// edge turns back (a feature thinner than `s`); crossings are left to `Domain::new`.
/// The ring a shrunk plan's [`DomainError`] shows at (the first it names; the outer ring when
/// it names none). Before issue 52 every such error said "at the outer ring", also for "the
/// boundaries of hole 37 and hole 38 cross or touch".
fn shrunk_ring(e: &DomainError) -> RingId {
    match e {
        DomainError::TooFewVertices { ring, .. }
        | DomainError::NonFinite { ring, .. }
        | DomainError::TooLarge { ring, .. }
        | DomainError::DegenerateEdge { ring, .. }
        | DomainError::SelfIntersecting { ring, .. }
        | DomainError::WrongOrientation { ring, .. } => *ring,
        DomainError::RingsMeet { first, .. } => *first,
        DomainError::HoleOutside { hole } => RingId::Hole(*hole),
        DomainError::HoleInHole { inner, .. } => RingId::Hole(*inner),
        _ => RingId::Outer,
    }
}

fn offset_ring(ring: &[Vector2<f64>], s: f64) -> Option<Vec<Vector2<f64>>> {
    let n = ring.len();
    let dir = |i: usize| {
        let e = ring[(i + 1) % n] - ring[i];
        e / e.norm()
    };
    let left = |d: Vector2<f64>| Vector2::new(-d.y, d.x);
    let mut out = Vec::with_capacity(2 * n);
    // For each edge, the first and last offset points it contributes (to check its direction).
    let mut ends = vec![(None, None); n];
    for i in 0..n {
        let prev = (i + n - 1) % n;
        let (d0, d1) = (dir(prev), dir(i));
        let (n0, n1) = (left(d0), left(d1));
        let a = ring[i];
        let turn = d0.x * d1.y - d0.y * d1.x;
        let cos = d0.dot(&d1);
        if turn > 1e-12 || (turn.abs() <= 1e-12 && cos > 0.0) {
            let m = a + s * (n0 + n1) / (1.0 + n0.dot(&n1));
            ends[prev].1 = Some(out.len());
            ends[i].0 = Some(out.len());
            out.push(m);
        } else {
            // Right turn (or a full reversal): the arc from n0 to n1, clockwise.
            let sweep = -(turn.atan2(cos)); // in (0, π]
            let pieces = (sweep / ARC_STEP).ceil().max(1.0) as usize;
            let step = sweep / pieces as f64;
            let start = n0.y.atan2(n0.x);
            ends[prev].1 = Some(out.len());
            out.push(a + s * n0);
            for j in 0..pieces {
                let t = start - (j as f64 + 0.5) * step;
                out.push(a + (s / (0.5 * step).cos()) * Vector2::new(t.cos(), t.sin()));
            }
            ends[i].0 = Some(out.len());
            out.push(a + s * n1);
        }
    }
    for (i, &(first, last)) in ends.iter().enumerate() {
        let (first, last) = (first?, last?);
        if (out[last] - out[first]).dot(&dir(i)) <= 0.0 {
            return None;
        }
    }
    Some(out)
}

/// Spacing of the samples of `∂W_δ`, in units of `δ`.
pub const EDGE_SPACING: f64 = 0.25;

/// Samples of `∂W_δ = {sd = δ}` about `EDGE_SPACING·δ` apart: every wall edge moved by `δ` along
/// its normal into the free space, and the arcs of radius `δ` about every vertex, kept where
/// `sd = δ` to rounding (elsewhere another wall is nearer).
fn layer_edge(
    domain: &Domain,
    walls: &Polyline,
    delta: f64,
    outer_only: bool,
) -> Vec<Vector2<f64>> {
    let step = EDGE_SPACING * delta;
    let mut candidates = Vec::new();
    let mut keep = |p: Vector2<f64>| candidates.push(p);
    for ring in rings(domain).take(if outer_only { 1 } else { usize::MAX }) {
        let n = ring.len();
        for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            let e = b - a;
            let len = e.norm();
            // Outer ring counter-clockwise, holes clockwise: the free side is on the left.
            let normal = Vector2::new(-e.y, e.x) / len;
            let m = (len / step).ceil().max(1.0) as usize;
            for j in 0..=m {
                keep(a + e * (j as f64 / m as f64) + delta * normal);
            }
            let arcs = (std::f64::consts::TAU * delta / step).ceil() as usize;
            for j in 0..arcs {
                let t = std::f64::consts::TAU * j as f64 / arcs as f64;
                keep(a + delta * Vector2::new(t.cos(), t.sin()));
            }
        }
    }
    // About 70 000 samples on a 60 m floor, each a wall query and a containment test.
    crate::halves::filter_map(&candidates, |&p| {
        let d = walls.distance_to_local_point(PVector::new(p.x, p.y), false);
        ((d - delta).abs() <= 1e-9 * delta.max(1.0) && domain.contains(p)).then_some(p)
    })
}

impl FloorMap {
    /// Validates the rings (either orientation is accepted: the outer ring is made
    /// counter-clockwise and the holes clockwise), shrinks them by `s = max(clearance − δ, 0)`,
    /// `δ = max_element`, and meshes and solves `H` on the result (one LU, `O((N + M)³)`).
    ///
    /// # Errors
    /// [`FloorError::InvalidOption`] for a non-positive or non-finite `max_element` or a
    /// negative `clearance`; [`FloorError::Domain`] for invalid rings (self-crossing, holes
    /// outside or touching, …); [`FloorError::TooNarrow`] when the shrunk rings are not valid
    /// (a passage narrower than the robot); [`FloorError::Solve`] when the solve fails.
    pub fn new(
        outer: Vec<Vector2<f64>>,
        holes: Vec<Vec<Vector2<f64>>>,
        options: &FloorOptions,
    ) -> Result<Self, FloorError> {
        let h = options.max_element;
        if !(h.is_finite() && h > 0.0) {
            return Err(FloorError::InvalidOption {
                field: "max_element",
                value: h,
            });
        }
        let c = options.clearance;
        if !(c.is_finite() && c >= 0.0) {
            return Err(FloorError::InvalidOption {
                field: "clearance",
                value: c,
            });
        }
        let outer = oriented(outer, true);
        let holes: Vec<_> = holes.into_iter().map(|r| oriented(r, false)).collect();
        let truth = Domain::new(outer, holes)?;
        // δ = h ≥ h_max: the layer of the discrete map. The free space is shrunk by the rest of
        // the clearance, so that W_δ is the configuration space with its margin.
        let delta = h;
        let shrink = (c - delta).max(0.0);
        let domain = if shrink > 0.0 {
            let rings: Vec<Vec<Vector2<f64>>> = rings(&truth)
                .enumerate()
                .map(|(i, r)| {
                    offset_ring(r, shrink).ok_or(FloorError::TooNarrow {
                        ring: if i == 0 {
                            RingId::Outer
                        } else {
                            RingId::Hole(i - 1)
                        },
                        problem: "an edge vanishes or turns back".into(),
                    })
                })
                .collect::<Result<_, _>>()?;
            let mut rings = rings.into_iter();
            let outer = rings.next().unwrap_or_default();
            Domain::new(outer, rings.collect()).map_err(|e| match e {
                // A size cap is not a narrow passage: say which cap, with its count.
                DomainError::TooManyVertices { .. } | DomainError::TooManyHoles { .. } => {
                    FloorError::Domain(e)
                }
                e => FloorError::TooNarrow {
                    ring: shrunk_ring(&e),
                    problem: e.to_string(),
                },
            })?
        } else {
            truth.clone()
        };
        Self::solved(truth, &domain, delta, shrink, c, options.centre)
    }

    /// The floor whose true walls are `truth` and whose shrunk free space `W_s` is `domain`
    /// (`truth` shrunk by `shrink`, less any cut, [`FloorMap::carved`]): `H` meshed at `δ` and
    /// solved on `domain`, the edge of the certified region and its images.
    pub(crate) fn solved(
        truth: Domain,
        domain: &Domain,
        delta: f64,
        shrink: f64,
        clearance: f64,
        centre: CentrePolicy,
    ) -> Result<Self, FloorError> {
        let map = HarmonicMap::new(domain, &MeshOptions::graded(delta))?;
        let walls = polyline(&truth);
        let boundary = polyline(domain);
        let edge = layer_edge(map.domain(), &boundary, delta, false);
        // Over every ring: near a hole the layer maps next to its puncture (the U's pocket
        // squeezes it to 2e-4), which widens S's band to MAX_BAND. Measured: taking r_δ along
        // the outer ring alone narrowed the band and the L room's far starts stalled.
        let edge_images = crate::halves::filter_map(&edge, |&p| map.eval(p).ok().map(|e| e.value));
        Ok(Self {
            map,
            truth,
            walls,
            boundary,
            delta,
            shrink,
            clearance,
            edge,
            edge_images,
            centre,
            memo: Memo::default(),
        })
    }

    /// The same floor with `H`'s far field of tolerance `tol` (`Some`) or without one
    /// (`None`: the direct `O(N)` sum), as [`HarmonicMap::with_far_field`]; [`FloorMap::new`]
    /// leaves [`HarmonicMap::new`]'s choice (the far field from
    /// [`harmonav_harmonic::FAR_FIELD_MIN_ELEMENTS`] elements). `H` itself is unchanged (the two
    /// paths agree to about 1e-14, docs/maths.md §11), and so are `δ` and `r_δ`.
    ///
    /// # Errors
    /// [`FloorError::Solve`] for a tolerance outside `[1e-15, 1e-2]`.
    pub fn with_far_field(mut self, tolerance: Option<f64>) -> Result<Self, FloorError> {
        self.map = self.map.with_far_field(tolerance)?;
        self.memo = Memo::default();
        Ok(self)
    }

    /// `H`'s enclosure of the disc `B(x, ρ)` ([`HarmonicMap::enclosure`]), remembered while a
    /// guard of [`FloorMap::remember_enclosures`] lives: the same value either way (a pure
    /// function of `x`, `ρ` and `H`), computed once per disc.
    ///
    /// # Errors
    /// As [`HarmonicMap::enclosure`].
    pub fn enclosure(&self, x: Vector2<f64>, rho: f64) -> Result<Enclosure, EvalError> {
        if self.memo.users.load(Ordering::SeqCst) == 0 {
            return self.map.enclosure(x, rho);
        }
        let key = [x.x.to_bits(), x.y.to_bits(), rho.to_bits()];
        if let Some(e) = self
            .memo
            .table
            .lock()
            .ok()
            .and_then(|t| t.get(&key).copied())
        {
            return Ok(e);
        }
        let e = self.map.enclosure(x, rho)?;
        if let Ok(mut table) = self.memo.table.lock() {
            table.insert(key, e);
        }
        Ok(e)
    }

    /// Remember `H`'s enclosures ([`FloorMap::enclosure`]) until the guard is dropped: for
    /// certifying many goals over one map ([`crate::FloorField::funnels`]). About 100 bytes a
    /// disc.
    #[must_use]
    pub fn remember_enclosures(&self) -> RememberEnclosures<'_> {
        self.memo.users.fetch_add(1, Ordering::SeqCst);
        RememberEnclosures(self)
    }

    /// The harmonic map `H`.
    #[must_use]
    pub fn map(&self) -> &HarmonicMap {
        &self.map
    }

    /// The free space `W_s` on which `H` is built: the walls shrunk by
    /// [`FloorMap::shrink`].
    #[must_use]
    pub fn domain(&self) -> &Domain {
        self.map.domain()
    }

    /// The true walls, as given (validated, oriented).
    #[must_use]
    pub fn walls(&self) -> &Domain {
        &self.truth
    }

    /// The component of the certified region `W_δ` that holds `goal` ([`Reach`]): the true
    /// walls eroded by `ρ = s + δ = max(radius + margin, δ)` (geo's buffer with round joins, as
    /// a map's opening, `RosMap::free_space`). A passage narrower than the robot with its
    /// margin cuts `W_δ`: a start may be certified and yet unable to reach the goal. `ρ` is
    /// taken `10⁻⁶` smaller, so that the buffer's polygonal arcs do not close a passage as
    /// wide as the robot.
    #[must_use]
    pub fn reach(&self, goal: Vector2<f64>) -> Reach {
        use geo::{Buffer, Contains, LineString, Point, Polygon};
        let ring = |r: &[Vector2<f64>]| {
            LineString::from(
                r.iter()
                    .chain(r.first())
                    .map(|p| (p.x, p.y))
                    .collect::<Vec<_>>(),
            )
        };
        let walls = Polygon::new(
            ring(self.truth.outer()),
            self.truth.holes().iter().map(|h| ring(h)).collect(),
        );
        let rho = (self.shrink + self.delta) * (1.0 - 1e-6);
        let g = Point::new(goal.x, goal.y);
        Reach(
            walls
                .buffer(-rho)
                .0
                .into_iter()
                .find(|part| part.contains(&g)),
        )
    }

    /// `δ = h` (the largest element asked for, `≥ h_max`): the certified region is
    /// `W_δ = {sd ≥ δ}`, `sd` the signed distance to `∂W_s`.
    #[must_use]
    pub fn delta(&self) -> f64 {
        self.delta
    }

    /// `∂W_s`, the walls shrunk by `s` (parry), whose distance is `sd`.
    pub(crate) fn shrunk_boundary(&self) -> &Polyline {
        &self.boundary
    }

    /// `s = max(radius + margin − δ, 0)`: how far the walls were shrunk to give `W_s`.
    #[must_use]
    pub fn shrink(&self) -> f64 {
        self.shrink
    }

    /// `v` moved onto `∂W_s` when it lies within `snap` of it: onto the nearer end of the
    /// nearest edge when that end is within `snap` too (then `true`: one of `∂W_s`'s own
    /// vertices), else onto the edge; `v` otherwise. ([`FloorMap::carved`]: geo's polygon
    /// difference rounds its vertices to about 1e-9 of the plan's size, which would move walls
    /// outwards.)
    pub(crate) fn snapped(&self, v: Vector2<f64>, snap: f64) -> (Vector2<f64>, bool) {
        let (proj, _) = self
            .boundary
            .project_local_point_and_get_feature(PVector::new(v.x, v.y));
        let on = Vector2::new(proj.point.x, proj.point.y);
        let gap = (on - v).norm();
        if gap.is_nan() || gap > snap {
            return (v, false);
        }
        let edge = self.boundary.segment(proj.subshape);
        let (a, b) = (
            Vector2::new(edge.a.x, edge.a.y),
            Vector2::new(edge.b.x, edge.b.y),
        );
        // The nearer end: on an edge shorter than `snap` both ends are within it.
        let end = if (a - v).norm() <= (b - v).norm() {
            a
        } else {
            b
        };
        if (end - v).norm() <= snap {
            (end, true)
        } else {
            (on, false)
        }
    }

    /// The clearance the floor was asked to keep (`radius + margin`, [`FloorOptions::new`]).
    pub(crate) fn clearance_asked(&self) -> f64 {
        self.clearance
    }

    /// `true` when `radius + margin < δ`: the robot keeps the larger `δ` from the walls (the
    /// discrete map is only claimed a diffeomorphism there).
    #[must_use]
    pub fn keeps_delta(&self) -> bool {
        self.clearance < self.delta
    }

    /// Samples of the edge `∂W_δ` of the certified region, [`EDGE_SPACING`]`·δ` apart (the
    /// wall edges moved by `δ` into the free space and the arcs about the vertices), where
    /// `c_δ` is sampled and its certified bound refined
    /// ([`crate::FloorField::certify_layer_level`]).
    #[must_use]
    pub fn layer_edge(&self) -> &[Vector2<f64>] {
        &self.edge
    }

    /// `min |H|` over [`FloorMap::layer_edge`]: `r_δ` of `S`'s band when the goal is not
    /// recentred ([`CentrePolicy::Solve`]; under [`CentrePolicy::Goal`] the transform takes
    /// `min |M_a(H)|` over [`FloorMap::edge_images`] instead). The stretch `S` starts inside it,
    /// so the walls' barrier is already steep at `∂W_δ` (`docs/maths.md` §13).
    #[must_use]
    pub fn edge_radius(&self) -> f64 {
        self.edge_images
            .iter()
            .map(|w| w.norm())
            .fold(1.0, f64::min)
    }

    /// `H` at the samples of [`FloorMap::layer_edge`] (those where it could be evaluated).
    #[must_use]
    pub fn edge_images(&self) -> &[Vector2<f64>] {
        &self.edge_images
    }

    /// Where the goal's image lies in the disk ([`CentrePolicy`]).
    #[must_use]
    pub fn centre_policy(&self) -> CentrePolicy {
        self.centre
    }

    /// The distance from `x` to the nearest wall (parry's point query on the wall segments),
    /// exact to rounding.
    #[must_use]
    pub fn wall_distance(&self, x: Vector2<f64>) -> f64 {
        if let Some((_, d)) = far_offset(&self.walls, x) {
            return d;
        }
        self.walls
            .distance_to_local_point(PVector::new(x.x, x.y), false)
    }

    /// The signed distance `sd(x)` to `∂W_s` (the shrunk walls, parry): positive in `W_s`,
    /// negative outside it. 1-Lipschitz.
    #[must_use]
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        if let Some((_, d)) = far_offset(&self.boundary, x) {
            return -d;
        }
        let d = self
            .boundary
            .distance_to_local_point(PVector::new(x.x, x.y), false);
        if self.domain().contains(x) { d } else { -d }
    }

    /// The unit vector from `x` to the nearest point of `∂W_s` (parry's projection), `−∇sd`
    /// inside `W_s`; `None` on the boundary itself.
    #[must_use]
    pub fn toward_boundary(&self, x: Vector2<f64>) -> Option<Vector2<f64>> {
        if let Some((d, norm)) = far_offset(&self.boundary, x) {
            return (norm > 0.0 && norm.is_finite()).then(|| d / norm);
        }
        let p = self
            .boundary
            .project_local_point(PVector::new(x.x, x.y), false)
            .point;
        let d = Vector2::new(p.x - x.x, p.y - x.y);
        let norm = d.norm();
        (norm > 0.0 && norm.is_finite()).then(|| d / norm)
    }

    /// A certified lower bound on how far the star `shape` stays from the boundary layer, m:
    /// `D − δ − h_s/2`, `D` the least certified distance (`StarShape::signed_distance_bounds`'s
    /// lower bound) from `shape` to the points of `∂W_s` sampled at spacing `h_s = δ/8` (each
    /// point of `∂W_s` lies within `h_s/2` of a sample, and the distance to `shape` is
    /// 1-Lipschitz); negative when it reaches the layer, holds a piece of `∂W_s`, or its centre
    /// is not in `W_δ`. Only the edges within `R_max + sd(c)` of the centre `c` are sampled
    /// (the nearest point of `∂W_s` to `c` is `sd(c)` from `c ∈ shape`, and an edge farther
    /// than that plus `R_max` is farther from `shape` than it).
    ///
    /// *Why it suffices* (docs/maths.md §12.17). When it is positive, `shape` is connected, holds
    /// `c ∈ W_s` and meets no point of `∂W_s`, so it lies in `W_s`, and each of its points is
    /// `D > δ` or more from `∂W_s`: `shape ⊂ W_δ`, as are its points within `D − δ` of it.
    /// The larger of this and the bounding disc's `sd(c) − δ − R_max` (also a lower bound): the
    /// disc's is the sharper for a disc, by up to the slack, and refuses a long shape along a
    /// wall.
    #[must_use]
    pub fn star_room(&self, shape: &harmonav_transform::StarShape) -> f64 {
        let c = shape.centre();
        let sd_c = self.signed_distance(c);
        if sd_c.is_nan() || sd_c <= self.delta {
            return sd_c - self.delta;
        }
        let r_max = shape.radius_bounds().1;
        let spacing = 0.125 * self.delta;
        let mut least = sd_c;
        for ring in rings(self.domain()) {
            let n = ring.len();
            for i in 0..n {
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                let edge = Segment::new(PVector::new(a.x, a.y), PVector::new(b.x, b.y));
                if edge.distance_to_local_point(PVector::new(c.x, c.y), true) - r_max >= least {
                    continue;
                }
                let steps = (((b - a).norm() / spacing).ceil() as usize).max(1);
                for j in 0..=steps {
                    let q = a + (b - a) * (j as f64 / steps as f64);
                    least = least.min(shape.signed_distance_bounds(q).0);
                }
            }
        }
        // Both are lower bounds of the room: the disc's `sd(c) − R_max − δ` is the sharper for
        // a disc, by up to the sampling slack.
        (least - 0.5 * spacing - self.delta).max(sd_c - r_max - self.delta)
    }

    /// A lower bound on the distance from `x ∈ W_δ` to the boundary layer: `sd(x) − δ` (exact:
    /// `sd` is 1-Lipschitz, so every `y` with `sd(y) < δ` is farther than `sd(x) − δ`). Negative
    /// in the layer and outside.
    #[must_use]
    pub fn clearance(&self, x: Vector2<f64>) -> f64 {
        self.signed_distance(x) - self.delta
    }

    /// The Lipschitz certificate of `det J_H > 0` and `|H| < 1` on all of `W_δ`
    /// ([`harmonav_harmonic::certify`], `O(N)` per cell) with at most `max_evaluations` cells.
    ///
    /// # Errors
    /// [`CertifyError`] when `δ` is out of range or the first grid exceeds the budget.
    pub fn certify(&self, max_evaluations: usize) -> Result<Certificate, CertifyError> {
        let mut options = CertifyOptions::new(self.delta);
        options.max_evaluations = max_evaluations;
        certify(&self.map, &options)
    }
}
