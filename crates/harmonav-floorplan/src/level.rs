//! The certified level `c_δ`: a lower bound of `Θ` on the edge `∂W_δ` of the certified region,
//! by interval bounds on a covering of `∂W_δ` (docs/maths.md §13.5).
//!
//! Each cell is a disc `B(x, ρ)`. [`crate::FloorTransform::enclose`] gives an annular sector `A` of
//! the point world that holds `Phi` of the disc; on `A`
//!
//! ```text
//! phi_k ≥ ln d_min(P_d, A)² − (1/k) Σ_i ln d_max(P_i, A)²,      Θ = sigma(phi_k) ≥ sigma(that)
//! ```
//!
//! (`sigma` increases), with `d_min` and `d_max` exact for a sector ([`Sector`]). Cells start
//! on a grid of half-diagonal `δ/3`, are kept while they may meet `∂W_δ` (`|sd(x) − δ| ≤ ρ`,
//! `sd` 1-Lipschitz) and are split in four while their bound is below the sampled least value
//! less a tolerance, up to a depth and an evaluation budget.

use harmonav_potential::sigma;
use std::sync::atomic::{AtomicUsize, Ordering};

use nalgebra::Vector2;

use crate::halves::both;
use crate::sector::Sector;
use crate::theta::FloorField;

/// How far the samples of `∂W_δ` are moved into `W_δ`, in units of `δ`
/// ([`FloorField::layer_slide`] and the sampled value of [`FloorField::certify_layer_level`]).
pub const EDGE_NUDGE: f64 = 1e-9;

/// The least nudge of an edge sample, in ulps of its largest coordinate
/// ([`FloorField::certify_layer_level`]'s samples).
pub const NUDGE_ULPS: f64 = 16.0;

/// How many more nudges a sample at a corner of `W_δ` may take, each away from the wall
/// nearest to it.
const CORNER_NUDGES: usize = 3;

/// Options of [`FloorField::certify_layer_level`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelOptions {
    /// How many times a first cell may be split in four (default 8: cells down to `δ/768`).
    pub max_depth: u32,
    /// The most cells evaluated (default 400 000, about a second at `N` = 2 000).
    pub max_evaluations: usize,
    /// A cell is done when its bound of `phi_k` is within this of the sampled least `phi_k`
    /// (default 0.05: `1 − Θ` within about 5 %).
    pub tolerance: f64,
}

impl Default for LevelOptions {
    fn default() -> Self {
        Self {
            max_depth: 8,
            max_evaluations: 400_000,
            tolerance: 0.05,
        }
    }
}

/// What [`FloorField::certify_layer_level`] found, in `phi_k` (log space: near the walls `Θ`
/// is within rounding of 1, `phi_k` is not) and in `Θ = sigma(phi_k)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerLevel {
    /// A lower bound of `phi_k ∘ Phi` on all of `∂W_δ` (to rounding); `−∞` when some cell
    /// could not be bounded.
    pub phi_certified: f64,
    /// The least `phi_k ∘ Phi` at the samples of `∂W_δ` ([`crate::FloorMap::layer_edge`]), no
    /// margin: an upper bound of the true least value.
    pub phi_sampled: f64,
    /// Cells evaluated.
    pub evaluations: usize,
    /// Cells left at the depth or budget limit with a bound below the sampled value less the
    /// tolerance (their bound is in `phi_certified`).
    pub unresolved: usize,
    /// Samples of `∂W_δ` where `Θ` could not be evaluated (0 in the suite's maps, near the
    /// origin and at 1e7 m; when it is all of them `phi_sampled` is `+∞`, which a report must
    /// not print as a value of `Θ`).
    pub skipped: usize,
    /// `c_s` in `phi_k` (docs/maths.md §13.9, [`crate::SlideLevel`]): below it the projected
    /// descent cannot rest on `∂W_δ`, so it converges even where it slides; `+∞` when no rest
    /// point is possible, `−∞` when not computed ([`FloorField::certify_layer_level`] alone).
    pub phi_slide: f64,
    /// The centre of the cell that set `phi_slide`: where a rest point of the slide may be
    /// (`None` when none is possible or it was not computed).
    pub slide_at: Option<Vector2<f64>>,
}

impl LayerLevel {
    /// `c_δ = sigma(phi_certified)`, certified.
    #[must_use]
    pub fn certified(&self) -> f64 {
        sigma(self.phi_certified)
    }

    /// `sigma(phi_sampled)`, the sampled least `Θ` on `∂W_δ`.
    #[must_use]
    pub fn sampled(&self) -> f64 {
        sigma(self.phi_sampled)
    }

    /// Whether a start with `phi_k(Phi(x₀)) = phi` is certified: `Θ(x₀) < c_δ`, so the
    /// continuous law's sublevel set through it stays inside `W_δ` (§13.5), or `Θ(x₀) < c_s`,
    /// so the projected descent from it cannot rest on `∂W_δ` (§13.9); compared in `phi_k`,
    /// which `sigma` orders the same way without rounding to 1.
    #[must_use]
    pub fn holds(&self, phi: f64) -> bool {
        phi < self.phi_certified || phi < self.phi_slide
    }

    /// `sigma(max(c_δ, c_s))` in `phi_k`: the level of `Θ` below which convergence is
    /// certified (1 when the slide has no possible rest point).
    #[must_use]
    pub fn convergence(&self) -> f64 {
        sigma(self.phi_certified.max(self.phi_slide))
    }

    /// `c_s = sigma(phi_slide)` (0 when not computed, 1 when no rest point is possible).
    #[must_use]
    pub fn slide(&self) -> f64 {
        sigma(self.phi_slide)
    }
}

impl FloorField {
    /// The samples of `∂W_δ` ([`crate::FloorMap::layer_edge`]) with `n`, the unit vector
    /// towards the nearest point of `∂W_s`, each moved along `−n` into `W_δ` by
    ///
    /// ```text
    /// nudge(p) = max(EDGE_NUDGE·δ, NUDGE_ULPS·ε·|p|_∞)      ε = f64::EPSILON
    /// ```
    ///
    /// on the edge itself rounding puts most samples a hair inside the layer, where `Θ` is not
    /// evaluated (measured: 2 907 of the U room's samples were skipped); far from the origin
    /// (1e7 m) `EDGE_NUDGE·δ` is below the coordinates' rounding and was lost, so the nudge is
    /// at least a few of their ulps (issue 56, D13); a sample still in the layer (a corner,
    /// where the other wall's coordinate rounds inward) is nudged from that wall too.
    fn edge_samples(&self) -> impl Iterator<Item = (Vector2<f64>, Vector2<f64>)> + '_ {
        let floor = self.floor();
        let base = EDGE_NUDGE * floor.delta();
        let delta = floor.delta();
        floor.layer_edge().iter().filter_map(move |&p| {
            let nudge = base.max(NUDGE_ULPS * f64::EPSILON * p.x.abs().max(p.y.abs()));
            let n = floor.toward_boundary(p)?;
            let mut q = p - nudge * n;
            // At a corner of `W_δ` the other wall's coordinate may still round into the layer:
            // away from the wall nearest to the nudged point too, a few times at most.
            for _ in 0..CORNER_NUDGES {
                if floor.signed_distance(q) >= delta {
                    break;
                }
                match floor.toward_boundary(q) {
                    Some(m) => q -= nudge * m,
                    None => break,
                }
            }
            Some((q, n))
        })
    }

    /// The least `phi_k` on a sector, from below (`−∞` if it may hold `P_d`).
    pub(crate) fn phi_lower(&self, a: &Sector) -> f64 {
        let world = self.point_world();
        let near = a.min_distance(world.destination());
        let far: f64 = world
            .obstacles()
            .iter()
            .map(|&p| a.max_distance(p).powi(2).ln())
            .sum();
        near.powi(2).ln() - far / world.k()
    }

    /// `c_δ` ([`FloorField::certify_layer_level`]) and `c_s`
    /// ([`FloorField::certify_slide_level`]) with the same options: the level below which
    /// convergence is certified ([`LayerLevel::holds`], docs/maths.md §13.5 and §13.9).
    #[must_use]
    pub fn certify_level(&self, options: &LevelOptions) -> LayerLevel {
        let mut level = self.certify_layer_level(options);
        let slide = self.certify_slide_level(options);
        level.phi_slide = slide.phi_certified;
        level.slide_at = slide.at;
        level
    }

    /// `c_δ` certified: a lower bound of `Θ` on `∂W_δ` by the covering of the module docs, next
    /// to the sampled least value. With sensed obstacles the bound is of the current field (`k`
    /// and the point world change at each discovery); their bands lie in `W_δ` at a positive
    /// distance from `∂W_δ`, and cells that may meet them are split until they do not.
    #[must_use]
    pub fn certify_layer_level(&self, options: &LevelOptions) -> LayerLevel {
        self.layer_level(options, true)
    }

    /// [`FloorField::certify_layer_level`], its covering on two threads while the budget
    /// allows (`parallel`) or on one.
    fn layer_level(&self, options: &LevelOptions, parallel: bool) -> LayerLevel {
        let floor = self.floor();
        let delta = floor.delta();
        let edge: Vec<Vector2<f64>> = self.edge_samples().map(|(p, _)| p).collect();
        // The least sampled phi and the samples that could not be evaluated, the halves of the
        // samples on two threads (a minimum and a count: the same whatever the order).
        let least = |part: &[Vector2<f64>]| {
            part.iter()
                .fold((f64::INFINITY, 0), |(m, k), &p| match self.eval(p) {
                    Ok(e) => (m.min(e.phi), k),
                    Err(_) => (m, k + 1),
                })
        };
        let (low, high) = edge.split_at(edge.len() / 2);
        let (a, b) = both(|| least(low), || least(high));
        let (sampled, skipped) = (a.0.min(b.0), a.1 + b.1);
        let target = sampled - options.tolerance;
        let (lo, hi) = floor.map().domain().bounding_box();
        let w0 = delta / (3.0 * std::f64::consts::SQRT_2);
        let nx = ((hi.x - lo.x) / (2.0 * w0)).ceil().max(1.0) as usize;
        let ny = ((hi.y - lo.y) / (2.0 * w0)).ceil().max(1.0) as usize;
        let mut stack: Vec<Cell> = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                let c = lo + Vector2::new(2.0 * i as f64 + 1.0, 2.0 * j as f64 + 1.0) * w0;
                stack.push((c, w0, 0));
            }
        }
        let mut out = LayerLevel {
            phi_certified: sampled,
            phi_sampled: sampled,
            evaluations: 0,
            unresolved: 0,
            skipped,
            phi_slide: f64::NEG_INFINITY,
            slide_at: None,
        };
        // Within the budget, which cells are split does not depend on the order they are taken
        // in (a cell is split when its bound is below the target and it is not at the depth
        // limit), and the result is a minimum and two counts: the two halves of the first grid
        // on two threads give the one-thread result. Once the budget binds the order matters
        // (`can_split` below): then the covering runs again on one thread, as it always did.
        let evaluations = AtomicUsize::new(0);
        let (low, high) = stack.split_at(stack.len() / 2);
        let within = |cells: &[Cell]| {
            parallel
                .then(|| self.layer_cells_within(cells.to_vec(), target, options, &evaluations))
                .flatten()
        };
        let (first, second) = both(|| within(low), || within(high));
        if let (Some(first), Some(second)) = (first, second) {
            out.phi_certified = out.phi_certified.min(first.0).min(second.0);
            out.unresolved = first.1 + second.1;
            out.evaluations = evaluations.into_inner();
            return out;
        }
        while let Some((c, w, depth)) = stack.pop() {
            let Some(phi) = self.layer_cell(c, w) else {
                continue;
            };
            let can_split = depth < options.max_depth && out.evaluations < options.max_evaluations;
            out.evaluations += 1;
            if phi >= target {
                out.phi_certified = out.phi_certified.min(phi);
            } else if can_split {
                push_children(&mut stack, (c, w, depth));
            } else {
                out.unresolved += 1;
                out.phi_certified = out.phi_certified.min(phi);
            }
        }
        out
    }

    /// The lower bound of `phi_k` on the cell of centre `c` and half-side `w`, or `None` when
    /// the cell does not meet `∂W_δ` (`sd` is 1-Lipschitz: a cell with `|sd(c) − δ| > ρ`
    /// cannot). `−∞` when the cell cannot be enclosed.
    fn layer_cell(&self, c: Vector2<f64>, w: f64) -> Option<f64> {
        let floor = self.floor();
        let rho = w * std::f64::consts::SQRT_2;
        let sd = floor.signed_distance(c);
        if (sd - floor.delta()).abs().partial_cmp(&rho) == Some(std::cmp::Ordering::Greater)
            || sd.is_nan()
        {
            return None;
        }
        Some(match self.transform().enclose(c, rho) {
            Ok(a) => self.phi_lower(&a),
            Err(_) => f64::NEG_INFINITY,
        })
    }

    /// The covering of `stack`'s cells with no budget but the shared count `evaluations`:
    /// the least bound of the final cells and how many were left unresolved at the depth
    /// limit, or `None` as soon as the count passes `options.max_evaluations` (the budget
    /// binds, and the one-thread order decides).
    fn layer_cells_within(
        &self,
        mut stack: Vec<Cell>,
        target: f64,
        options: &LevelOptions,
        evaluations: &AtomicUsize,
    ) -> Option<(f64, usize)> {
        let (mut least, mut unresolved) = (f64::INFINITY, 0);
        while let Some((c, w, depth)) = stack.pop() {
            let Some(phi) = self.layer_cell(c, w) else {
                continue;
            };
            if evaluations.fetch_add(1, Ordering::Relaxed) >= options.max_evaluations {
                return None;
            }
            if phi >= target {
                least = least.min(phi);
            } else if depth < options.max_depth {
                push_children(&mut stack, (c, w, depth));
            } else {
                unresolved += 1;
                least = least.min(phi);
            }
        }
        Some((least, unresolved))
    }
}

/// A cell of the covering: centre, half-side, depth.
type Cell = (Vector2<f64>, f64, u32);

/// The four children of a cell, pushed in the covering's order.
fn push_children(stack: &mut Vec<Cell>, (c, w, depth): Cell) {
    let h = w / 2.0;
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        stack.push((c + Vector2::new(sx, sy) * h, h, depth + 1));
    }
}

/// What [`FloorField::layer_slide`] found on the samples of `∂W_δ`.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerSlide {
    /// Samples where `Θ` was evaluated.
    pub samples: usize,
    /// Of those, how many have `−∇Θ` pointing into the layer (`d·n > 0`, `n` towards the
    /// nearest point of `∂W_s`): where the hold's projected descent slides.
    pub into: usize,
    /// The least `|d − (d·n)n|` over them (1 when there are none): the projected descent
    /// rests on `∂W_δ` only where this is 0 (`−∇Θ` along the outward normal).
    pub least_tangential: f64,
    /// Rest points of the projected descent that attract it along the edge: between two
    /// neighbouring samples of one straight piece of `∂W_δ`, both with `−∇Θ` into the layer,
    /// whose tangential parts point at each other (the midpoint is given). The tangential part
    /// is continuous, so it vanishes between them: a spurious local minimum of `Θ` on `W_δ`.
    pub attracting: Vec<Vector2<f64>>,
    /// The same with the tangential parts pointing apart (rest points the slide leaves).
    pub repelling: usize,
}

impl FloorField {
    /// The projected descent of the hold along `∂W_δ` (docs/maths.md §13.5): at each sample of
    /// [`crate::FloorMap::layer_edge`] (in order along the edge), `d = −∇Θ/|∇Θ|` against `n`,
    /// the unit vector towards the nearest point of `∂W_s`, and the rest points where the
    /// tangential part `d·t` changes sign between neighbours on one straight piece. The sign
    /// changes prove rest points (to the accuracy of `Θ`); between samples others may hide.
    #[must_use]
    pub fn layer_slide(&self) -> LayerSlide {
        let mut out = LayerSlide {
            samples: 0,
            into: 0,
            least_tangential: 1.0,
            attracting: Vec::new(),
            repelling: 0,
        };
        // (position, n, d·t) of the previous sample with −∇Θ into the layer; neighbours are
        // at most a few sample spacings apart (rings follow each other in the list).
        let mut last: Option<(Vector2<f64>, Vector2<f64>, f64)> = None;
        let near = 4.0 * crate::plan::EDGE_SPACING * self.floor().delta();
        for (p, n) in self.edge_samples() {
            let Ok(e) = self.eval(p) else {
                last = None;
                continue;
            };
            out.samples += 1;
            let Some(d) = e.direction.filter(|d| d.dot(&n) > 0.0) else {
                last = None;
                continue;
            };
            out.into += 1;
            let along = d.dot(&n);
            out.least_tangential = out.least_tangential.min((d - along * n).norm());
            let t = Vector2::new(-n.y, n.x);
            let flow = d.dot(&t);
            if let Some((q, m, before)) = last
                && (m - n).norm() < 1e-9
                && (p - q).norm() <= near
            {
                // The flow at q towards p (and at p towards q) along the piece.
                let toward = (p - q).dot(&t).signum();
                if before * toward > 0.0 && flow * toward < 0.0 {
                    out.attracting.push(0.5 * (p + q));
                } else if before * toward < 0.0 && flow * toward > 0.0 {
                    out.repelling += 1;
                }
            }
            last = Some((p, n, flow));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use harmonav_field::KPolicy;

    use super::*;
    use crate::{FloorMap, FloorOptions};

    /// A 6 × 4 m room with an L-shaped pillar, the goal beside it.
    fn pillared_room() -> FloorField {
        let v = Vector2::new;
        let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
        let pillar = vec![
            v(2.5, 1.5),
            v(4.0, 1.5),
            v(4.0, 2.0),
            v(3.0, 2.0),
            v(3.0, 2.8),
            v(2.5, 2.8),
        ];
        let floor = FloorMap::new(room, vec![pillar], &FloorOptions::new(0.1, 0.2)).unwrap();
        FloorField::new(Arc::new(floor), v(3.5, 2.6), KPolicy::default()).unwrap()
    }

    /// The covering on two threads is the one-thread covering, field for field, within the
    /// budget; when the budget binds it gives way to the one-thread order (whose result then
    /// differs from the unbounded one: a lower certified bound).
    #[test]
    fn the_two_thread_covering_is_the_one_thread_covering() {
        let field = pillared_room();
        let options = LevelOptions::default();
        let one = field.layer_level(&options, false);
        assert_eq!(field.layer_level(&options, true), one);
        assert!(one.evaluations > 1_000 && one.evaluations < options.max_evaluations);
        let tight = LevelOptions {
            max_evaluations: one.evaluations / 2,
            ..options
        };
        let bound = field.layer_level(&tight, false);
        assert_eq!(field.layer_level(&tight, true), bound);
        assert!(
            bound.phi_certified < one.phi_certified,
            "{bound:?} against {one:?}"
        );
    }
}
