//! The slide level `c_s`: where on `∂W_δ` the hold's projected descent may rest, certified by
//! interval bounds on the direction of `−∇Θ` over a covering of `∂W_δ` (docs/maths.md §13.9).
//!
//! The projected descent `ẋ = u − (u·n)₊ n`, `u = −c∇Θ`, rests at a point `p` of `∂W_δ` only
//! where `−∇Θ(p)` lies in the normal cone `N(p)` of `W_δ` (the directions from `p` to its nearest
//! points of `∂W_s`). A cell `B(x, ρ)` is *free* when the arc of directions that holds
//! `−∇Θ(B)` misses the arc that holds every `N(p)`, `p ∈ B ∩ ∂W_δ`:
//!
//! ```text
//! −∇Θ(y) ∝ −J_H(y)ᵀ · e^{iφ} · (ν'·g_ρ e_ρ + (ν/t)·g_θ e_θ)                      (eq. slidedir)
//!   g = ∇phi_k(S(z)) = 2/conj(S(z) − P_d) − (2/k) Σ_i 1/conj(S(z) − P_i),   z = M_a(H(y))
//!   φ = −arg M_a'(H(y)) = 2 arg(1 − ā H(y)),   t = |z|,   ν = ν(t) the stretch of S
//! ```
//!
//! each factor enclosed over the cell: `H(B) ⊂ B(H(x), r)` and the rows of `J_H`
//! ([`harmonav_harmonic::Enclosure`]), `M_a` of that disc exactly, `S`'s `ν'` and `ν/t` by
//! monotone pieces, `1/conj(h − p)` of a disc exactly (an inversion), the rest in interval
//! arithmetic (certified to rounding). Positive factors (`σ'`, `|M_a'|`) do not change a
//! direction and are left out. `c_s` is the least bound of `phi_k` over the cells that stay not
//! free after splitting (`+∞` when there are none); cells are taken least bound first, and a cell
//! whose bound is at or above the current `c_s` cannot lower it and is dropped.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::f64::consts::PI;

use harmonav_harmonic::Enclosure;
use harmonav_transform::smooth::beta;
use nalgebra::{Matrix2, Vector2};
use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::Vector as PVector;

use crate::compose::mobius_disc;
use crate::level::LevelOptions;
use crate::theta::FloorField;

/// A closed interval of reals, rounded to nearest (certified to rounding, as §13.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Iv {
    lo: f64,
    hi: f64,
}

impl Iv {
    fn new(lo: f64, hi: f64) -> Self {
        Self { lo, hi }
    }

    fn around(c: f64, r: f64) -> Self {
        Self::new(c - r, c + r)
    }

    fn add(self, o: Self) -> Self {
        Self::new(self.lo + o.lo, self.hi + o.hi)
    }

    fn neg(self) -> Self {
        Self::new(-self.hi, -self.lo)
    }

    fn sub(self, o: Self) -> Self {
        self.add(o.neg())
    }

    fn mul(self, o: Self) -> Self {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        // 0·∞ is NaN: an unbounded factor times a zero bound is unbounded.
        if p.iter().any(|v| v.is_nan()) {
            return Self::new(f64::NEG_INFINITY, f64::INFINITY);
        }
        Self::new(
            p.iter().copied().fold(f64::INFINITY, f64::min),
            p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// Whether the interval holds 0 (or is not a finite interval).
    fn meets_zero(self) -> bool {
        !(self.lo.is_finite() && self.hi.is_finite()) || (self.lo <= 0.0 && self.hi >= 0.0)
    }

    /// `cos` over `[c − w, c + w]`.
    fn cos_of(c: f64, w: f64) -> Self {
        if w.is_nan() || w >= PI {
            return Self::new(-1.0, 1.0);
        }
        let (a, b) = ((c - w).cos(), (c + w).cos());
        let (mut lo, mut hi) = (a.min(b), a.max(b));
        // A maximum at 2πm or a minimum at π + 2πm inside the interval.
        if ((c + w) / (2.0 * PI)).floor() > ((c - w) / (2.0 * PI)).ceil() - 1.0 {
            hi = 1.0;
        }
        if ((c + w - PI) / (2.0 * PI)).floor() > ((c - w - PI) / (2.0 * PI)).ceil() - 1.0 {
            lo = -1.0;
        }
        Self::new(lo, hi)
    }

    /// `sin` over `[c − w, c + w]`.
    fn sin_of(c: f64, w: f64) -> Self {
        Self::cos_of(c - 0.5 * PI, w)
    }
}

/// An arc of directions `[mid − half, mid + half]`, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionArc {
    /// Its middle direction.
    pub mid: f64,
    /// Its half opening (below `π/2` for a descent arc, `π` for a hull of normals).
    pub half: f64,
}

/// `a` wrapped into `(−π, π]`.
fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

impl DirectionArc {
    /// The arc of directions of a box `X × Y` that does not hold 0 (a convex set seen from
    /// outside: its corners give the extreme directions); `None` if it may hold 0.
    fn of_box(x: Iv, y: Iv) -> Option<Self> {
        if x.meets_zero() && y.meets_zero() {
            return None;
        }
        if ![x.lo, x.hi, y.lo, y.hi].iter().all(|v| v.is_finite()) {
            return None;
        }
        let mid = (0.5 * (y.lo + y.hi)).atan2(0.5 * (x.lo + x.hi));
        let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
        for (cx, cy) in [(x.lo, y.lo), (x.lo, y.hi), (x.hi, y.lo), (x.hi, y.hi)] {
            let d = wrap(cy.atan2(cx) - mid);
            lo = lo.min(d);
            hi = hi.max(d);
        }
        let mid = mid + 0.5 * (lo + hi);
        let half = 0.5 * (hi - lo);
        (half < 0.5 * PI).then_some(Self { mid, half })
    }

    /// Whether the direction of `v` lies in the arc (to `1e-12` rad).
    #[must_use]
    pub fn contains(&self, v: Vector2<f64>) -> bool {
        wrap(v.y.atan2(v.x) - self.mid).abs() <= self.half + 1e-12
    }

    /// Whether two arcs are disjoint (strictly).
    fn misses(&self, o: &Self) -> bool {
        self.half + o.half < PI && wrap(self.mid - o.mid).abs() > self.half + o.half
    }

    /// The least arc holding all of `arcs` (`None` if it spans `π` or more, or none given).
    fn hull(arcs: &[Self]) -> Option<Self> {
        let first = arcs.first()?;
        let (mut lo, mut hi) = (-first.half, first.half);
        for a in &arcs[1..] {
            let d = wrap(a.mid - first.mid);
            lo = lo.min(d - a.half);
            hi = hi.max(d + a.half);
        }
        (hi - lo < PI).then_some(Self {
            mid: first.mid + 0.5 * (lo + hi),
            half: 0.5 * (hi - lo),
        })
    }
}

/// `L'(w) = e^{−|w|}/(1 + e^{−|w|})²`, the logistic's slope (even, falling in `|w|`).
fn logistic_slope(w: f64) -> f64 {
    let e = (-w.abs()).exp();
    e / ((1.0 + e) * (1.0 + e))
}

/// `(ν', ν/t)` of `S`'s stretch over `t ∈ [t1, t2]` (radius in the disk), by monotone pieces of
///
/// ```text
/// s = (t − 1 + ε_0)/ε_0,   ν = t + A·β(s)·s/(1 − s),
/// ν' = 1 + (A/ε_0)·(β'(s)·s/(1 − s) + β(s)/(1 − s)²),   β'(s) = L'(w)·(1/s² + 1/(1 − s)²)
/// ```
///
/// with `w = 1/(1 − s) − 1/s` increasing, `β` increasing, `L'` even and falling in `|w|`
/// (`radial::outer_map` about the unit circle, `harmonav_transform::smooth::beta`). The identity
/// (`1, 1`) below the band; `None` where the interval reaches the band's start or its end
/// (`β'`'s bound has `1/s²`; `ν` is infinite at `s = 1`).
fn stretch_slopes(t1: f64, t2: f64, eps0: f64, gain: f64) -> Option<(Iv, Iv)> {
    let s = |t: f64| (t - 1.0 + eps0) / eps0;
    let (s1, s2) = (s(t1), s(t2));
    if s2 <= 0.0 {
        return Some((Iv::new(1.0, 1.0), Iv::new(1.0, 1.0)));
    }
    if !(s1 > 0.0 && s2 < 1.0 && t1 > 0.0) {
        return None;
    }
    let (b1, b2) = (beta(s1).0, beta(s2).0);
    let w = |s: f64| 1.0 / (1.0 - s) - 1.0 / s;
    let (w1, w2) = (w(s1), w(s2));
    let slope_hi = if w1 <= 0.0 && w2 >= 0.0 {
        0.25
    } else {
        logistic_slope(w1).max(logistic_slope(w2))
    };
    let slope_lo = logistic_slope(w1).min(logistic_slope(w2));
    let factor = Iv::new(
        1.0 / (s2 * s2) + 1.0 / ((1.0 - s1) * (1.0 - s1)),
        1.0 / (s1 * s1) + 1.0 / ((1.0 - s2) * (1.0 - s2)),
    );
    let dbeta = Iv::new(slope_lo, slope_hi).mul(factor);
    let odds = Iv::new(s1 / (1.0 - s1), s2 / (1.0 - s2));
    let inv2 = Iv::new(
        1.0 / ((1.0 - s1) * (1.0 - s1)),
        1.0 / ((1.0 - s2) * (1.0 - s2)),
    );
    let g = gain / eps0;
    let bracket = dbeta.mul(odds).add(Iv::new(b1, b2).mul(inv2));
    let nu_rho = Iv::new(1.0 + g * bracket.lo, 1.0 + g * bracket.hi);
    let nu_t = Iv::new(
        1.0 + gain * b1 * s1 / ((1.0 - s1) * t2),
        1.0 + gain * b2 * s2 / ((1.0 - s2) * t1),
    );
    Some((nu_rho, nu_t))
}

/// What [`FloorField::certify_slide_level`] found, in `phi_k` (log space, as
/// [`crate::LayerLevel`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlideLevel {
    /// `c_s` in `phi_k`: a lower bound of `phi_k ∘ Phi` over the cells of `∂W_δ` where the
    /// projected descent may rest (`−∇Θ` not proven outside the normal cone); `+∞` when every
    /// cell was proven free of rest points, `−∞` when some cell could not be bounded.
    pub phi_certified: f64,
    /// The centre of the cell that set `phi_certified`, if any: where a rest point may be.
    pub at: Option<Vector2<f64>>,
    /// Cells evaluated.
    pub evaluations: usize,
    /// Cells left not free at the depth or budget limit (each bounds `phi_certified`).
    pub unresolved: usize,
    /// `true` when not computed (`phi_certified` is `−∞`, and `c_δ` alone certifies): the
    /// first covering alone exceeded [`SLIDE_WORK`], or the field has a sensed obstacle.
    pub skipped: bool,
}

/// The most work of [`FloorField::certify_slide_level`], in element evaluations (cells ×
/// boundary elements; measured 1.6·10⁶ per second on one core, so about a minute): beyond it
/// the cells stop splitting, and a first covering larger than it is not evaluated at all.
pub const SLIDE_WORK: f64 = 1e8;

/// A cell of the covering, ordered by the bound of its parent (least first).
struct Cell {
    key: f64,
    centre: Vector2<f64>,
    half: f64,
    depth: u32,
}

impl PartialEq for Cell {
    fn eq(&self, o: &Self) -> bool {
        self.key.total_cmp(&o.key) == Ordering::Equal
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cell {
    fn cmp(&self, o: &Self) -> Ordering {
        // BinaryHeap pops the greatest: the least key first.
        o.key.total_cmp(&self.key)
    }
}

impl FloorField {
    /// The arc that holds every outward normal of `W_δ` at the points of `∂W_δ` in `B(x, ρ)`:
    /// each is a direction from such a point `p` to a nearest point `q` of `∂W_s`, `|q − p| = δ`,
    /// on a segment within `δ + ρ` of `x`: its normal, when `p` may project inside it, or the
    /// directions to an end `v` from the points of `B(x, ρ)` at `δ` from it, within
    /// `acos((δ² + |v − x|² − ρ²)/(2δ|v − x|))` of `v − x` (the law of cosines). The hull of
    /// them also holds the normal cone of a corner. `None` when it cannot be told (a segment
    /// whose line passes within `ρ` of `x`, or a hull of `π` or more).
    #[must_use]
    pub fn normal_arc(&self, x: Vector2<f64>, rho: f64) -> Option<DirectionArc> {
        let floor = self.floor();
        let delta = floor.delta();
        let mut arcs: Vec<DirectionArc> = Vec::new();
        let reach = delta + rho;
        let boundary = floor.shrunk_boundary();
        let query = Aabb::new(
            PVector::new(x.x - reach, x.y - reach),
            PVector::new(x.x + reach, x.y + reach),
        );
        for i in boundary.bvh().intersect_aabb(&query) {
            let seg = boundary.segment(i);
            let (a, b) = (
                Vector2::new(seg.a.x, seg.a.y),
                Vector2::new(seg.b.x, seg.b.y),
            );
            let e = b - a;
            let len = e.norm();
            if len.partial_cmp(&0.0) != Some(Ordering::Greater) {
                continue;
            }
            let tau = e / len;
            let along = (x - a).dot(&tau);
            let closest = a + tau * along.clamp(0.0, len);
            if (x - closest).norm() > reach {
                continue;
            }
            let nu = Vector2::new(-tau.y, tau.x);
            let off = (x - a).dot(&nu);
            if along + rho > 0.0 && along - rho < len && (off.abs() - delta).abs() <= rho {
                if off.abs() <= rho {
                    return None;
                }
                let to_line = -nu * off.signum();
                arcs.push(DirectionArc {
                    mid: to_line.y.atan2(to_line.x),
                    half: 0.0,
                });
            }
            for v in [a, b] {
                let w = v - x;
                let d = w.norm();
                if (d - delta).abs() > rho {
                    continue;
                }
                if d <= rho {
                    return None;
                }
                let cos = (delta * delta + d * d - rho * rho) / (2.0 * delta * d);
                arcs.push(DirectionArc {
                    mid: w.y.atan2(w.x),
                    half: cos.clamp(-1.0, 1.0).acos(),
                });
            }
        }
        DirectionArc::hull(&arcs)
    }

    /// An arc that holds the direction of `−∇Θ(y)` for every `y ∈ B(x, ρ)`: that of a box
    /// `X × Y` holding a positive multiple of it (eq. slidedir; the walls' point world only:
    /// `None` with a sensed obstacle, where a factor has no finite bound, or where the box may
    /// hold 0).
    #[must_use]
    pub fn descent_arc(&self, x: Vector2<f64>, rho: f64) -> Option<DirectionArc> {
        let e = self.floor().enclosure(x, rho).ok()?;
        let (bx, by) = self.descent_box_of(&e)?;
        DirectionArc::of_box(bx, by)
    }

    /// The box of [`FloorField::descent_arc`] from `H`'s enclosure of the disc.
    fn descent_box_of(&self, e: &Enclosure) -> Option<(Iv, Iv)> {
        let transform = self.transform();
        if transform.obstacles().next().is_some() {
            return None;
        }
        let (w0, r) = (e.eval.value, e.radius);
        if (w0.norm() + r).partial_cmp(&1.0) != Some(Ordering::Less) {
            return None;
        }
        let a = transform.recentre();
        let (zc, rz) = mobius_disc(a, w0, r);
        let t = zc.norm();
        if !(t + rz < 1.0 && rz < t) {
            return None;
        }
        let theta = zc.y.atan2(zc.x);
        let half = (rz / t).asin();
        let (eps0, gain) = transform.outer_band();
        let (nu_rho, nu_t) = stretch_slopes(t - rz, t + rz, eps0, gain)?;
        // The sector S(Z) in a disc: |ρe^{iψ} − ρ_c e^{iθ}| ≤ |ρ − ρ_c| + ρ|ψ − θ|.
        let nu = |t: f64| {
            if t <= 1.0 - eps0 {
                t
            } else {
                harmonav_transform::radial::outer_map(t, 1.0, 0.0, eps0, gain).nu
            }
        };
        let (r1, r2) = (nu((t - rz).max(0.0)), nu(t + rz));
        let rc = 0.5 * (r1 + r2);
        let hc = Vector2::new(rc * theta.cos(), rc * theta.sin());
        let hr = 0.5 * (r2 - r1) + r2 * half;
        if !(hr.is_finite() && hc.x.is_finite() && hc.y.is_finite()) {
            return None;
        }
        // g = Σ weight·2(h − p)/|h − p|²; over h ∈ B(hc, hr), 2(h − p)/|h − p|² = 2/conj(h − p)
        // lies in B(2q/(|q|² − hr²), 2hr/(|q|² − hr²)), q = hc − p, |q| > hr (an inversion).
        let world = self.point_world();
        let (mut gc, mut gr) = (Vector2::zeros(), 0.0);
        let mut term = |p: Vector2<f64>, weight: f64| -> Option<()> {
            let q = hc - p;
            let den = q.norm_squared() - hr * hr;
            if den.partial_cmp(&0.0) != Some(Ordering::Greater) {
                return None;
            }
            gc += q * (2.0 * weight / den);
            gr += 2.0 * weight.abs() * hr / den;
            Some(())
        };
        term(world.destination(), 1.0)?;
        let w = -1.0 / world.k();
        for &p in world.obstacles() {
            term(p, w)?;
        }
        let (gx, gy) = (Iv::around(gc.x, gr), Iv::around(gc.y, gr));
        let (cos, sin) = (Iv::cos_of(theta, half), Iv::sin_of(theta, half));
        let g_rho = gx.mul(cos).add(gy.mul(sin));
        let g_theta = gy.mul(cos).sub(gx.mul(sin));
        let radial = nu_rho.mul(g_rho);
        let tangential = nu_t.mul(g_theta);
        let mut big_x = radial.mul(cos).sub(tangential.mul(sin));
        let mut big_y = radial.mul(sin).add(tangential.mul(cos));
        // conj(M_a'(w)) = |M_a'|·e^{iφ}, φ = 2 arg(1 − ā w), w ∈ B(w0, r).
        if a != Vector2::zeros() {
            let q = Vector2::new(1.0 - a.dot(&w0), -(a.x * w0.y - a.y * w0.x));
            let spread = a.norm() * r;
            if spread.partial_cmp(&q.norm()) != Some(Ordering::Less) {
                return None;
            }
            let phi = 2.0 * q.y.atan2(q.x);
            let phi_half = 2.0 * (spread / q.norm()).asin();
            let (c, s) = (Iv::cos_of(phi, phi_half), Iv::sin_of(phi, phi_half));
            let (nx, ny) = (
                big_x.mul(c).sub(big_y.mul(s)),
                big_x.mul(s).add(big_y.mul(c)),
            );
            big_x = nx;
            big_y = ny;
        }
        // ∇Θ ∝ J_Hᵀ G with the rows of J_H each within its radius of J_H(x).
        let j: Matrix2<f64> = e.eval.jacobian;
        let [eu, ev] = e.gradient_radius;
        let (ux, uy) = (Iv::around(j[(0, 0)], eu), Iv::around(j[(0, 1)], eu));
        let (vx, vy) = (Iv::around(j[(1, 0)], ev), Iv::around(j[(1, 1)], ev));
        let grad_x = ux.mul(big_x).add(vx.mul(big_y));
        let grad_y = uy.mul(big_x).add(vy.mul(big_y));
        Some((grad_x.neg(), grad_y.neg()))
    }

    /// Whether the projected descent is proven not to rest in `B(x, ρ) ∩ ∂W_δ`: the arc of
    /// [`FloorField::descent_arc`] misses [`FloorField::normal_arc`].
    #[must_use]
    pub fn slide_free(&self, x: Vector2<f64>, rho: f64) -> bool {
        match self.floor().enclosure(x, rho) {
            Ok(e) => self.slide_free_of(x, rho, &e),
            Err(_) => false,
        }
    }

    /// [`FloorField::slide_free`] from `H`'s enclosure of the disc.
    fn slide_free_of(&self, x: Vector2<f64>, rho: f64, e: &Enclosure) -> bool {
        let Some(normals) = self.normal_arc(x, rho) else {
            return false;
        };
        self.descent_box_of(e)
            .and_then(|(bx, by)| DirectionArc::of_box(bx, by))
            .is_some_and(|d| d.misses(&normals))
    }

    /// `c_s` certified (module docs, docs/maths.md §13.9): the least bound of `phi_k ∘ Phi`
    /// over the cells of a covering of `∂W_δ` where the projected descent may rest. The cells
    /// start on the grid of [`FloorField::certify_layer_level`] (half-diagonal `δ/3`), are kept
    /// while they may meet `∂W_δ`, and one not proven free is split in four up to
    /// `options.max_depth` and `options.max_evaluations` (and [`SLIDE_WORK`]). The walls' field
    /// only: with a sensed obstacle it is not run ([`SlideLevel::skipped`]).
    #[must_use]
    pub fn certify_slide_level(&self, options: &LevelOptions) -> SlideLevel {
        let floor = self.floor();
        let delta = floor.delta();
        let (lo, hi) = floor.map().domain().bounding_box();
        let w0 = delta / (3.0 * std::f64::consts::SQRT_2);
        let nx = ((hi.x - lo.x) / (2.0 * w0)).ceil().max(1.0) as usize;
        let ny = ((hi.y - lo.y) / (2.0 * w0)).ceil().max(1.0) as usize;
        let mut heap = BinaryHeap::new();
        for i in 0..nx {
            for j in 0..ny {
                let centre = lo + Vector2::new(2.0 * i as f64 + 1.0, 2.0 * j as f64 + 1.0) * w0;
                let rho = w0 * std::f64::consts::SQRT_2;
                let sd = floor.signed_distance(centre);
                // sd is 1-Lipschitz: a cell with |sd(c) − δ| > ρ does not meet ∂W_δ.
                if sd.is_nan() || (sd - delta).abs() > rho {
                    continue;
                }
                heap.push(Cell {
                    key: f64::NEG_INFINITY,
                    centre,
                    half: w0,
                    depth: 0,
                });
            }
        }
        let elements = floor.map().elements().len().max(1) as f64;
        let most = options
            .max_evaluations
            .min((SLIDE_WORK / elements) as usize);
        let mut out = SlideLevel {
            phi_certified: f64::INFINITY,
            at: None,
            evaluations: 0,
            unresolved: 0,
            skipped: heap.len() > most,
        };
        // With a sensed obstacle the walls' covering proves nothing (module docs): not run.
        if out.skipped || self.transform().obstacles().next().is_some() {
            out.skipped = true;
            out.phi_certified = f64::NEG_INFINITY;
            return out;
        }
        while let Some(cell) = heap.pop() {
            let rho = cell.half * std::f64::consts::SQRT_2;
            let sd = floor.signed_distance(cell.centre);
            if sd.is_nan() || (sd - delta).abs() > rho {
                continue;
            }
            out.evaluations += 1;
            let e = self.floor().enclosure(cell.centre, rho).ok();
            let phi = match e.as_ref() {
                Some(e) => self
                    .transform()
                    .sector_of(e)
                    .map_or(f64::NEG_INFINITY, |a| self.phi_lower(&a)),
                None => f64::NEG_INFINITY,
            };
            // A cell whose bound is at or above c_s cannot lower it.
            if phi >= out.phi_certified
                || e.is_some_and(|e| self.slide_free_of(cell.centre, rho, &e))
            {
                continue;
            }
            if cell.depth < options.max_depth && out.evaluations < most {
                let h = cell.half / 2.0;
                for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                    heap.push(Cell {
                        key: phi,
                        centre: cell.centre + Vector2::new(sx, sy) * h,
                        half: h,
                        depth: cell.depth + 1,
                    });
                }
            } else {
                out.unresolved += 1;
                out.phi_certified = phi;
                out.at = Some(cell.centre);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cos_and_sin_of_an_interval_hold_every_value_and_reach_the_extremes() {
        for (c, w) in [(0.1, 0.05), (0.0, 0.3), (3.0, 0.3), (-2.0, 1.0), (1.5, 0.1)] {
            let (ci, si) = (Iv::cos_of(c, w), Iv::sin_of(c, w));
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=1000 {
                let a = c - w + 2.0 * w * f64::from(i) / 1000.0;
                assert!(ci.lo - 1e-15 <= a.cos() && a.cos() <= ci.hi + 1e-15);
                assert!(si.lo - 1e-15 <= a.sin() && a.sin() <= si.hi + 1e-15);
                lo = lo.min(a.cos());
                hi = hi.max(a.cos());
            }
            assert!(
                (ci.lo - lo).abs() < 1e-5 && (ci.hi - hi).abs() < 1e-5,
                "{c} {w}"
            );
        }
    }

    #[test]
    fn the_stretch_slopes_hold_the_sampled_ones() {
        let (eps0, gain) = (0.5, 1.0);
        for (t1, t2) in [(0.8, 0.81), (0.55, 0.7), (0.9, 0.99), (0.6, 0.95)] {
            let (nr, nt) = stretch_slopes(t1, t2, eps0, gain).unwrap();
            for i in 0..=200 {
                let t = t1 + (t2 - t1) * f64::from(i) / 200.0;
                let m = harmonav_transform::radial::outer_map(t, 1.0, 0.0, eps0, gain);
                assert!(nr.lo <= m.nu_rho * (1.0 + 1e-12) && m.nu_rho <= nr.hi * (1.0 + 1e-12));
                let q = m.nu / t;
                assert!(
                    nt.lo <= q * (1.0 + 1e-12) && q <= nt.hi * (1.0 + 1e-12),
                    "{t}"
                );
            }
        }
        // The band's start and end have no finite bound; below it, the identity.
        assert!(stretch_slopes(0.4, 0.6, eps0, gain).is_none());
        assert!(stretch_slopes(0.9, 1.0, eps0, gain).is_none());
        let (nr, nt) = stretch_slopes(0.1, 0.4, eps0, gain).unwrap();
        assert_eq!((nr.lo, nr.hi, nt.lo, nt.hi), (1.0, 1.0, 1.0, 1.0));
    }

    #[test]
    fn arcs_of_boxes_hold_their_corners_and_disjoint_arcs_miss() {
        let a = DirectionArc::of_box(Iv::new(1.0, 2.0), Iv::new(-0.5, 0.5)).unwrap();
        assert!((a.mid).abs() < 1e-12 && (a.half - 0.5_f64.atan()).abs() < 1e-12);
        // Across ±π.
        let b = DirectionArc::of_box(Iv::new(-2.0, -1.0), Iv::new(-0.5, 0.5)).unwrap();
        assert!((wrap(b.mid - PI)).abs() < 1e-12, "{b:?}");
        assert!(a.misses(&b) && b.misses(&a));
        assert!(DirectionArc::of_box(Iv::new(-1.0, 1.0), Iv::new(-1.0, 1.0)).is_none());
        let h = DirectionArc::hull(&[
            DirectionArc {
                mid: 3.0,
                half: 0.1,
            },
            DirectionArc {
                mid: -3.0,
                half: 0.1,
            },
        ])
        .unwrap();
        assert!((wrap(h.mid - PI)).abs() < 1e-12 && (h.half - (PI - 3.0 + 0.1)).abs() < 1e-12);
        assert!(
            DirectionArc::hull(&[
                DirectionArc {
                    mid: 0.0,
                    half: 0.1
                },
                DirectionArc { mid: PI, half: 0.1 }
            ])
            .is_none()
        );
    }
}
