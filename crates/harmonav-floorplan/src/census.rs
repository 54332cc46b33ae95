//! The census of a floor plan's `Θ` (theorem `isNF` through `Phi = S∘M_a∘H∘B`, docs/maths.md
//! §13): the goal, the unique minimum, and the saddles of `phi_k` in the point world pulled
//! back into `W_δ` by Newton's method on `Phi`, each typed by the Hessian of `Θ`, as a star
//! world's census ([`harmonav_field::Census`]).

use harmonav_field::{
    Census, CensusPoint, CriticalType, FieldError, ascending_eigenvalues, fd_hessian,
};
use harmonav_potential::CriticalKind;
use nalgebra::{Matrix2, Vector2};

use crate::theta::FloorField;

/// Grid points per side of the bounding box from which Newton's method on `Phi` is seeded:
/// the images of the points of this grid in `W_δ` are the seeds' pool.
pub const SEED_GRID: usize = 64;

/// Seeds tried per preimage (the nearest images first).
const SEEDS: usize = 6;

/// Newton iterations per seed.
const NEWTON_STEPS: usize = 60;

/// A preimage is accepted when `|Phi(x) − h|` is below this (the point world is the unit disk
/// stretched by `S`: lengths of order 1).
pub const PREIMAGE_TOLERANCE: f64 = 1e-10;

impl FloorField {
    /// The point `x` of `W_δ` (minus the sensed obstacles) with `Phi(x) = h`, within
    /// [`PREIMAGE_TOLERANCE`], by Newton's method `x ← x + J_Phi(x)⁻¹(h − Phi(x))` (the step
    /// halved until the residual falls and `x` stays where `Phi` is defined) from the
    /// [`SEED_GRID`] points whose images lie nearest `h`; `None` when no seed converges (`h`
    /// not in the image of `W_δ`: in the layer's band, beyond the disk, or inside a point's
    /// obstacle).
    #[must_use]
    pub fn preimage(&self, h: Vector2<f64>) -> Option<Vector2<f64>> {
        self.preimage_from(&self.seed_images(), h)
    }

    /// The grid points of the bounding box in `W_δ` and their images.
    fn seed_images(&self) -> Vec<(Vector2<f64>, Vector2<f64>)> {
        let (lo, hi) = self.floor().domain().bounding_box();
        let n = SEED_GRID;
        let t = |i: usize| (i as f64 + 0.5) / n as f64;
        (0..n * n)
            .filter_map(|i| {
                let x = lo + (hi - lo).component_mul(&Vector2::new(t(i % n), t(i / n)));
                self.transform().nav_transform(x).ok().map(|m| (x, m.h))
            })
            .collect()
    }

    fn preimage_from(
        &self,
        seeds: &[(Vector2<f64>, Vector2<f64>)],
        h: Vector2<f64>,
    ) -> Option<Vector2<f64>> {
        let mut nearest: Vec<&(Vector2<f64>, Vector2<f64>)> = seeds.iter().collect();
        nearest.sort_by(|a, b| (a.1 - h).norm().total_cmp(&(b.1 - h).norm()));
        nearest
            .into_iter()
            .take(SEEDS)
            .find_map(|&(x0, _)| self.newton(x0, h))
    }

    /// Newton's method on `Phi(x) = h` from `x0`.
    fn newton(&self, x0: Vector2<f64>, h: Vector2<f64>) -> Option<Vector2<f64>> {
        let map = |x| self.transform().nav_transform(x).ok();
        let mut x = x0;
        let mut m = map(x)?;
        for _ in 0..NEWTON_STEPS {
            let r = h - m.h;
            if r.norm() < PREIMAGE_TOLERANCE {
                return Some(x);
            }
            let step = m.jacobian.try_inverse()? * r;
            let mut t = 1.0;
            loop {
                if let Some(next) = map(x + t * step).filter(|n| (h - n.h).norm() < r.norm()) {
                    x += t * step;
                    m = next;
                    break;
                }
                t *= 0.5;
                if t < 1e-12 {
                    return None;
                }
            }
        }
        ((h - m.h).norm() < PREIMAGE_TOLERANCE).then_some(x)
    }

    /// `H(Θ)(x)` ([`harmonav_field::fd_hessian`]), as a star world's.
    ///
    /// # Errors
    /// As [`FloorField::eval`] at a difference point (one that leaves `W_δ` or enters a
    /// sensed obstacle).
    pub fn hessian(&self, x: Vector2<f64>) -> Result<Matrix2<f64>, FieldError> {
        fd_hessian(|y| self.eval(y), x)
    }

    /// The census of `Θ` on the floor plan: the goal, then each saddle of `phi_k` whose
    /// preimage ([`FloorField::preimage`]) lies in `W_δ`, typed by the point world (degenerate
    /// or not) with the eigenvalues of [`FloorField::hessian`]. Theorem `isNF`: one minimum and
    /// one saddle per hole and sensed obstacle whose saddle's image lies in the image of `W_δ`.
    #[must_use]
    pub fn census(&self) -> Census {
        let goal = self.transform().goal();
        let mut census = Census {
            points: Vec::new(),
            minima: 1,
            saddles: 0,
            degenerate: 0,
        };
        let eigenvalues = |x: Vector2<f64>| self.hessian(x).ok().map(ascending_eigenvalues);
        census.points.push(CensusPoint {
            x: goal,
            kind: CriticalType::Minimum,
            eigenvalues: eigenvalues(goal),
        });
        let seeds = self.seed_images();
        for c in self.point_world().critical_points() {
            let Some(x) = self.preimage_from(&seeds, c.position) else {
                continue;
            };
            let kind = if c.kind == CriticalKind::Degenerate {
                census.degenerate += 1;
                CriticalType::DegenerateSaddle
            } else {
                census.saddles += 1;
                CriticalType::Saddle
            };
            census.points.push(CensusPoint {
                x,
                kind,
                eigenvalues: eigenvalues(x),
            });
        }
        census
    }
}
