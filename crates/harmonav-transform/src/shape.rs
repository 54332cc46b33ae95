//! Star-shaped obstacle and workspace shapes: circle, ellipse, rounded polygon, Fourier star.
//!
//! Every shape is star-shaped about its [`StarShape::centre`] and is described by its *radial
//! function*: the boundary point in direction `θ` is `centre + R(θ)(cos θ, sin θ)`. The
//! navigation transformation needs `R(θ)` and `R'(θ)` (both exact, closed form or analytic ray
//! casts). Distances come from parry2d-f64 queries on each shape's *certified outline*, a
//! polyline whose resolution follows the shape's curvature and whose distance to the curve has a
//! proven bound (module [`crate::outline`]), so they are exact to
//! [`crate::outline::DISTANCE_TOLERANCE`] whatever the harmonics (queries in `distance.rs`);
//! `rho_min`, the minimum radius of curvature of the convex parts of the boundary, feeds `d_min`
//! (eq. `dmin`).

use std::f64::consts::{PI, TAU};
use std::sync::{Arc, OnceLock};

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::{PointQuery, Ray, RayCast};

use crate::error::ShapeError;
use crate::outline::{
    DISTANCE_TOLERANCE, MAX_OUTLINE_VERTICES, Outline, Span, TABLE_BLOCK, subdivide,
};

/// Number of vertices of the display outline ([`StarShape::outline`]) of curved shapes.
const DISPLAY: usize = 512;

/// Fewest chords of the certified outline of a shape with a single span (circle, ellipse, star),
/// so that consecutive vertices are never more than 0.1 rad apart as seen from the centre.
const MIN_CHORDS: usize = 64;

/// A star-shaped region of the plane with its radial function (see the module docs).
#[derive(Clone, Debug)]
pub struct StarShape {
    kind: Kind,
    centre: Vector2<f64>,
    r_min: f64,
    r_max: f64,
    rho_min: f64,
    /// The certified outline of the distance queries.
    outline: Arc<Outline>,
    /// The display outline, built on first use.
    display: Arc<OnceLock<Vec<Vector2<f64>>>>,
}

#[derive(Clone, Debug)]
enum Kind {
    Circle {
        r: f64,
    },
    Ellipse {
        a: f64,
        b: f64,
        axis: Vector2<f64>,
    },
    Polygon {
        pieces: Vec<Piece>,
        starts: Vec<f64>,
    },
    /// An offset (inflated or deflated) shape: `(R, R')` on a uniform grid of directions,
    /// cubic Hermite interpolation in between (so `R` is `C¹`).
    Table {
        values: Vec<(f64, f64)>,
    },
    Star {
        r0: f64,
        harmonics: Vec<Harmonic>,
    },
}

/// One term `a cos nθ + b sin nθ` of a Fourier star; `gap` is `n` minus the previous term's `n`
/// (the terms are sorted by `n`, one per `n`).
#[derive(Clone, Copy, Debug)]
struct Harmonic {
    gap: u32,
    n: f64,
    a: f64,
    b: f64,
}

/// A piece of a rounded polygon's boundary, traversed counter-clockwise.
#[derive(Clone, Copy, Debug)]
enum Piece {
    Segment {
        a: Vector2<f64>,
        b: Vector2<f64>,
    },
    /// A fillet: `convex` arcs (centre inside the shape) turn left, the others right.
    /// `angles`: its start and end angle about `centre` ([`arc_angles`], set once the
    /// polygon's pieces are all known; every point of the curve reads them).
    Arc {
        centre: Vector2<f64>,
        radius: f64,
        convex: bool,
        angles: (f64, f64),
    },
}

/// The largest coordinate or length a shape takes, m. Squared distances then stay below 1e19
/// (far from overflow, which at 1e155 m let an ellipse through whose distances were infinite)
/// and positions keep a resolution of 1e-7 m.
pub const MAX_LENGTH: f64 = 1e9;

fn finite(v: f64, field: &'static str) -> Result<f64, ShapeError> {
    if !v.is_finite() {
        Err(ShapeError::NonFinite { field })
    } else if v.abs() > MAX_LENGTH {
        Err(ShapeError::Invalid {
            field,
            problem: format!("must be at most {MAX_LENGTH:e} m in magnitude, got {v:e}"),
        })
    } else {
        Ok(v)
    }
}

/// The largest harmonic number `n` of a Fourier star. A star's outline needs about
/// `2π·√(n²|c_n|/(4·DISTANCE_TOLERANCE·r0))` vertices (module [`crate::outline`]), so the cap
/// keeps every single-harmonic star below [`MAX_OUTLINE_VERTICES`]; scenario files use the same
/// cap.
pub const MAX_HARMONIC: u32 = 1000;

/// The largest angle magnitude a shape takes, rad. Beyond it an `f64` no longer resolves the
/// orientation to 1e-10 rad (the spacing of `f64` near 1e6 is 1.2e-10).
pub const MAX_ANGLE: f64 = 1e6;

fn finite_angle(v: f64, field: &'static str) -> Result<f64, ShapeError> {
    if !v.is_finite() {
        Err(ShapeError::NonFinite { field })
    } else if v.abs() > MAX_ANGLE {
        Err(ShapeError::Invalid {
            field,
            problem: format!(
                "an angle must be at most {MAX_ANGLE:e} rad ({:.1e}°) in magnitude, got {v:e} rad",
                MAX_ANGLE.to_degrees()
            ),
        })
    } else {
        Ok(v)
    }
}

fn positive(v: f64, field: &'static str) -> Result<f64, ShapeError> {
    if finite(v, field)? > 0.0 {
        Ok(v)
    } else {
        Err(ShapeError::NotPositive { field, value: v })
    }
}

fn finite_point(p: Vector2<f64>, field: &'static str) -> Result<Vector2<f64>, ShapeError> {
    finite(p.x, field)?;
    finite(p.y, field)?;
    Ok(p)
}

fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

fn left(v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

fn dir(theta: f64) -> Vector2<f64> {
    Vector2::new(theta.cos(), theta.sin())
}

impl StarShape {
    /// A disc of the given radius: `R(θ) = r`, `rho_min = r`.
    pub fn circle(centre: Vector2<f64>, radius: f64) -> Result<Self, ShapeError> {
        let centre = finite_point(centre, "center")?;
        let r = positive(radius, "radius")?;
        let spans = [Span {
            t0: 0.0,
            t1: TAU,
            k: r, // |p''| = r
        }];
        Self::new(Kind::Circle { r }, centre, (r, r), r)
            .certify(&spans, TAU, MIN_CHORDS, r, "radius")
    }

    /// An ellipse with semi-axes `(a, b)` along the directions `angle` and `angle + π/2`
    /// (radians): `R(ψ) = ab/√(b² cos²ψ + a² sin²ψ)`, `ψ = θ − angle`;
    /// `rho_min = min(a,b)²/max(a,b)`.
    pub fn ellipse(
        centre: Vector2<f64>,
        semi_axes: [f64; 2],
        angle: f64,
    ) -> Result<Self, ShapeError> {
        let centre = finite_point(centre, "center")?;
        let a = positive(semi_axes[0], "semi_axes")?;
        let b = positive(semi_axes[1], "semi_axes")?;
        let angle = finite_angle(angle, "angle_deg")?;
        let (lo, hi) = (a.min(b), a.max(b));
        let kind = Kind::Ellipse {
            a,
            b,
            axis: dir(angle),
        };
        // Parametrised by the eccentric anomaly t: p'' = −(p − c), |p''| ≤ max(a, b).
        let spans = [Span {
            t0: 0.0,
            t1: TAU,
            k: hi,
        }];
        Self::new(kind, centre, (lo, hi), lo * lo / hi).certify(
            &spans,
            TAU,
            MIN_CHORDS,
            hi,
            "semi_axes",
        )
    }

    /// A Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)` about `centre`, harmonics
    /// given as `(n, a_n, b_n)` with `1 ≤ n ≤` [`MAX_HARMONIC`] (terms of equal `n` add up).
    ///
    /// Rejected if `R ≤ 0` anywhere, certified: on a grid of step `h` containing the outline's
    /// directions, `R(θ) ≥ min R(θ_i) − max|R''|·h²/8` between grid points (eq. chord of
    /// [`crate::outline`] for `R` itself, `max|R''| ≤ Σ n²√(a_n² + b_n²)`), and the same margin
    /// makes [`Self::radius_bounds`] certified. `rho_min` is the smallest curvature radius on the
    /// grid (at least 8192 directions).
    ///
    /// Errors: `radius` not positive, a harmonic number of 0 or above [`MAX_HARMONIC`], a
    /// non-finite or too large amplitude, `R ≤ 0` somewhere, or an outline of more than
    /// [`MAX_OUTLINE_VERTICES`] (amplitudes that make the curvature too fine), all on the field
    /// `harmonics` but the first.
    pub fn fourier_star(
        centre: Vector2<f64>,
        r0: f64,
        harmonics: &[(u32, f64, f64)],
    ) -> Result<Self, ShapeError> {
        let centre = finite_point(centre, "center")?;
        let r0 = positive(r0, "radius")?;
        let mut terms = Vec::with_capacity(harmonics.len());
        for &(n, a, b) in harmonics {
            if n == 0 {
                return Err(ShapeError::Invalid {
                    field: "harmonics",
                    problem: "harmonic numbers n must be ≥ 1".into(),
                });
            }
            if n > MAX_HARMONIC {
                return Err(ShapeError::Invalid {
                    field: "harmonics",
                    problem: format!(
                        "harmonic number {n} is above the cap MAX_HARMONIC = {MAX_HARMONIC}"
                    ),
                });
            }
            terms.push((n, finite(a, "harmonics")?, finite(b, "harmonics")?));
        }
        terms.sort_by_key(|t| t.0);
        let mut merged: Vec<(u32, f64, f64)> = Vec::with_capacity(terms.len());
        for (n, a, b) in terms {
            match merged.last_mut() {
                Some(last) if last.0 == n => {
                    last.1 += a;
                    last.2 += b;
                }
                _ => merged.push((n, a, b)),
            }
        }
        let mut prev = 0;
        let mut h = Vec::with_capacity(merged.len());
        for (n, a, b) in merged {
            h.push(Harmonic {
                gap: n - prev,
                n: n as f64,
                a: finite(a, "harmonics")?,
                b: finite(b, "harmonics")?,
            });
            prev = n;
        }
        // Certified bounds (module `outline`): |R'| ≤ m1, |R''| ≤ m2, |R'' − R| ≤ bend.
        let (mut m1, mut m2, mut bend, mut size) = (0.0, 0.0, r0, r0);
        for t in &h {
            let c = t.a.hypot(t.b);
            m1 += t.n * c;
            m2 += t.n * t.n * c;
            bend += (t.n * t.n + 1.0) * c;
            size += c;
        }
        let spans = [Span {
            t0: 0.0,
            t1: TAU,
            k: bend.hypot(2.0 * m1),
        }];
        // r0 is the mean of R over the turn, so r0 ≤ max R (the tolerance's reference).
        let (params, delta) =
            subdivide(&spans, r0, MIN_CHORDS).map_err(|count| too_detailed("harmonics", count))?;
        let kind = Kind::Star { r0, harmonics: h };
        let harmonics = match &kind {
            Kind::Star { harmonics, .. } => harmonics,
            _ => unreachable!(),
        };
        let samples = params.len() * 8192usize.div_ceil(params.len());
        let step = TAU / samples as f64;
        let (mut lo, mut hi, mut rho) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        for i in 0..samples {
            let (r, dr, ddr) = star_radius(r0, harmonics, dir(i as f64 * step));
            lo = lo.min(r);
            hi = hi.max(r);
            let den = r * r + 2.0 * dr * dr - r * ddr;
            if den > 0.0 {
                rho = rho.min((r * r + dr * dr).powf(1.5) / den);
            }
        }
        // Between grid points R strays at most m2·step²/8 from the chord (plus rounding).
        let margin = m2 * step * step / 8.0 + 1e-12 * size;
        if lo - margin <= 0.0 {
            return Err(ShapeError::Invalid {
                field: "harmonics",
                problem: format!(
                    "the radius R(θ) reaches {lo:.3} ≤ 0: the star is not a valid star-shaped region"
                ),
            });
        }
        Ok(Self::new(kind, centre, (lo - margin, hi + margin), rho)
            .with_outline(params, delta, TAU))
    }

    /// A polygon with rounded corners: each corner (convex or reflex) is replaced by a circular
    /// arc of radius `corner_radius` tangent to both edges, so the boundary is `C¹`. The
    /// polygon must be strictly star-shaped about its vertex centroid (the centre); vertices
    /// may be given in either orientation. `rho_min = corner_radius`.
    pub fn rounded_polygon(
        vertices: &[Vector2<f64>],
        corner_radius: f64,
    ) -> Result<Self, ShapeError> {
        if vertices.len() < 3 {
            return Err(ShapeError::Invalid {
                field: "vertices",
                problem: format!(
                    "a polygon needs at least 3 vertices, got {}",
                    vertices.len()
                ),
            });
        }
        for &v in vertices {
            finite_point(v, "vertices")?;
        }
        let rc = positive(corner_radius, "corner_radius")?;
        let mut v: Vec<Vector2<f64>> = vertices.to_vec();
        let area2: f64 = (0..v.len())
            .map(|i| cross(v[i], v[(i + 1) % v.len()]))
            .sum();
        if area2 < 0.0 {
            v.reverse();
        }
        let n = v.len();
        let centre = v.iter().sum::<Vector2<f64>>() / n as f64;
        // Tangent points and fillet arcs.
        let mut t_in = Vec::with_capacity(n);
        let mut t_out = Vec::with_capacity(n);
        let mut arcs = Vec::with_capacity(n);
        for i in 0..n {
            let (p, c, q) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
            let (l1, l2) = ((c - p).norm(), (q - c).norm());
            if l1 == 0.0 || l2 == 0.0 {
                return Err(ShapeError::Invalid {
                    field: "vertices",
                    problem: format!("vertex {i} repeats its neighbour"),
                });
            }
            let (e1, e2) = ((c - p) / l1, (q - c) / l2);
            let turn = cross(e1, e2).atan2(e1.dot(&e2)); // signed turning angle
            if turn.abs() >= PI - 1e-9 {
                return Err(ShapeError::Invalid {
                    field: "vertices",
                    problem: format!("the polygon folds back on itself at vertex {i}"),
                });
            }
            let d = rc * (turn.abs() / 2.0).tan();
            t_in.push(c - d * e1);
            t_out.push(c + d * e2);
            let convex = turn > 0.0;
            let centre_arc = if convex {
                c - d * e1 + rc * left(e1)
            } else {
                c - d * e1 - rc * left(e1)
            };
            arcs.push((turn.abs() > 1e-12).then_some(Piece::Arc {
                centre: centre_arc,
                radius: rc,
                convex,
                angles: (0.0, 0.0),
            }));
        }
        let mut pieces = Vec::with_capacity(2 * n);
        for i in 0..n {
            let j = (i + 1) % n;
            let edge = (v[j] - v[i]).norm();
            let used = (t_out[i] - v[i]).norm() + (v[j] - t_in[j]).norm();
            if used > edge * (1.0 + 1e-12) {
                return Err(ShapeError::Invalid {
                    field: "corner_radius",
                    problem: format!(
                        "corner radius {rc} is too large for edge {i}–{j} (length {edge:.4})"
                    ),
                });
            }
            if let Some(arc) = arcs[i] {
                pieces.push(arc);
            }
            if used < edge {
                pieces.push(Piece::Segment {
                    a: t_out[i],
                    b: t_in[j],
                });
            }
        }
        // Each arc's end angles, from its neighbours' ends (which do not read them).
        let angles: Vec<(f64, f64)> = (0..pieces.len())
            .map(|k| match pieces[k] {
                Piece::Arc { .. } => arc_angles(&pieces, k),
                Piece::Segment { .. } => (0.0, 0.0),
            })
            .collect();
        for (piece, ends) in pieces.iter_mut().zip(angles) {
            if let Piece::Arc { angles, .. } = piece {
                *angles = ends;
            }
        }
        // Strict star-shapedness: the boundary turns counter-clockwise as seen from the centre.
        let mut starts = Vec::with_capacity(pieces.len());
        let mut rho_max = 0.0f64;
        for (k, piece) in pieces.iter().enumerate() {
            let (start, _) = piece_ends(piece, &pieces, k);
            for s in 0..=16 {
                let (p, tangent) = piece_point(piece, s as f64 / 16.0);
                rho_max = rho_max.max((p - centre).norm());
                if cross(p - centre, tangent) <= 1e-12 * (p - centre).norm() {
                    return Err(ShapeError::Invalid { field: "vertices", problem: "the rounded polygon is not strictly star-shaped about its vertex centroid".into() });
                }
            }
            starts.push((start - centre).y.atan2((start - centre).x));
        }
        // Unwrap the start angles into an increasing sequence over one turn.
        for k in 1..starts.len() {
            while starts[k] <= starts[k - 1] {
                starts[k] += TAU;
            }
        }
        if starts[starts.len() - 1] - starts[0] >= TAU {
            return Err(ShapeError::Invalid {
                field: "vertices",
                problem: "the rounded polygon winds more than once about its centroid".into(),
            });
        }
        // Segments are exact chords (|p''| = 0); an arc of radius rc and angle Δ, parametrised
        // by s ∈ [0, 1], has |p''| = rc Δ².
        let spans: Vec<Span> = (0..pieces.len())
            .map(|k| Span {
                t0: k as f64,
                t1: (k + 1) as f64,
                k: match pieces[k] {
                    Piece::Segment { .. } => 0.0,
                    Piece::Arc {
                        radius,
                        angles: (a0, a1),
                        ..
                    } => radius * (a1 - a0) * (a1 - a0),
                },
            })
            .collect();
        let period = pieces.len() as f64;
        let kind = Kind::Polygon { pieces, starts };
        // rho_max: the farthest sampled boundary point, at most max R.
        let mut shape = Self::new(kind, centre, (0.0, f64::INFINITY), rc)
            .certify(&spans, period, 1, rho_max, "vertices")?;
        // Certified radius bounds from the outline: the curve is within δ of it.
        let outline = &shape.outline;
        let near = outline
            .polyline
            .distance_to_local_point(PVector::new(centre.x, centre.y), false);
        let far = (0..outline.len())
            .map(|i| (outline.vertex(i) - centre).norm())
            .fold(0.0, f64::max);
        shape.r_min = ((near - outline.delta) * (1.0 - 1e-12)).max(0.0);
        shape.r_max = (far + outline.delta) * (1.0 + 1e-12);
        Ok(shape)
    }

    /// The same shape with `rho_min` (for eq. `dmin`) replaced.
    pub(crate) fn with_rho_min(mut self, rho_min: f64) -> Self {
        self.rho_min = rho_min;
        self
    }

    /// A shape without its outline yet; `radii` are the certified bounds of `R`.
    fn new(kind: Kind, centre: Vector2<f64>, radii: (f64, f64), rho_min: f64) -> Self {
        Self {
            kind,
            centre,
            r_min: radii.0,
            r_max: radii.1,
            rho_min,
            outline: Arc::new(Outline::empty()),
            display: Arc::new(OnceLock::new()),
        }
    }

    /// The shape with its certified outline on `spans` (module [`crate::outline`]) for the
    /// reference radius `r_ref ≤ max R`; a typed error on `field` beyond
    /// [`MAX_OUTLINE_VERTICES`].
    fn certify(
        self,
        spans: &[Span],
        period: f64,
        min_chords: usize,
        r_ref: f64,
        field: &'static str,
    ) -> Result<Self, ShapeError> {
        let (params, delta) =
            subdivide(spans, r_ref, min_chords).map_err(|count| too_detailed(field, count))?;
        Ok(self.with_outline(params, delta, period))
    }

    /// The shape with the outline through its curve points at `params`.
    fn with_outline(mut self, params: Vec<f64>, delta: f64, period: f64) -> Self {
        let vertices: Vec<Vector2<f64>> = params.iter().map(|&t| self.curve_point(t)).collect();
        self.outline = Arc::new(Outline::new(&vertices, params, period, delta));
        self
    }

    /// The boundary curve `p(t)` in the parameter of the certified outline: the polar angle for
    /// circles, stars and offset shapes, the eccentric anomaly for ellipses
    /// (`c + a cos t e₁ + b sin t e₂`), piece index plus fraction for rounded polygons.
    pub(crate) fn curve_point(&self, t: f64) -> Vector2<f64> {
        match &self.kind {
            Kind::Ellipse { a, b, axis } => {
                self.centre + a * t.cos() * axis + b * t.sin() * left(*axis)
            }
            Kind::Polygon { pieces, .. } => {
                let t = t.rem_euclid(pieces.len() as f64);
                let k = (t.floor() as usize).min(pieces.len() - 1);
                piece_point(&pieces[k], (t - k as f64).min(1.0)).0
            }
            _ => {
                let u = dir(t);
                self.centre + self.radius_along(u).0 * u
            }
        }
    }

    /// The certified outline of the distance queries.
    pub(crate) fn certified(&self) -> &Outline {
        &self.outline
    }

    /// `Some(r)` for a circle.
    pub(crate) fn circle_radius(&self) -> Option<f64> {
        match self.kind {
            Kind::Circle { r } => Some(r),
            _ => None,
        }
    }

    /// The display outline: polygon pieces with 32 vertices per arc; other shapes [`DISPLAY`]
    /// points evenly spaced in arc length (from a dense angular grid), so that sharply curved
    /// tips are drawn as finely as flat sides.
    fn display_outline(&self) -> Vec<Vector2<f64>> {
        if let Kind::Polygon { pieces, .. } = &self.kind {
            return pieces
                .iter()
                .flat_map(|piece| {
                    let steps = if matches!(piece, Piece::Arc { .. }) {
                        32
                    } else {
                        1
                    };
                    (0..steps).map(move |i| piece_point(piece, i as f64 / steps as f64).0)
                })
                .collect();
        }
        let dense = 4 * DISPLAY;
        let p: Vec<Vector2<f64>> = (0..=dense)
            .map(|i| self.boundary_point(TAU * i as f64 / dense as f64))
            .collect();
        let mut arc = vec![0.0; dense + 1];
        for i in 1..=dense {
            arc[i] = arc[i - 1] + (p[i] - p[i - 1]).norm();
        }
        let total = arc[dense];
        let mut j = 0;
        (0..DISPLAY)
            .map(|k| {
                let target = total * k as f64 / DISPLAY as f64;
                while arc[j + 1] < target {
                    j += 1;
                }
                let t = (target - arc[j]) / (arc[j + 1] - arc[j]).max(f64::MIN_POSITIVE);
                self.boundary_point(TAU * (j as f64 + t) / dense as f64)
            })
            .collect()
    }

    /// Whether `other` is this very shape: a clone of it (or both of one original), which
    /// share their certified outline. Shapes built apart are never the same, even when equal
    /// (a cheap test of "unchanged", for a caller that keeps what it built from a shape).
    #[must_use]
    pub fn is_clone_of(&self, other: &StarShape) -> bool {
        Arc::ptr_eq(&self.outline, &other.outline)
    }

    /// The centre about which the shape is star-shaped (the obstacle's point `P_i`).
    pub fn centre(&self) -> Vector2<f64> {
        self.centre
    }

    /// Lower and upper bounds of `R(θ)` over all directions, certified (exact for circles and
    /// ellipses; for stars and offset shapes from a grid with the margin `max|R''|·h²/8`, for
    /// rounded polygons from the certified outline widened by its chord bound).
    pub fn radius_bounds(&self) -> (f64, f64) {
        (self.r_min, self.r_max)
    }

    /// Minimum radius of curvature of the convex parts of the boundary (for eq. `dmin`).
    pub fn rho_min(&self) -> f64 {
        self.rho_min
    }

    /// The enclosed area, m²: `A = ½∮R(θ)² dθ`, by the trapezoid rule on 1 024 directions
    /// (spectrally accurate for a smooth periodic `R`; for a rounded polygon, whose `R` has
    /// corners in its derivative, within about 1e-5 relative).
    #[must_use]
    pub fn area(&self) -> f64 {
        const N: usize = 1024;
        let sum: f64 = (0..N)
            .map(|j| self.radius(TAU * j as f64 / N as f64).0.powi(2))
            .sum();
        0.5 * TAU * sum / N as f64
    }

    /// The radial function `(R(θ), R'(θ))` for the direction `θ` (radians, any value).
    pub fn radius(&self, theta: f64) -> (f64, f64) {
        self.radius_along(dir(theta))
    }

    /// The radial function `(R(θ), R'(θ))` for the unit direction `u = (cos θ, sin θ)`.
    ///
    /// The hot path of `Phi`: circles, ellipses and Fourier stars need no trigonometric call
    /// (`cos nθ + i sin nθ = (u_x + i u_y)^n`, by repeated squaring: `O(log n)` products per
    /// harmonic); rounded polygons and offset shapes take one `atan2`.
    pub fn radius_along(&self, u: Vector2<f64>) -> (f64, f64) {
        match &self.kind {
            Kind::Circle { r } => (*r, 0.0),
            Kind::Ellipse { a, b, axis } => {
                // ψ = θ − angle: cos ψ = u·axis, sin ψ = axis × u.
                let (c, s) = (u.dot(axis), cross(*axis, u));
                let d = b * b * c * c + a * a * s * s;
                let r = a * b / d.sqrt();
                (r, -a * b * (a * a - b * b) * s * c / (d * d.sqrt()))
            }
            Kind::Star { r0, harmonics } => {
                let (r, dr, _) = star_radius(*r0, harmonics, u);
                (r, dr)
            }
            Kind::Polygon { pieces, starts } => {
                polygon_radius(self.centre, pieces, starts, u.y.atan2(u.x))
            }
            Kind::Table { values } => table_radius(values, u.y.atan2(u.x)),
        }
    }

    /// The radial function `(R(θ), R'(θ))` about another interior point `p` (the shape is
    /// convex, so star-shaped about it), for circles and ellipses; `None` for other shapes. In
    /// the ellipse's frame scaled to the unit circle (`M`), with `q = M(p − c)`, `v = M u`,
    /// `v' = M u⊥`, the ray `p + t u` meets the boundary at `|q + t v| = 1`:
    ///
    /// ```text
    /// R  = (−q·v + √((q·v)² − |v|²(|q|² − 1))) / |v|²
    /// R' = −R (q·v' + R v·v') / (q·v + R |v|²)
    /// ```
    pub fn radius_about(&self, p: Vector2<f64>, u: Vector2<f64>) -> Option<(f64, f64)> {
        let (a, b, axis) = match &self.kind {
            Kind::Ellipse { a, b, axis } => (*a, *b, *axis),
            Kind::Circle { r } => (*r, *r, Vector2::new(1.0, 0.0)),
            _ => return None,
        };
        let m = |w: Vector2<f64>| Vector2::new(w.dot(&axis) / a, cross(axis, w) / b);
        let q = m(p - self.centre);
        let v = m(u);
        let vp = m(left(u));
        let (qv, vv) = (q.dot(&v), v.norm_squared());
        let disc = qv * qv - vv * (q.norm_squared() - 1.0);
        // disc ≥ (q·v)² > 0 for p inside (|q| < 1); the guard only absorbs rounding at the wall.
        let t = (-qv + disc.max(0.0).sqrt()) / vv;
        let dt = -t * (q.dot(&vp) + t * v.dot(&vp)) / (qv + t * vv);
        Some((t, dt))
    }

    /// The shape offset by `r` along its outward normal: inflated for `r > 0` (an obstacle
    /// grown by the robot radius), deflated for `r < 0` (the workspace boundary shrunk by it).
    ///
    /// Circles stay exact circles. Other shapes: the boundary is sampled at 8192 directions,
    /// each point moved by `r` along its normal (the offset curve keeps the tangent, so
    /// `R' = −R (u⊥·n)/(u·n)` there), and `(R, R')` is resampled on 4096 directions with cubic
    /// Hermite interpolation (`C¹`). `rho_min` grows by `r`. The table's radius bounds and
    /// certified outline come from its cubic cells (bounds on `R, R', R''` per cell).
    ///
    /// Errors if the offset curve folds (the radius exceeds the curvature radius of a concave
    /// part of the boundary, where the true grown region would have a corner) or is not
    /// star-shaped about the same centre: such a world needs a smaller robot.
    pub fn offset(&self, r: f64) -> Result<StarShape, ShapeError> {
        finite(r, "robot.radius")?;
        if r == 0.0 {
            return Ok(self.clone());
        }
        if let Kind::Circle { r: radius } = self.kind {
            return Self::circle(self.centre, radius + r).map_err(|_| ShapeError::Invalid {
                field: "robot.radius",
                problem: format!(
                    "deflating a circle of radius {radius} by {} leaves nothing",
                    -r
                ),
            });
        }
        let not_star = || ShapeError::Invalid {
            field: "robot.radius",
            problem: format!(
                "offsetting the shape by {r} makes it lose its star shape about its centre"
            ),
        };
        let samples = 8192;
        let mut pts: Vec<(f64, f64, f64)> = Vec::with_capacity(samples); // (θ, R, R')
        for j in 0..samples {
            let phi = TAU * j as f64 / samples as f64;
            let (rr, dr) = self.radius(phi);
            let (u, up) = (dir(phi), left(dir(phi)));
            let tangent = dr * u + rr * up;
            let n = Vector2::new(tangent.y, -tangent.x) / tangent.norm(); // outward
            let q = rr * u + r * n;
            let rq = q.norm();
            let uq = q / rq;
            if rq <= 0.0 || uq.dot(&n) <= 1e-9 {
                return Err(not_star());
            }
            let mut th = q.y.atan2(q.x);
            if let Some(&(prev, _, _)) = pts.last() {
                while th <= prev - PI {
                    th += TAU;
                }
                if th <= prev {
                    return Err(not_star());
                }
            }
            pts.push((th, rq, -rq * left(uq).dot(&n) / uq.dot(&n)));
        }
        if pts[samples - 1].0 - pts[0].0 >= TAU {
            return Err(not_star());
        }
        let grid = 4096;
        let mut values = Vec::with_capacity(grid);
        for g in 0..grid {
            // The grid angle within the samples' unwrapped turn [θ_0, θ_0 + 2π).
            let th = pts[0].0 + (TAU * g as f64 / grid as f64 - pts[0].0).rem_euclid(TAU);
            let k = pts.partition_point(|p| p.0 <= th).saturating_sub(1);
            let a = pts[k];
            let b = match pts.get(k + 1) {
                Some(&b) => b,
                None => (pts[0].0 + TAU, pts[0].1, pts[0].2),
            };
            values.push(hermite(a, b, th));
        }
        if table_spans(&values).1 <= 0.0 {
            return Err(not_star());
        }
        let rho = (self.rho_min + r).max(f64::MIN_POSITIVE);
        Self::table(self.centre, values, rho, false, "robot.radius")
    }

    /// The star about `centre` whose `(R, R')` are `values` on the uniform grid
    /// `θ_i = 2πi/G` (cubic Hermite in between, [`StarShape::offset`]'s kind), with its
    /// certified radius bounds and outline. `monotone`: every cell is monotone (the caller's
    /// slopes guarantee it), so `R` stays between its cell's end values, the bounds. Errors on
    /// `field` if `R` may reach 0 or the outline would need more than [`MAX_OUTLINE_VERTICES`].
    pub(crate) fn table(
        centre: Vector2<f64>,
        values: Vec<(f64, f64)>,
        rho_min: f64,
        monotone: bool,
        field: &'static str,
    ) -> Result<Self, ShapeError> {
        let (spans, mut lo, mut hi) = table_spans(&values);
        if monotone {
            lo = values.iter().map(|v| v.0).fold(f64::INFINITY, f64::min) * (1.0 - 1e-12);
            hi = values.iter().map(|v| v.0).fold(0.0, f64::max) * (1.0 + 1e-12);
        }
        if lo.is_nan() || lo <= 0.0 {
            return Err(ShapeError::Invalid {
                field,
                problem: format!("the tabulated radius R(θ) may reach {lo:.3e} ≤ 0"),
            });
        }
        // The largest tabulated radius is a value of R, at most max R.
        let r_ref = values.iter().map(|v| v.0).fold(0.0, f64::max);
        Self::new(Kind::Table { values }, centre, (lo, hi), rho_min)
            .certify(&spans, TAU, 1, r_ref, field)
    }

    /// The boundary point `centre + R(θ)(cos θ, sin θ)`.
    pub fn boundary_point(&self, theta: f64) -> Vector2<f64> {
        self.centre + self.radius(theta).0 * dir(theta)
    }

    /// Whether `x` lies in the closed region (exact, from the radial function).
    pub fn contains(&self, x: Vector2<f64>) -> bool {
        let v = x - self.centre;
        let rho = v.norm();
        rho <= self.r_min || (rho <= self.r_max && rho <= self.radius(v.y.atan2(v.x)).0)
    }

    /// The display outline (counter-clockwise, closed): for figures and visibility graphs, not
    /// for distances. Rounded polygons: the pieces' ends and 32 vertices per arc; other shapes:
    /// 512 vertices on the curve, evenly spaced in arc length. (Distances use the certified
    /// outline, module [`crate::outline`], whose resolution follows the curvature.)
    pub fn outline(&self) -> impl Iterator<Item = Vector2<f64>> + '_ {
        self.display
            .get_or_init(|| self.display_outline())
            .iter()
            .copied()
    }

    /// Distance along the ray `origin + t·dir` (`dir` a unit vector, `origin` outside the
    /// shape) to the first boundary point, if it is at most `max`.
    ///
    /// parry casts the ray against the outline; the hit is then refined by bisection on the
    /// exact containment test, bracketed a little before and after parry's hit.
    pub fn ray_hit(&self, origin: Vector2<f64>, dir: Vector2<f64>, max: f64) -> Option<f64> {
        // Quick reject: the ray's closest approach to the centre is beyond the largest radius.
        let to_c = self.centre - origin;
        let along = to_c.dot(&dir).clamp(0.0, max);
        if (to_c - along * dir).norm() > self.r_max {
            return None;
        }
        // Far larger than the certified outline's chord bound (δ ≤ 5e-5 of max R).
        let slack = 4e-3 * self.r_max;
        let coarse = self.outline.polyline.cast_local_ray(
            &Ray::new(PVector::new(origin.x, origin.y), PVector::new(dir.x, dir.y)),
            max + slack,
            false,
        );
        // parry's hit on the outline is within the chord bound of the true one: bisect on the
        // exact containment test in a bracket around it. (A ray that grazes the curve less than
        // the chord bound δ deep can be missed.)
        let t = coarse?;
        let (mut a, mut b) = ((t - slack).max(0.0), t + slack);
        if self.contains(origin + a * dir) {
            return Some(a).filter(|&a| a <= max);
        }
        if !self.contains(origin + b * dir) {
            // The exact boundary is entered somewhere in the bracket: search it on a fine grid.
            let steps = 64;
            b = (1..=steps)
                .map(|i| a + (b - a) * i as f64 / steps as f64)
                .find(|&s| self.contains(origin + s * dir))?;
            a = b - 2.0 * slack / steps as f64;
        }
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if self.contains(origin + m * dir) {
                b = m
            } else {
                a = m
            }
        }
        (b <= max).then_some(b)
    }

    /// The local minima of the distance from `x` (outside the shape) to the boundary: the
    /// boundary points where `|p(θ) − x|` has a local minimum, found at the vertices of the
    /// certified outline and refined on the exact curve within two vertices on either side. The
    /// global minimum (the nearest point) is among them.
    pub fn distance_minima(&self, x: Vector2<f64>) -> impl Iterator<Item = Vector2<f64>> + '_ {
        let outline = &self.outline;
        let n = outline.len();
        let d = move |i: usize| (outline.vertex(i % n) - x).norm_squared();
        (0..n).filter_map(move |i| {
            let (prev, here, next) = (d(i + n - 1), d(i), d(i + 1));
            if here > prev || here > next {
                return None;
            }
            let (lo, hi) = outline.window(i as isize - 2, i as isize + 2);
            Some(self.curve_point(golden_min(
                |t| (self.curve_point(t) - x).norm_squared(),
                lo,
                hi,
            )))
        })
    }
}

/// The typed error for a shape whose certified outline would exceed [`MAX_OUTLINE_VERTICES`].
fn too_detailed(field: &'static str, count: f64) -> ShapeError {
    ShapeError::Invalid {
        field,
        problem: format!(
            "the boundary bends too sharply: its outline needs {count:.0} vertices for the \
             distance tolerance {DISTANCE_TOLERANCE:e}, more than MAX_OUTLINE_VERTICES = \
             {MAX_OUTLINE_VERTICES}"
        ),
    }
}

/// `(R, R', R'')` of a Fourier star in the unit direction `u`: `cos nθ + i sin nθ` is
/// `(u_x + i u_y)^n`, advanced from one harmonic to the next by the power `u^gap` (harmonics
/// sorted by `n`).
///
/// ```text
/// R = r0 + Σ (a_n cos nθ + b_n sin nθ),  R' = Σ n (b_n cos nθ − a_n sin nθ),
/// R'' = −Σ n² (a_n cos nθ + b_n sin nθ)
/// ```
///
/// Cost `O(Σ log₂ gap)` products, at most ~20 per harmonic for `n ≤ MAX_HARMONIC`; the relative
/// error of `u^n` is `O(n ε)`, the same as that of `sin_cos(n θ)` for the rounded angle.
#[inline(always)]
fn star_radius(r0: f64, harmonics: &[Harmonic], u: Vector2<f64>) -> (f64, f64, f64) {
    let Some((first, rest)) = harmonics.split_first() else {
        return (r0, 0.0, 0.0);
    };
    let (mut c, mut s) = unit_power(u, first.gap);
    let mut even = first.a * c + first.b * s;
    let (mut r, mut dr, mut ddr) = (
        r0 + even,
        first.n * (first.b * c - first.a * s),
        -first.n * first.n * even,
    );
    for h in rest {
        let (pc, ps) = unit_power(u, h.gap);
        (c, s) = (c * pc - s * ps, c * ps + s * pc);
        even = h.a * c + h.b * s;
        r += even;
        dr += h.n * (h.b * c - h.a * s);
        ddr -= h.n * h.n * even;
    }
    (r, dr, ddr)
}

/// `(u_x + i u_y)^g` for `g ≥ 1`: `g − 1` products up to `g = 4` (the common dense harmonics),
/// binary exponentiation beyond (`⌊log₂ g⌋` squarings and `popcount(g) − 1` products).
fn unit_power(u: Vector2<f64>, g: u32) -> (f64, f64) {
    let (mut c, mut s) = (u.x, u.y);
    if g <= 4 {
        for _ in 1..g {
            (c, s) = (c * u.x - s * u.y, c * u.y + s * u.x);
        }
        return (c, s);
    }
    let mut g = g;
    while g & 1 == 0 {
        (c, s) = (c * c - s * s, 2.0 * c * s);
        g >>= 1;
    }
    let (mut bc, mut bs) = (c, s);
    g >>= 1;
    while g > 0 {
        (bc, bs) = (bc * bc - bs * bs, 2.0 * bc * bs);
        if g & 1 == 1 {
            (c, s) = (c * bc - s * bs, c * bs + s * bc);
        }
        g >>= 1;
    }
    (c, s)
}

/// The outline spans of an offset shape's table (one per `TABLE_BLOCK` Hermite cells) with
/// certified bounds `(min R, max R)`.
///
/// On a cell of width `H`, in `t = (θ − θ_a)/H`, `R = c₀ + c₁t + c₂t² + c₃t³` with
/// `c₀ = R_a`, `c₁ = H R'_a`, `c₂ = 3(R_b − R_a) − H(2R'_a + R'_b)`,
/// `c₃ = 2(R_a − R_b) + H(R'_a + R'_b)`. So `R'' = (2c₂ + 6c₃t)/H²` is largest at an end,
/// `R' = (c₁ + 2c₂t + 3c₃t²)/H` at an end or at `t = −c₂/(3c₃)`, `|R| ≤ max(|R_a|, |R_b|) +
/// max|R'|·H/2`, and `R` is within `max|R''|·H²/8` of its chord (eq. chord). `K` of a span is
/// the largest `√((max|R''| + max|R|)² + 4 max|R'|²)` of its cells.
fn table_spans(values: &[(f64, f64)]) -> (Vec<Span>, f64, f64) {
    let g = values.len();
    let h = TAU / g as f64;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut spans = Vec::with_capacity(g.div_ceil(TABLE_BLOCK));
    for first in (0..g).step_by(TABLE_BLOCK) {
        let last = (first + TABLE_BLOCK).min(g);
        let mut k = 0.0f64;
        for i in first..last {
            let ((ra, da), (rb, db)) = (values[i], values[(i + 1) % g]);
            let c1 = h * da;
            let c2 = 3.0 * (rb - ra) - h * (2.0 * da + db);
            let c3 = 2.0 * (ra - rb) + h * (da + db);
            let d2 = (2.0 * c2).abs().max((2.0 * c2 + 6.0 * c3).abs()) / (h * h);
            let mut d1 = c1.abs().max((c1 + 2.0 * c2 + 3.0 * c3).abs());
            let vertex = -c2 / (3.0 * c3);
            if vertex > 0.0 && vertex < 1.0 {
                d1 = d1.max((c1 + vertex * (2.0 * c2 + 3.0 * c3 * vertex)).abs());
            }
            let d1 = d1 / h;
            let sag = d2 * h * h / 8.0;
            lo = lo.min(ra.min(rb) - sag);
            hi = hi.max(ra.max(rb) + sag);
            let r_abs = ra.abs().max(rb.abs()) + d1 * h / 2.0;
            k = k.max((d2 + r_abs).hypot(2.0 * d1));
        }
        spans.push(Span {
            t0: first as f64 * h,
            t1: last as f64 * h,
            k,
        });
    }
    // Rounding of the cubic's evaluation.
    (spans, lo * (1.0 - 1e-12), hi * (1.0 + 1e-12))
}

/// Golden-section search for the minimum of a unimodal `f` on `[lo, hi]` (to ~1e-13).
pub(crate) fn golden_min(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    for _ in 0..64 {
        if fa < fb {
            hi = b;
            (b, fb) = (a, fa);
            a = hi - g * (hi - lo);
            fa = f(a);
        } else {
            lo = a;
            (a, fa) = (b, fb);
            b = lo + g * (hi - lo);
            fb = f(b);
        }
    }
    if fa < fb { a } else { b }
}

/// Cubic Hermite interpolation of `(R, R')` between samples `a = (θ_a, R_a, R'_a)` and `b`.
fn hermite(a: (f64, f64, f64), b: (f64, f64, f64), th: f64) -> (f64, f64) {
    let h = b.0 - a.0;
    let t = ((th - a.0) / h).clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    let r = (2.0 * t3 - 3.0 * t2 + 1.0) * a.1
        + (t3 - 2.0 * t2 + t) * h * a.2
        + (-2.0 * t3 + 3.0 * t2) * b.1
        + (t3 - t2) * h * b.2;
    let dr = ((6.0 * t2 - 6.0 * t) * a.1
        + (3.0 * t2 - 4.0 * t + 1.0) * h * a.2
        + (-6.0 * t2 + 6.0 * t) * b.1
        + (3.0 * t2 - 2.0 * t) * h * b.2)
        / h;
    (r, dr)
}

/// `(R, R')` from a uniform table over `[0, 2π)` by cubic Hermite interpolation.
fn table_radius(values: &[(f64, f64)], theta: f64) -> (f64, f64) {
    let n = values.len();
    let step = TAU / n as f64;
    let x = theta.rem_euclid(TAU) / step;
    let i = (x.floor() as usize).min(n - 1);
    let (a, b) = (values[i], values[(i + 1) % n]);
    let th0 = i as f64 * step;
    hermite(
        (th0, a.0, a.1),
        (th0 + step, b.0, b.1),
        theta.rem_euclid(TAU),
    )
}

/// Start and end point of piece `k` (arcs run from the previous segment's end, or the
/// tangent point, to the next one).
fn piece_ends(piece: &Piece, pieces: &[Piece], k: usize) -> (Vector2<f64>, Vector2<f64>) {
    match *piece {
        Piece::Segment { a, b } => (a, b),
        Piece::Arc { .. } => {
            let n = pieces.len();
            let prev = pieces[(k + n - 1) % n];
            let next = pieces[(k + 1) % n];
            let start = match prev {
                Piece::Segment { b, .. } => b,
                Piece::Arc { .. } => arc_neighbour_end(pieces, k, false),
            };
            let end = match next {
                Piece::Segment { a, .. } => a,
                Piece::Arc { .. } => arc_neighbour_end(pieces, k, true),
            };
            (start, end)
        }
    }
}

/// Where two consecutive arcs meet (an edge fully consumed by its fillets): the tangent point
/// shared by both arcs lies on the line between their centres at `radius` from each.
fn arc_neighbour_end(pieces: &[Piece], k: usize, forward: bool) -> Vector2<f64> {
    let n = pieces.len();
    let other = if forward {
        pieces[(k + 1) % n]
    } else {
        pieces[(k + n - 1) % n]
    };
    match (pieces[k], other) {
        (
            Piece::Arc {
                centre: c1,
                radius: r1,
                ..
            },
            Piece::Arc { centre: c2, .. },
        ) => {
            let d = c2 - c1;
            let dist = d.norm();
            if dist == 0.0 {
                c1
            } else {
                c1 + d * (r1 / dist).min(1.0)
            }
        }
        _ => unreachable!("only called for two consecutive arcs"),
    }
}

/// Point and counter-clockwise unit tangent at parameter `s ∈ [0, 1]` of a piece.
fn piece_point(piece: &Piece, s: f64) -> (Vector2<f64>, Vector2<f64>) {
    match *piece {
        Piece::Segment { a, b } => (a + s * (b - a), (b - a).normalize()),
        Piece::Arc {
            centre,
            radius,
            convex,
            angles: (a0, a1),
        } => {
            let a = a0 + s * (a1 - a0);
            let p = centre + radius * dir(a);
            let t = if convex { left(dir(a)) } else { -left(dir(a)) };
            (p, t)
        }
    }
}

/// Start and end angle (about its centre) of the arc `pieces[k]`, increasing for convex arcs
/// (turning left) and decreasing for the others.
fn arc_angles(pieces: &[Piece], k: usize) -> (f64, f64) {
    let (start, end) = piece_ends(&pieces[k], pieces, k);
    let Piece::Arc { centre, convex, .. } = pieces[k] else {
        unreachable!("only called for arcs")
    };
    let a0 = (start - centre).y.atan2((start - centre).x);
    let mut a1 = (end - centre).y.atan2((end - centre).x);
    if convex {
        while a1 < a0 {
            a1 += TAU;
        }
    } else {
        while a1 > a0 {
            a1 -= TAU;
        }
    }
    (a0, a1)
}

/// `(R, R')` of a rounded polygon: find the piece whose angular span contains `θ` and
/// intersect the ray with it; `R' = −R (u⊥·n)/(u·n)` from the outward normal `n`.
fn polygon_radius(c: Vector2<f64>, pieces: &[Piece], starts: &[f64], theta: f64) -> (f64, f64) {
    let mut th = theta;
    let base = starts[0];
    th = base + (th - base).rem_euclid(TAU);
    let k = starts.partition_point(|&s| s <= th).saturating_sub(1);
    let u = dir(th);
    let (r, n) = match pieces[k] {
        Piece::Segment { a, b } => {
            let d = b - a;
            let r = cross(a - c, d) / cross(u, d);
            (r, Vector2::new(d.y, -d.x).normalize())
        }
        Piece::Arc {
            centre,
            radius,
            convex,
            ..
        } => {
            let w = c - centre;
            let uw = u.dot(&w);
            let disc = (uw * uw - w.norm_squared() + radius * radius)
                .max(0.0)
                .sqrt();
            let r = if convex { -uw + disc } else { -uw - disc };
            let p = c + r * u;
            let n = if convex {
                (p - centre) / radius
            } else {
                (centre - p) / radius
            };
            (r, n)
        }
    };
    (r, -r * left(u).dot(&n) / u.dot(&n))
}
