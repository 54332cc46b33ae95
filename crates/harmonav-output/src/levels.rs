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

    /// The level lines `Θ = v` for each `v` in `levels` (in `(0, 1)`), traced on the samples:
    /// each vertex interpolated linearly between the two samples of a grid edge. Cells outside
    /// the free space count as `Θ = 1`, the value `Θ` takes on every boundary, so no line runs
    /// into an obstacle or out of the workspace. Marching squares runs on `1 − Θ` against
    /// `1 − v`: the `contour` crate treats the outside of the grid as below every threshold,
    /// which `1 − Θ = 0` on the boundary matches (on `Θ` itself it would trace the grid's
    /// frame).
    pub fn level_lines(&self, levels: &[f64]) -> Vec<LevelLine> {
        let filled: Vec<f64> = self.values.iter().map(|&v| 1.0 - self.filled(v)).collect();
        let thresholds: Vec<f64> = levels.iter().map(|v| 1.0 - v).collect();
        // The crate puts sample (i, j) at (i + ½, j + ½) steps from the origin.
        let builder = ContourBuilder::new(self.n, self.n, true)
            .x_origin(self.corner.x)
            .y_origin(self.corner.y)
            .x_step(self.cell)
            .y_step(self.cell);
        let Ok(lines) = builder.lines(&filled, &thresholds) else {
            return Vec::new();
        };
        // Where the field is below the level at the grid's edge, marching squares closes the
        // line along the grid's frame, half a cell outside the outermost samples (outside
        // counts as below): cut the lines at the frame's points.
        let (lo, hi) = (
            self.corner.add_scalar(0.25 * self.cell),
            self.corner.add_scalar((self.n as f64 - 0.25) * self.cell),
        );
        let on_frame = |p: &Vector2<f64>| p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y;
        lines
            .into_iter()
            .map(|l| {
                let value = 1.0 - l.threshold();
                let mut out: Vec<Vec<Vector2<f64>>> = Vec::new();
                for ls in &l.geometry().0 {
                    let mut run: Vec<Vector2<f64>> = Vec::new();
                    for p in ls.0.iter().map(|c| Vector2::new(c.x, c.y)) {
                        if on_frame(&p) {
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

    /// [`Self::level_lines`] with each vertex moved onto the true level set of `f` (the
    /// function the grid sampled; `None` outside the free space, counted as 1): the crossing
    /// on the vertex's grid edge, found by false position (Illinois) from the two samples.
    /// Linear interpolation cuts the corners of a level set where `Θ` bends (near the goal,
    /// along the obstacles); the refined vertices lie on it, at the cost of a few evaluations
    /// of `f` per vertex.
    pub fn refined_level_lines(
        &self,
        levels: &[f64],
        f: impl Fn(Vector2<f64>) -> Option<f64>,
    ) -> Vec<LevelLine> {
        let mut lines = self.level_lines(levels);
        for level in &mut lines {
            for p in level.lines.iter_mut().flatten() {
                let edge = self.edge_of(*p);
                if let Some(q) = edge.and_then(|(a, b)| self.crossing(a, b, level.value, &f)) {
                    *p = q;
                }
            }
        }
        lines
    }

    /// A value as the level lines count it: 1 outside the free space.
    fn filled(&self, v: f64) -> f64 {
        if v.is_finite() { v } else { 1.0 }
    }

    /// The sample `(i, j)`, filled, and its point.
    fn node(&self, i: usize, j: usize) -> (f64, Vector2<f64>) {
        let p = self.corner + self.cell * Vector2::new(i as f64 + 0.5, j as f64 + 0.5);
        (self.filled(self.values[j * self.n + i]), p)
    }

    /// The samples `(i, j)` at both ends of the grid edge that a traced vertex `p` lies on,
    /// or `None` for a vertex on a sample itself (or off the grid).
    fn edge_of(&self, p: Vector2<f64>) -> Option<((usize, usize), (usize, usize))> {
        let u = (p.x - self.corner.x) / self.cell - 0.5;
        let w = (p.y - self.corner.y) / self.cell - 0.5;
        let on_line = |t: f64| (t - t.round()).abs() < 1e-6;
        let index = |t: f64| (t >= 0.0 && t < self.n as f64).then_some(t as usize);
        let (a, b) = match (on_line(u), on_line(w)) {
            (false, true) => {
                let (i, j) = (index(u.floor())?, index(w.round())?);
                ((i, j), (i + 1, j))
            }
            (true, false) => {
                let (i, j) = (index(u.round())?, index(w.floor())?);
                ((i, j), (i, j + 1))
            }
            _ => return None,
        };
        (b.0 < self.n && b.1 < self.n).then_some((a, b))
    }

    /// The point where `f` crosses `value` between the samples `a` and `b` (false position,
    /// Illinois variant: a bracket kept, to `10⁻⁹` of the edge); `None` if the samples do
    /// not bracket it.
    fn crossing(
        &self,
        a: (usize, usize),
        b: (usize, usize),
        value: f64,
        f: &impl Fn(Vector2<f64>) -> Option<f64>,
    ) -> Option<Vector2<f64>> {
        let ((va, pa), (vb, pb)) = (self.node(a.0, a.1), self.node(b.0, b.1));
        let at = |s: f64| pa + s * (pb - pa);
        let g = |s: f64| self.filled(f(at(s)).unwrap_or(f64::NAN)) - value;
        let (mut s0, mut g0, mut s1, mut g1) = (0.0, va - value, 1.0, vb - value);
        if g0 * g1 > 0.0 || g0 == g1 {
            return None;
        }
        for _ in 0..REFINE_STEPS {
            let s = (s0 * g1 - s1 * g0) / (g1 - g0);
            let gs = g(s);
            if gs == 0.0 {
                return Some(at(s));
            }
            if gs * g1 < 0.0 {
                (s0, g0) = (s1, g1);
            } else {
                g0 *= 0.5;
            }
            (s1, g1) = (s, gs);
            if (s1 - s0).abs() < 1e-9 {
                break;
            }
        }
        Some(at(s1))
    }
}

/// Evaluations of `f` at most per refined vertex (false position converges in about five).
const REFINE_STEPS: usize = 12;

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
        let theta = |p| field.eval(p).ok().map(|e| e.value);
        for (level, refined) in grid
            .level_lines(&[0.05, 0.1])
            .iter()
            .zip(grid.refined_level_lines(&[0.05, 0.1], theta))
        {
            let radius = (0.5 * (level.value / (1.0 - level.value)).ln()).exp();
            let off = |l: &LevelLine| {
                let points: Vec<_> = l.lines.iter().flatten().collect();
                assert!(points.len() > 20);
                points
                    .iter()
                    .map(|p| ((*p - goal).norm() - radius).abs())
                    .fold(0.0, f64::max)
            };
            // Traced: within a tenth of a cell (0.025); refined: on the circle.
            assert!(off(level) < 2.5e-3, "level {}: {}", level.value, off(level));
            assert!(
                off(&refined) < 1e-9,
                "level {}: {}",
                level.value,
                off(&refined)
            );
        }
    }

    /// On a linear field, the traced lines are the level lines themselves: the vertices sit
    /// where the samples (at the cells' centres) put them, not half a cell off.
    #[test]
    fn level_lines_of_a_linear_field_are_exact() {
        let f = |p: Vector2<f64>| Some(0.5 + 0.1 * (p.x + 0.3 * p.y));
        let grid = ThetaGrid::from_fn(Vector2::new(0.1, 0.2), 2.0, 20, f);
        let points: Vec<_> = grid.level_lines(&[0.5])[0]
            .lines
            .iter()
            .flatten()
            .copied()
            .collect();
        assert!(points.len() > 15, "{}", points.len());
        for p in points {
            let off = (p.x + 0.3 * p.y).abs() / 0.3f64.hypot(1.0);
            assert!(off < 1e-9, "{p} is {off} off the line");
        }
    }

    /// A steep radial field on a coarse grid (a circle of radius 1 across 10 cells): the
    /// refined vertices lie on the circle where linear interpolation cuts inside it.
    #[test]
    fn refined_level_lines_of_a_radial_field_lie_on_its_circles() {
        let centre = Vector2::new(0.33, -0.21);
        let f = |p: Vector2<f64>| Some(1.0 - (-(p - centre).norm_squared().powi(2)).exp());
        let grid = ThetaGrid::from_fn(Vector2::zeros(), 2.0, 20, f);
        let level = 1.0 - (-1.0f64).exp(); // the circle of radius 1
        let traced = &grid.level_lines(&[level])[0];
        let refined = &grid.refined_level_lines(&[level], f)[0];
        let points = |l: &LevelLine| l.lines.iter().flatten().copied().collect::<Vec<_>>();
        let (traced, refined) = (points(traced), points(refined));
        assert!(refined.len() > 30, "{}", refined.len());
        let off = |ps: &[Vector2<f64>]| {
            ps.iter()
                .map(|p| ((p - centre).norm() - 1.0).abs())
                .fold(0.0, f64::max)
        };
        assert!(
            off(&traced) > 1e-3,
            "linear interpolation: {}",
            off(&traced)
        );
        assert!(off(&refined) < 1e-9, "refined: {}", off(&refined));
    }
}
