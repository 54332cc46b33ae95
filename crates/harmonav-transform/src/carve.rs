//! A boundary that takes in the obstacles against it: the star about the boundary's centre
//! with the shadows of some shapes cut out ([`StarShape::carved`]).
//!
//! Furniture stands against walls. Grown by the robot's radius and margin, such an obstacle
//! reaches the boundary shrunk by the same amount, and a star world (disjoint obstacles
//! strictly inside the boundary) cannot hold it. The space between it and the wall is closed to
//! the robot anyway, so the boundary takes the obstacle in: seen from the boundary's centre
//! `c`, each ray stops at the boundary or at the first of the shapes it meets, whichever comes
//! first,
//!
//! ```text
//! m(θ) = min(R(θ), e(θ)),   e(θ) = inf { s : c + s·u(θ) ∈ O_j for some j }           (eq. carve)
//! ```
//!
//! and `{c + s·u(θ) : s < m(θ)}` is star-shaped about `c` by construction. It lies inside the
//! boundary and outside every shape `O_j`; what it loses is the shapes and their *shadows*, the
//! points behind them as seen from `c`.
//!
//! **The table.** `m` jumps where a ray grazes a shape, so it is not a star's radius as it
//! stands. On the grid `θ_i = 2πi/G` a lower bound `L_i ≤ min m` over each cell is taken, and
//! the star is [`StarShape::tabulated`] of `R_i = min(L_{i−1}, L_i)`: a monotone cubic Hermite
//! cell stays between its end values, so on cell `i`, `R ≤ max(R_i, R_{i+1}) ≤ L_i ≤ m`. The
//! carved star lies inside the boundary and outside every shape, whatever the grid.
//!
//! - *The boundary's part.* The sector `{c + s·u(θ) : s ≤ T, θ ∈ cell}` lies in the boundary
//!   when its arc does (the boundary is a star about `c`); the arc lies within `2T sin(Δ/4)`
//!   of its midpoint `p = c + T·u(θ_mid)` (`Δ = 2π/G`). So `T` is admitted when the certified
//!   upper bound of the signed distance at `p` is at most `−2T sin(Δ/4)`
//!   ([`StarShape::signed_distance_bounds`]), and `T` starts at `R(θ_mid)` and moves in by the
//!   shortfall until it is (eq. carvearc). It costs at most `2R sin(Δ/4) ≈ RΔ/2` of the
//!   boundary: 2.3 mm at 3 m with `G = 4096`.
//! - *The shapes' part.* A ray from `c` (outside the shape) first meets `O` on its boundary,
//!   which lies within `δ + h/2` of points spaced `h` along its certified outline (as in
//!   [`StarShape::dilated_hull`]). So the ray meets one of the discs `B(p_k, δ + h/2)` no later,
//!   and `e(θ)` is at least the first entry into their union. A disc of radius `ρ` at distance
//!   `t > ρ` in the direction `β` is entered at
//!
//!   ```text
//!   n(α) = t cos α − √(ρ² − t² sin² α),   α = θ − β, |sin α| ≤ ρ/t                     (eq. entry)
//!   ```
//!
//!   which grows with `|α|` (its derivative is `t sin α (t cos α/√(ρ² − t² sin² α) − 1)`,
//!   positive for `α > 0` where the ray meets the disc: `t cos α ≥ √(ρ² − t² sin² α)` there);
//!   so its least value over a cell is at the cell's `α` nearest 0, exactly.

use std::f64::consts::TAU;

use nalgebra::Vector2;

use crate::error::ShapeError;
use crate::hull::disc_cells;
use crate::shape::StarShape;

/// Cells of a carved boundary's table, `G` (0.09° each; eq. carvearc's loss is `RΔ/2`, 2.3 mm
/// at 3 m).
pub const CARVE_CELLS: usize = 4096;

/// The spacing of the discs that cover a carved shape's boundary, relative to the shape's
/// largest radius (eq. entry: the shadow starts up to `δ + h/2` early, 1 mm on a 1 m shape).
const CARVE_SPACING: f64 = 2e-3;

/// The most steps of eq. carvearc's search along one ray before the carve is refused.
const MAX_STEPS: usize = 200;

impl StarShape {
    /// This star (a workspace's boundary) with `shapes` and their shadows seen from its centre
    /// cut out (module docs, eq. carve): a tabulated star about the same centre, inside this
    /// one and disjoint from every shape, on [`CARVE_CELLS`] directions.
    ///
    /// Errors on `obstacle` if a shape (within its certified outline's tolerance) holds the
    /// centre, and on `boundary` if no part of a ray stays in the boundary clear of the shapes.
    pub fn carved(&self, shapes: &[&StarShape]) -> Result<StarShape, ShapeError> {
        let c = self.centre();
        let g = CARVE_CELLS;
        let step = TAU / g as f64;
        let mut low: Vec<f64> = (0..g)
            .map(|i| self.arc_inside(c, (i as f64 + 0.5) * step, step))
            .collect::<Result<_, _>>()?;
        for shape in shapes {
            let outline = shape.certified();
            let h = CARVE_SPACING * shape.radius_bounds().1;
            let rho = outline.delta + 0.5 * h;
            if shape.signed_distance_bounds(c).0 <= rho {
                return Err(ShapeError::Invalid {
                    field: "obstacle",
                    problem: "a shape to join the boundary holds the boundary's centre".into(),
                });
            }
            let n = outline.len();
            for j in 0..n {
                let (a, b) = (outline.vertex(j), outline.vertex((j + 1) % n));
                let pieces = ((b - a).norm() / h).ceil().max(1.0) as usize;
                for q in 0..pieces {
                    let v = a + (b - a) * (q as f64 / pieces as f64) - c;
                    // `t > ρ`: the centre is more than `ρ` outside the shape.
                    let t = v.norm();
                    let beta = v.y.atan2(v.x).rem_euclid(TAU);
                    disc_cells(t, beta, rho, g, |i, alpha| {
                        low[i] = low[i].min(entry(t, rho, alpha));
                    });
                }
            }
        }
        // Rounding of eq. entry and of the table: a few ulp of the radii.
        let lower = 1.0 - 1e-12;
        let radii: Vec<f64> = (0..g)
            .map(|i| low[(i + g - 1) % g].min(low[i]) * lower)
            .collect();
        if radii.iter().any(|&r| r.is_nan() || r <= 0.0) {
            return Err(ShapeError::Invalid {
                field: "boundary",
                problem: "a ray from the boundary's centre meets a shape at once".into(),
            });
        }
        StarShape::tabulated(c, &radii)
    }

    /// The largest `T` whose arc `{c + T·u(θ) : |θ − mid| ≤ Δ/2}` is certified inside this
    /// star (eq. carvearc).
    fn arc_inside(&self, c: Vector2<f64>, mid: f64, step: f64) -> Result<f64, ShapeError> {
        let u = Vector2::new(mid.cos(), mid.sin());
        let spread = 2.0 * (step / 4.0).sin();
        let mut t = self.radius_along(u).0;
        for steps in 0..MAX_STEPS {
            let room = -self.signed_distance_bounds(c + t * u).1;
            let need = spread * t;
            if room >= need {
                return Ok(t);
            }
            // Moving in by `s` gains at most `s` of room (all of it where the boundary meets
            // the ray square on); after a few steps, twice the shortfall, which converges where
            // it meets the ray at 30° or more.
            let gain = if steps < 4 { 1.0 + 1e-9 } else { 2.0 };
            t -= (gain * (need - room)).max(1e-12 * t);
            if t <= 0.0 {
                break;
            }
        }
        Err(ShapeError::Invalid {
            field: "boundary",
            problem: format!(
                "no arc about the centre in the direction {mid:.4} rad could be certified inside"
            ),
        })
    }
}

/// `n(α)` of eq. entry: where the ray at `|α|` from the direction of a disc of radius `rho` at
/// distance `t > rho` enters it (`|sin α| ≤ ρ/t`).
fn entry(t: f64, rho: f64, alpha: f64) -> f64 {
    let (s, co) = alpha.sin_cos();
    t * co - (rho * rho - t * t * s * s).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 m disc room with a 0.4 × 0.3 box whose far side stands 0.05 m from the wall: the
    /// carved boundary is inside the room (dense rays), outside the box (its outline and
    /// interior points), keeps the room away from the box (a ray on the far side of the room
    /// loses at most eq. carvearc's `RΔ/2`), and the shadow behind the box is gone.
    #[test]
    fn a_box_against_the_wall_is_cut_out_with_its_shadow() {
        let room = StarShape::circle(Vector2::zeros(), 3.0).unwrap();
        let corners = [
            Vector2::new(2.55, -0.2),
            Vector2::new(2.95, -0.2),
            Vector2::new(2.95, 0.2),
            Vector2::new(2.55, 0.2),
        ];
        let boxed = StarShape::rounded_polygon(&corners, 0.02).unwrap();
        let carved = room.carved(&[&boxed]).unwrap();
        let slack = 3.0 * TAU / CARVE_CELLS as f64 / 2.0;
        for j in 0..20_000 {
            let th = TAU * j as f64 / 20_000.0;
            let u = Vector2::new(th.cos(), th.sin());
            let r = carved.radius_along(u).0;
            assert!(r <= 3.0, "outside the room at {th}: {r}");
            // No point of the ray up to the carved boundary is in the box.
            assert!(
                boxed.ray_hit(Vector2::zeros(), u, r).is_none(),
                "the box at {th}"
            );
            if th > 0.4 && th < TAU - 0.4 {
                assert!(r > 3.0 - slack * 1.01, "lost too much at {th}: {r}");
            }
        }
        // The box's shadow: the gap behind it is outside, as is the box itself.
        assert!(!carved.contains(Vector2::new(2.97, 0.0)));
        assert!(!carved.contains(Vector2::new(2.7, 0.0)));
        assert!(carved.contains(Vector2::new(2.5, 0.0)));
    }

    /// Negative controls: a shape over the centre is refused by name; tabulating the
    /// boundary's own radii at the nodes (no lower bound over the cell, no shadow) is not inside
    /// the room's box-free part, which is what the cell bounds are for.
    #[test]
    fn a_shape_over_the_centre_is_refused_and_node_values_are_not_enough() {
        let room = StarShape::circle(Vector2::zeros(), 3.0).unwrap();
        let over = StarShape::circle(Vector2::new(0.1, 0.0), 0.5).unwrap();
        let e = room.carved(&[&over]).unwrap_err();
        assert!(e.to_string().contains("centre"), "{e}");
        // The nodes alone: a disc box near the wall, radii min(R, entry) at the nodes only.
        let disc = StarShape::circle(Vector2::new(2.7, 0.0), 0.2).unwrap();
        let g = CARVE_CELLS;
        let naive: Vec<f64> = (0..g)
            .map(|i| {
                let th = TAU * i as f64 / g as f64;
                let u = Vector2::new(th.cos(), th.sin());
                disc.ray_hit(Vector2::zeros(), u, 3.0).unwrap_or(3.0)
            })
            .collect();
        let naive = StarShape::tabulated(Vector2::zeros(), &naive).unwrap();
        let inside = |s: &StarShape| {
            (0..20_000).all(|j| {
                let th = TAU * j as f64 / 20_000.0;
                let u = Vector2::new(th.cos(), th.sin());
                let r = s.radius_along(u).0;
                disc.ray_hit(Vector2::zeros(), u, r * (1.0 - 1e-9))
                    .is_none()
                    && r <= 3.0
            })
        };
        assert!(
            !inside(&naive),
            "the node values must leave the disc's edge in"
        );
        assert!(inside(&room.carved(&[&disc]).unwrap()));
    }
}
