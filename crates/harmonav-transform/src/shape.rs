//! Star-shaped obstacle and workspace shapes: circle, ellipse, rounded polygon, Fourier star.
//!
//! Every shape is star-shaped about its [`StarShape::centre`] and is described by its *radial
//! function*: the boundary point in direction `θ` is `centre + R(θ)(cos θ, sin θ)`. The
//! navigation transformation needs `R(θ)` and `R'(θ)` (both exact, closed form or analytic ray
//! casts); signed distances for the automatic band widths come from parry2d-f64 point queries
//! on a dense outline (exact for circles); `rho_min`, the minimum radius of curvature of the
//! convex parts of the boundary, feeds `d_min` (eq. `dmin`).

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::query::{PointQuery, Ray, RayCast};
use parry2d_f64::shape::Polyline;

use crate::error::ShapeError;

/// Number of outline vertices (evenly spaced in arc length) for parry distance queries on
/// curved shapes.
const OUTLINE: usize = 512;

/// A star-shaped region of the plane with its radial function (see the module docs).
#[derive(Clone, Debug)]
pub struct StarShape {
    kind: Kind,
    centre: Vector2<f64>,
    r_min: f64,
    r_max: f64,
    rho_min: f64,
    outline: Arc<Polyline>,
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
        harmonics: Vec<(f64, f64, f64)>,
    },
}

/// A piece of a rounded polygon's boundary, traversed counter-clockwise.
#[derive(Clone, Copy, Debug)]
enum Piece {
    Segment {
        a: Vector2<f64>,
        b: Vector2<f64>,
    },
    /// A fillet: `convex` arcs (centre inside the shape) turn left, the others right.
    Arc {
        centre: Vector2<f64>,
        radius: f64,
        convex: bool,
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
        Ok(Self::build(Kind::Circle { r }, centre, r, r, r))
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
        let angle = finite(angle, "angle_deg")?;
        let (lo, hi) = (a.min(b), a.max(b));
        Ok(Self::build(
            Kind::Ellipse {
                a,
                b,
                axis: dir(angle),
            },
            centre,
            lo,
            hi,
            lo * lo / hi,
        ))
    }

    /// A Fourier star `R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)` about `centre`, harmonics
    /// given as `(n, a_n, b_n)` with `n ≥ 1`. Rejected if `R ≤ 0` anywhere (checked on a dense
    /// grid with a margin bounding the variation between grid points).
    pub fn fourier_star(
        centre: Vector2<f64>,
        r0: f64,
        harmonics: &[(u32, f64, f64)],
    ) -> Result<Self, ShapeError> {
        let centre = finite_point(centre, "center")?;
        let r0 = positive(r0, "radius")?;
        let mut h = Vec::with_capacity(harmonics.len());
        for &(n, a, b) in harmonics {
            if n == 0 {
                return Err(ShapeError::Invalid {
                    field: "harmonics",
                    problem: "harmonic numbers n must be ≥ 1".into(),
                });
            }
            h.push((n as f64, finite(a, "harmonics")?, finite(b, "harmonics")?));
        }
        h.sort_by(|x, y| x.0.total_cmp(&y.0));
        let kind = Kind::Star { r0, harmonics: h };
        let samples = 8192;
        let step = TAU / samples as f64;
        let (mut lo, mut hi, mut slope, mut rho) = (f64::INFINITY, 0.0f64, 0.0f64, f64::INFINITY);
        for i in 0..samples {
            let th = i as f64 * step;
            let (r, dr, ddr) = star_radius(r0, kind_harmonics(&kind), dir(th));
            lo = lo.min(r);
            hi = hi.max(r);
            slope = slope.max(dr.abs());
            let den = r * r + 2.0 * dr * dr - r * ddr;
            if den > 0.0 {
                rho = rho.min((r * r + dr * dr).powf(1.5) / den);
            }
        }
        let margin = slope * step; // |R(θ) − R(θ_i)| ≤ max|R'|·Δθ between grid points
        if lo - margin <= 0.0 {
            return Err(ShapeError::Invalid {
                field: "harmonics",
                problem: format!(
                    "the radius R(θ) reaches {lo:.3} ≤ 0: the star is not a valid star-shaped region"
                ),
            });
        }
        Ok(Self::build(kind, centre, lo - margin, hi + margin, rho))
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
        // Strict star-shapedness: the boundary turns counter-clockwise as seen from the centre.
        let mut starts = Vec::with_capacity(pieces.len());
        let mut rho_max = 0.0f64;
        for (k, piece) in pieces.iter().enumerate() {
            let (start, _) = piece_ends(piece, &pieces, k);
            for s in 0..=16 {
                let (p, tangent) = piece_point(piece, &pieces, k, s as f64 / 16.0);
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
        let kind = Kind::Polygon { pieces, starts };
        let mut shape = Self::build(kind, centre, 0.0, rho_max * (1.0 + 1e-12), rc);
        shape.r_min = (0..4096)
            .map(|i| shape.radius(i as f64 * TAU / 4096.0).0)
            .fold(f64::INFINITY, f64::min)
            * (1.0 - 1e-3);
        Ok(shape)
    }

    fn build(kind: Kind, centre: Vector2<f64>, r_min: f64, r_max: f64, rho_min: f64) -> Self {
        let mut shape = Self {
            kind,
            centre,
            r_min,
            r_max,
            rho_min,
            outline: Arc::new(Polyline::new(Vec::new(), None)),
        };
        let pts: Vec<PVector> = match &shape.kind {
            // Segments are exact with their end points; arcs get 32 vertices each.
            Kind::Polygon { pieces, .. } => pieces
                .iter()
                .enumerate()
                .flat_map(|(k, piece)| {
                    let steps = if matches!(piece, Piece::Arc { .. }) {
                        32
                    } else {
                        1
                    };
                    (0..steps)
                        .map(move |i| piece_point(piece, pieces, k, i as f64 / steps as f64).0)
                })
                .map(|p| PVector::new(p.x, p.y))
                .collect(),
            // Curved shapes: OUTLINE points evenly spaced in arc length (from a dense angular
            // grid), so sharply curved tips are sampled as finely as flat sides.
            _ => {
                let dense = 4 * OUTLINE;
                let p: Vec<Vector2<f64>> = (0..=dense)
                    .map(|i| shape.boundary_point(TAU * i as f64 / dense as f64))
                    .collect();
                let mut arc = vec![0.0; dense + 1];
                for i in 1..=dense {
                    arc[i] = arc[i - 1] + (p[i] - p[i - 1]).norm();
                }
                let total = arc[dense];
                let mut j = 0;
                (0..OUTLINE)
                    .map(|k| {
                        let target = total * k as f64 / OUTLINE as f64;
                        while arc[j + 1] < target {
                            j += 1;
                        }
                        let t = (target - arc[j]) / (arc[j + 1] - arc[j]).max(f64::MIN_POSITIVE);
                        let th = TAU * (j as f64 + t) / dense as f64;
                        let q = shape.boundary_point(th);
                        PVector::new(q.x, q.y)
                    })
                    .collect()
            }
        };
        let n = pts.len() as u32;
        let idx = (0..n).map(|i| [i, (i + 1) % n]).collect();
        shape.outline = Arc::new(Polyline::new(pts, Some(idx)));
        shape
    }

    /// The centre about which the shape is star-shaped (the obstacle's point `P_i`).
    pub fn centre(&self) -> Vector2<f64> {
        self.centre
    }

    /// Lower and upper bounds of `R(θ)` over all directions (exact for circles and ellipses).
    pub fn radius_bounds(&self) -> (f64, f64) {
        (self.r_min, self.r_max)
    }

    /// Minimum radius of curvature of the convex parts of the boundary (for eq. `dmin`).
    pub fn rho_min(&self) -> f64 {
        self.rho_min
    }

    /// The radial function `(R(θ), R'(θ))` for the direction `θ` (radians, any value).
    pub fn radius(&self, theta: f64) -> (f64, f64) {
        self.radius_along(dir(theta))
    }

    /// The radial function `(R(θ), R'(θ))` for the unit direction `u = (cos θ, sin θ)`.
    ///
    /// The hot path of `Phi`: circles, ellipses and Fourier stars need no trigonometric call
    /// (`cos nθ + i sin nθ = (u_x + i u_y)^n`); rounded polygons take one `atan2`.
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
    /// Hermite interpolation (`C¹`). `rho_min` grows by `r`.
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
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..4 * grid {
            let rr = table_radius(&values, TAU * i as f64 / (4 * grid) as f64).0;
            lo = lo.min(rr);
            hi = hi.max(rr);
        }
        if lo <= 0.0 {
            return Err(not_star());
        }
        let rho = (self.rho_min + r).max(f64::MIN_POSITIVE);
        Ok(Self::build(
            Kind::Table { values },
            self.centre,
            lo * (1.0 - 1e-6),
            hi * (1.0 + 1e-6),
            rho,
        ))
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

    /// Signed distance to the boundary: negative inside. Exact for circles; otherwise a parry
    /// point query on a 512-vertex outline (evenly spaced in arc length), refined by a
    /// golden-section search on the exact boundary curve (to ~1e-12; about 2 µs), with the sign from the exact [`Self::contains`].
    pub fn signed_distance(&self, x: Vector2<f64>) -> f64 {
        if let Kind::Circle { r } = self.kind {
            return (x - self.centre).norm() - r;
        }
        // parry finds the nearest outline point; a golden-section search for the nearest point
        // of the exact boundary curve p(θ) = c + R(θ)u(θ) around it removes the chord error.
        let proj = self
            .outline
            .project_local_point(PVector::new(x.x, x.y), false)
            .point;
        let near = Vector2::new(proj.x, proj.y);
        let coarse = (near - x).norm();
        let start = near - self.centre;
        let th0 = start.y.atan2(start.x);
        let th = golden_min(
            |th| (self.boundary_point(th) - x).norm_squared(),
            th0 - 0.05,
            th0 + 0.05,
        );
        let fine = (self.boundary_point(th) - x).norm();
        // Keep the refined value unless the search left the right stretch of boundary.
        let d = if fine <= coarse + 1e-3 * (1.0 + coarse) {
            fine
        } else {
            coarse
        };
        if self.contains(x) { -d } else { d }
    }

    /// The outline vertices used for distance queries (counter-clockwise, closed).
    pub fn outline(&self) -> impl Iterator<Item = Vector2<f64>> + '_ {
        self.outline
            .vertices()
            .iter()
            .map(|p| Vector2::new(p.x, p.y))
    }

    /// Smallest signed distance from any outline point of `self` to `other` (negative when
    /// they overlap): the distance between two obstacles, one side sampled.
    pub fn distance_to(&self, other: &StarShape) -> f64 {
        let a = self
            .outline()
            .map(|p| other.coarse_signed_distance(p))
            .fold(f64::INFINITY, f64::min);
        let b = other
            .outline()
            .map(|p| self.coarse_signed_distance(p))
            .fold(f64::INFINITY, f64::min);
        a.min(b)
    }

    /// Smallest distance from the outline of `self` to the boundary of the region `outer`,
    /// positive when `self` lies inside `outer` (negative when it crosses or leaves it).
    pub fn clearance_inside(&self, outer: &StarShape) -> f64 {
        self.outline()
            .map(|p| -outer.coarse_signed_distance(p))
            .fold(f64::INFINITY, f64::min)
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
        // Larger than the outline's chord error (~3e-4 of the size at curvature radius 0.05).
        let slack = 4e-3 * self.r_max;
        let coarse = self.outline.cast_local_ray(
            &Ray::new(PVector::new(origin.x, origin.y), PVector::new(dir.x, dir.y)),
            max + slack,
            false,
        );
        // parry's hit on the outline is within the chord error of the true one: bisect on the
        // exact containment test in a bracket around it. (A part of the shape thinner than the
        // outline's chord error, ~1e-5 of its size, can be missed.)
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
    /// boundary points where `|p(θ) − x|` has a local minimum, found on the outline and
    /// refined on the exact curve. The global minimum (the nearest point) is among them.
    pub fn distance_minima(&self, x: Vector2<f64>) -> impl Iterator<Item = Vector2<f64>> + '_ {
        let n = self.outline.vertices().len();
        let d = move |i: usize| {
            let v = self.outline.vertices()[i % n];
            (Vector2::new(v.x, v.y) - x).norm_squared()
        };
        (0..n).filter_map(move |i| {
            let (prev, here, next) = (d(i + n - 1), d(i), d(i + 1));
            if here > prev || here > next {
                return None;
            }
            let v = self.outline.vertices()[i];
            let w = Vector2::new(v.x, v.y) - self.centre;
            let th0 = w.y.atan2(w.x);
            // The minimum lies within the neighbouring outline spacing: search ±2 spacings.
            let spread = 4.0 * (TAU / n as f64).max(0.02);
            Some(self.boundary_point(golden_min(
                |th| (self.boundary_point(th) - x).norm_squared(),
                th0 - spread,
                th0 + spread,
            )))
        })
    }

    /// [`Self::signed_distance`] without the refinement: the outline's chord error (~1e-5 of
    /// the size) remains. For the band widths (where the factor 0.45 absorbs it) and sampling.
    pub fn coarse_signed_distance(&self, x: Vector2<f64>) -> f64 {
        if let Kind::Circle { r } = self.kind {
            return (x - self.centre).norm() - r;
        }
        let d = self
            .outline
            .distance_to_local_point(PVector::new(x.x, x.y), false);
        if self.contains(x) { -d } else { d }
    }
}

fn kind_harmonics(kind: &Kind) -> &[(f64, f64, f64)] {
    match kind {
        Kind::Star { harmonics, .. } => harmonics,
        _ => &[],
    }
}

/// `(R, R', R'')` of a Fourier star in the unit direction `u`, with `cos nθ + i sin nθ`
/// as the `n`-th power of `u_x + i u_y` (harmonics sorted by `n`).
fn star_radius(r0: f64, harmonics: &[(f64, f64, f64)], u: Vector2<f64>) -> (f64, f64, f64) {
    let (mut r, mut dr, mut ddr) = (r0, 0.0, 0.0);
    let (mut power, mut c, mut s) = (0.0, 1.0, 0.0);
    for &(n, a, b) in harmonics {
        while power < n {
            (c, s) = (c * u.x - s * u.y, c * u.y + s * u.x);
            power += 1.0;
        }
        r += a * c + b * s;
        dr += n * (b * c - a * s);
        ddr -= n * n * (a * c + b * s);
    }
    (r, dr, ddr)
}

/// Golden-section search for the minimum of a unimodal `f` on `[lo, hi]` (to ~1e-13).
fn golden_min(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
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

/// Point and counter-clockwise unit tangent at parameter `s ∈ [0, 1]` of piece `k`.
fn piece_point(piece: &Piece, pieces: &[Piece], k: usize, s: f64) -> (Vector2<f64>, Vector2<f64>) {
    let (start, end) = piece_ends(piece, pieces, k);
    match *piece {
        Piece::Segment { a, b } => (a + s * (b - a), (b - a).normalize()),
        Piece::Arc {
            centre,
            radius,
            convex,
        } => {
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
            let a = a0 + s * (a1 - a0);
            let p = centre + radius * dir(a);
            let t = if convex { left(dir(a)) } else { -left(dir(a)) };
            (p, t)
        }
    }
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
