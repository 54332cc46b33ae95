//! `Θ` sampled on a square grid over the workspace, and its level sets (marching squares, the
//! `contour` crate): the `/theta` grid of the recording and the level lines of the figures.

use contour::ContourBuilder;
use harmonav_field::{Field, FieldError};
use nalgebra::Vector2;

/// `Θ` at the centres of an `n × n` grid of square cells, row by row from `corner` (the
/// lower-left corner) upwards; NaN outside the free space.
#[derive(Clone, Debug, PartialEq)]
pub struct ThetaGrid {
    /// The lower-left corner of the grid.
    pub corner: Vector2<f64>,
    /// The side of a cell, m.
    pub cell: f64,
    /// Cells per side.
    pub n: usize,
    /// `n²` values, row-major from the bottom row.
    pub values: Vec<f64>,
}

/// A level line of `Θ`: its value and its polylines.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelLine {
    /// The level `Θ = value`.
    pub value: f64,
    /// The lines, each a sequence of points.
    pub lines: Vec<Vec<Vector2<f64>>>,
}

impl ThetaGrid {
    /// `f` on an `n × n` grid over the square of half-side `half` about `centre` (`None`:
    /// outside the free space).
    pub fn from_fn(
        centre: Vector2<f64>,
        half: f64,
        n: usize,
        f: impl Fn(Vector2<f64>) -> Option<f64>,
    ) -> Self {
        let cell = 2.0 * half / n as f64;
        let corner = centre - Vector2::new(half, half);
        let values = (0..n * n)
            .map(|k| {
                let p = corner + cell * Vector2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
                f(p).unwrap_or(f64::NAN)
            })
            .collect();
        Self {
            corner,
            cell,
            n,
            values,
        }
    }

    /// `Θ` of `field` on an `n × n` grid over the square of half-side `half` about `centre`.
    pub fn sample(
        field: &Field,
        centre: Vector2<f64>,
        half: f64,
        n: usize,
    ) -> Result<Self, FieldError> {
        let cell = 2.0 * half / n as f64;
        let corner = centre - Vector2::new(half, half);
        let mut values = Vec::with_capacity(n * n);
        let mut row = vec![Vector2::zeros(); n];
        let mut evals = vec![Err(FieldError::Outside); n];
        for j in 0..n {
            for (i, p) in row.iter_mut().enumerate() {
                *p = corner + cell * Vector2::new(i as f64 + 0.5, j as f64 + 0.5);
            }
            field.eval_many(&row, &mut evals)?;
            values.extend(
                evals
                    .iter()
                    .map(|e| e.as_ref().map_or(f64::NAN, |e| e.value)),
            );
        }
        Ok(Self {
            corner,
            cell,
            n,
            values,
        })
    }

    /// The level lines `Θ = v` for each `v` in `levels` (in `(0, 1)`). Cells outside the free
    /// space count as `Θ = 1`, the value `Θ` takes on every boundary, so no line runs into an
    /// obstacle or out of the workspace. Marching squares runs on `1 − Θ` against `1 − v`:
    /// the `contour` crate treats the outside of the grid as below every threshold, which
    /// `1 − Θ = 0` on the boundary matches (on `Θ` itself it would trace the grid's frame).
    pub fn level_lines(&self, levels: &[f64]) -> Vec<LevelLine> {
        let filled: Vec<f64> = self
            .values
            .iter()
            .map(|&v| if v.is_nan() { 0.0 } else { 1.0 - v })
            .collect();
        let thresholds: Vec<f64> = levels.iter().map(|v| 1.0 - v).collect();
        let builder = ContourBuilder::new(self.n, self.n, true)
            .x_origin(self.corner.x + 0.5 * self.cell)
            .y_origin(self.corner.y + 0.5 * self.cell)
            .x_step(self.cell)
            .y_step(self.cell);
        let Ok(lines) = builder.lines(&filled, &thresholds) else {
            return Vec::new();
        };
        // Where the field is below the level at the grid's edge, marching squares closes the
        // line along the edge (outside counts as below): cut the lines at the edge's points.
        let (lo, hi) = (
            self.corner.add_scalar(0.5 * self.cell),
            self.corner.add_scalar((self.n as f64 - 0.5) * self.cell),
        );
        // The traced frame lies between the outermost samples and the padding.
        let on_edge = |p: &Vector2<f64>| p.x <= lo.x || p.x >= hi.x || p.y <= lo.y || p.y >= hi.y;
        lines
            .into_iter()
            .map(|l| {
                let value = 1.0 - l.threshold();
                let mut out: Vec<Vec<Vector2<f64>>> = Vec::new();
                for ls in &l.geometry().0 {
                    let mut run: Vec<Vector2<f64>> = Vec::new();
                    for p in ls.0.iter().map(|c| Vector2::new(c.x, c.y)) {
                        if on_edge(&p) {
                            if run.len() > 1 {
                                out.push(std::mem::take(&mut run));
                            }
                            run.clear();
                        } else {
                            run.push(p);
                        }
                    }
                    if run.len() > 1 {
                        out.push(run);
                    }
                }
                LevelLine { value, lines: out }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use harmonav_transform::{StarShape, Workspace};

    use super::*;

    /// With no obstacle `Phi` is the identity near the goal, so the level line `Θ = v` there is
    /// the circle `|x − x_d| = e^{σ⁻¹(v)/2}` (`phi_k = ln|x − x_d|²`).
    #[test]
    fn level_lines_near_the_goal_are_the_closed_form_circles() {
        let boundary = StarShape::circle(Vector2::zeros(), 5.0).unwrap();
        let goal = Vector2::new(0.5, -0.3);
        let ws = Arc::new(Workspace::new(boundary, Vec::new(), goal).unwrap());
        let field = Field::all_known(ws).unwrap();
        let grid = ThetaGrid::sample(&field, Vector2::zeros(), 5.0, 400).unwrap();
        assert!(
            grid.values.iter().any(|v| v.is_nan()),
            "the corners lie outside"
        );
        // Phi is the identity within 1.02 of the centre (the outer band is wide: no obstacle).
        for level in grid.level_lines(&[0.05, 0.1]) {
            let radius = (0.5 * (level.value / (1.0 - level.value)).ln()).exp();
            let points: Vec<_> = level.lines.iter().flatten().collect();
            assert!(points.len() > 20);
            for p in points {
                let err = ((p - goal).norm() - radius).abs();
                assert!(
                    err < 0.02,
                    "level {}: {err} off the circle of radius {radius}",
                    level.value
                );
            }
        }
    }
}
