//! Radial hulls of discs: the tabulated star about a point that contains a union of discs,
//! and the dilation of a star by a disc as such a hull (it never folds, where an offset may).
//!
//! **The construction** (eq. radialhull). For discs `B(x_k, ρ_k)` and a centre `c`, the ray
//! `c + s·u(θ)` leaves the disc `k` at
//!
//! ```text
//! e_k(θ) = t cos α + √(ρ² − t² sin² α),   t = |x_k − c|, α = θ − arg(x_k − c)          (eq. exit)
//! ```
//!
//! when it meets it (`|sin α| ≤ ρ/t`, `cos α > 0`, or any `α` when `t ≤ ρ`), and `e_k`
//! decreases in `|α|` (its derivative is `−t sin α (1 + t cos α/√(ρ² − t² sin² α))`, and the
//! bracket is positive where the ray meets the disc). So the largest exit over a cell
//! `[θ_i, θ_{i+1}]` of the grid `θ_i = 2πi/G` is `e_k` at the `α` of the cell nearest 0:
//! `M_i = max_k max_{cell i} e_k`, exactly. The table takes
//!
//! ```text
//! R_i = max(M_{i−1}, M_i),   R'_i = the harmonic mean of the neighbouring secants (PCHIP),
//! ```
//!
//! 0 where they differ in sign. With that slope each cubic Hermite cell is monotone (its end
//! slopes are at most twice its secant, inside Fritsch–Carlson's region), so on cell `i`
//! `R ≥ min(R_i, R_{i+1}) ≥ M_i`: every disc lies in the star, whatever the grid. A star that
//! holds the discs covering the boundary of a bounded set holds the set, about any centre (the
//! ray through a point of the set leaves it at a boundary point). Cells no disc reaches (the
//! centre outside the union) take the smallest `M` of the others, so `R > 0`.
//!
//! Unlike a Fourier sum, the hull has no Gibbs undershoot for a raise to undo: on cell `i` it
//! is at most `max(M_{i−1}, M_i, M_{i+1})`, the union's own radial function taken two cells
//! wide, whatever the union's shape.

use std::f64::consts::TAU;

use nalgebra::Vector2;

use crate::error::ShapeError;
use crate::shape::StarShape;

/// Cells of a radial hull's table, `G` (0.35° each).
pub const HULL_CELLS: usize = 1024;

/// `e_k` of eq. exit for `t = |x − c|`, disc radius `rho` and `|α|` (rad).
fn exit(t: f64, rho: f64, alpha: f64) -> f64 {
    let (s, co) = alpha.sin_cos();
    t * co + (rho * rho - t * t * s * s).max(0.0).sqrt()
}

impl StarShape {
    /// The radial hull about `centre` of the discs `(x_k, ρ_k)` (module docs, eq.
    /// radialhull): a tabulated star ([`StarShape::offset`]'s kind) on [`HULL_CELLS`]
    /// directions that contains every disc.
    ///
    /// Errors on `discs` when there is none, or a centre or radius is not finite, or a radius
    /// is not positive; on `centre` when it is not finite.
    pub fn radial_hull(
        centre: Vector2<f64>,
        discs: &[(Vector2<f64>, f64)],
    ) -> Result<StarShape, ShapeError> {
        StarShape::tabulated(centre, &radial_hull_radii(centre, discs)?)
    }

    /// The star about `centre` with the radii `R_i` at the directions `θ_i = 2πi/G`
    /// (`G = radii.len() ≥ 8`) and monotone cubic Hermite cells in between: `R'_i` the harmonic
    /// mean of the neighbouring secants, 0 where they differ in sign (PCHIP), so `R` stays
    /// between its cell's end values (module docs). `ρ_min` is sampled at four points per cell.
    /// A radial hull is `tabulated` of its radii ([`StarShape::radial_hull`]), so this rebuilds
    /// it exactly.
    ///
    /// Errors on `radii` unless there are at least 8, each finite and positive; on `centre`
    /// unless it is finite.
    pub fn tabulated(centre: Vector2<f64>, radii: &[f64]) -> Result<StarShape, ShapeError> {
        if !(centre.x.is_finite() && centre.y.is_finite()) {
            return Err(ShapeError::NonFinite { field: "centre" });
        }
        let g = radii.len();
        if g < 8 || radii.iter().any(|r| !r.is_finite() || *r <= 0.0) {
            return Err(ShapeError::Invalid {
                field: "radii",
                problem: format!(
                    "a tabulated star needs at least 8 radii, each finite and positive (got {g})"
                ),
            });
        }
        let step = TAU / g as f64;
        let secant: Vec<f64> = (0..g)
            .map(|i| (radii[(i + 1) % g] - radii[i]) / step)
            .collect();
        let values: Vec<(f64, f64)> = (0..g)
            .map(|i| {
                let (a, b) = (secant[(i + g - 1) % g], secant[i]);
                let slope = if a * b > 0.0 {
                    2.0 * a * b / (a + b)
                } else {
                    0.0
                };
                (radii[i], slope)
            })
            .collect();
        let rho = table_rho_min(&values);
        StarShape::table(centre, values, rho, true, "radii")
    }

    /// This shape dilated by `r ≥ 0` (the Minkowski sum with `B(0, r)`), enclosed in the radial
    /// hull about the centre of the discs of radius `r + δ + h/2` on points of the certified
    /// outline at most `h` apart (every boundary point lies within `δ` of the outline and
    /// within `h/2` of such a point). Contains the dilation: its boundary lies in
    /// `∂(shape) ⊕ B(r)`, inside the discs. Where [`StarShape::offset`] folds (a concave
    /// corner sharper than `r`) this does not; it is larger by at most `2δ + h/2` (the disc
    /// centres lie on chords, up to `δ` off the curve) plus two cells' widening and the
    /// shadows of the dilation about the centre. `ρ_min` is the smaller of the hull's sampled
    /// one and `ρ_min + r`.
    ///
    /// Errors on `robot.radius` if `r` is negative or not finite, on `check_spacing` unless
    /// `h > 0` is finite.
    pub fn dilated_hull(&self, r: f64, h: f64) -> Result<StarShape, ShapeError> {
        if !r.is_finite() || r < 0.0 {
            return Err(ShapeError::Invalid {
                field: "robot.radius",
                problem: format!("a dilation needs a finite r ≥ 0, got {r}"),
            });
        }
        if !h.is_finite() || h <= 0.0 {
            return Err(ShapeError::Invalid {
                field: "check_spacing",
                problem: format!("must be a finite h > 0, got {h}"),
            });
        }
        let outline = self.certified();
        let n = outline.len();
        let radius = r + outline.delta + 0.5 * h;
        let mut discs = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (outline.vertex(i), outline.vertex((i + 1) % n));
            let pieces = ((b - a).norm() / h).ceil().max(1.0) as usize;
            discs.extend((0..pieces).map(|j| (a + (b - a) * (j as f64 / pieces as f64), radius)));
        }
        let hull = StarShape::radial_hull(self.centre(), &discs)?;
        // The hull's own sampled ρ (its cells may bend tighter than the dilation's r + ρ).
        let rho = hull.rho_min().min(self.rho_min() + r);
        Ok(hull.with_rho_min(rho))
    }
}

/// The radii `R_i` of [`StarShape::radial_hull`] at `θ_i = 2πi/G`, `G` = [`HULL_CELLS`]
/// (eq. radialhull: `R_i = max(M_{i−1}, M_i)`, lifted by 1e-12 for the rounding of eq. exit);
/// errors as [`StarShape::radial_hull`].
pub fn radial_hull_radii(
    centre: Vector2<f64>,
    discs: &[(Vector2<f64>, f64)],
) -> Result<Vec<f64>, ShapeError> {
    if !(centre.x.is_finite() && centre.y.is_finite()) {
        return Err(ShapeError::NonFinite { field: "centre" });
    }
    let bad = |problem: &str| ShapeError::Invalid {
        field: "discs",
        problem: problem.into(),
    };
    if discs.is_empty() {
        return Err(bad("a radial hull needs at least one disc"));
    }
    let g = HULL_CELLS;
    let step = TAU / g as f64;
    let mut m = vec![f64::NEG_INFINITY; g];
    for &(x, rho) in discs {
        if !(x.x.is_finite() && x.y.is_finite() && rho.is_finite()) {
            return Err(ShapeError::NonFinite { field: "discs" });
        }
        if rho <= 0.0 {
            return Err(bad("every disc radius must be positive"));
        }
        let v = x - centre;
        let t = v.norm();
        let beta = v.y.atan2(v.x).rem_euclid(TAU);
        if t <= rho {
            // The disc holds the centre: every ray leaves it.
            for (i, mi) in m.iter_mut().enumerate() {
                let d = (beta - i as f64 * step).rem_euclid(TAU);
                let alpha = if d <= step {
                    0.0
                } else {
                    (d - step).min(TAU - d)
                };
                *mi = mi.max(exit(t, rho, alpha));
            }
            continue;
        }
        disc_cells(t, beta, rho, g, |i, alpha| {
            m[i] = m[i].max(exit(t, rho, alpha))
        });
    }
    if m.contains(&0.0) {
        return Err(bad(
            "the centre lies on a disc's circle (a radius of 0 about it)",
        ));
    }
    let floor = m
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    // Rounding of eq. exit: a few ulp of t + ρ.
    let lift = 1.0 + 1e-12;
    let r: Vec<f64> = (0..g)
        .map(|i| {
            let (a, b) = (m[(i + g - 1) % g], m[i]);
            let v = a.max(b);
            // No disc reached either cell: the floor. An exit that overflowed is +∞ and
            // stays so, for `tabulated` to refuse.
            if v > f64::NEG_INFINITY { v } else { floor }.max(floor) * lift
        })
        .collect();
    Ok(r)
}

/// For a disc of radius `rho` at distance `t > rho` from the centre in the direction `beta`
/// (rad, in `[0, 2π)`), each cell `i` of the grid of `g` cells `[2πi/g, 2π(i+1)/g]` whose rays
/// meet it, with the `|α|` of the cell nearest the disc's direction (`α = θ − beta`; the ray
/// meets the disc iff `|α| ≤ asin(ρ/t)`). Eq. exit and eq. entry (module [`crate::carve`])
/// are monotone in `|α|`, so that `α` gives their extreme over the cell.
pub(crate) fn disc_cells(t: f64, beta: f64, rho: f64, g: usize, mut f: impl FnMut(usize, f64)) {
    let step = TAU / g as f64;
    let half = (rho / t).asin();
    let first = ((beta - half) / step).floor() as i64;
    let last = ((beta + half) / step).floor() as i64;
    for k in first..=last {
        let (lo, hi) = (k as f64 * step, (k + 1) as f64 * step);
        let alpha = (beta.clamp(lo, hi) - beta).abs();
        if alpha <= half {
            f(k.rem_euclid(g as i64) as usize, alpha);
        }
    }
}

/// The smallest radius of curvature of the convex parts of a tabulated star, sampled at four
/// points per cell (as [`StarShape::fourier_star`] samples its grid):
/// `ρ = (R² + R'²)^{3/2} / (R² + 2R'² − R R'')` where the denominator is positive.
fn table_rho_min(values: &[(f64, f64)]) -> f64 {
    let g = values.len();
    let step = TAU / g as f64;
    let mut rho = f64::INFINITY;
    for i in 0..g {
        let ((ra, da), (rb, db)) = (values[i], values[(i + 1) % g]);
        for q in 0..=4 {
            let t = q as f64 / 4.0;
            let r = (2.0 * t.powi(3) - 3.0 * t * t + 1.0) * ra
                + (t.powi(3) - 2.0 * t * t + t) * step * da
                + (-2.0 * t.powi(3) + 3.0 * t * t) * rb
                + (t.powi(3) - t * t) * step * db;
            let dr = ((6.0 * t * t - 6.0 * t) * ra
                + (3.0 * t * t - 4.0 * t + 1.0) * step * da
                + (-6.0 * t * t + 6.0 * t) * rb
                + (3.0 * t * t - 2.0 * t) * step * db)
                / step;
            let ddr = ((12.0 * t - 6.0) * ra
                + (6.0 * t - 4.0) * step * da
                + (-12.0 * t + 6.0) * rb
                + (6.0 * t - 2.0) * step * db)
                / (step * step);
            let den = r * r + 2.0 * dr * dr - r * ddr;
            if den > 0.0 {
                rho = rho.min((r * r + dr * dr).powf(1.5) / den);
            }
        }
    }
    rho.max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Every disc lies in its hull: points on each disc's circle are inside the star (by the
    /// radial function, densely between the grid's directions), for random discs about random
    /// centres, some discs holding the centre. Fails if a cell's maximum or the slopes are
    /// wrong (tested: with the arithmetic mean of the secants as slope, or `R_i = M_i` alone, points poke out).
    #[test]
    fn the_hull_holds_every_disc() {
        let mut seed = 7u64;
        for trial in 0..40 {
            let c = Vector2::new(lcg(&mut seed) - 0.5, lcg(&mut seed) - 0.5);
            let discs: Vec<(Vector2<f64>, f64)> = (0..1 + trial % 9)
                .map(|_| {
                    let x = Vector2::new(3.0 * lcg(&mut seed) - 1.5, 3.0 * lcg(&mut seed) - 1.5);
                    (x, 0.02 + 0.8 * lcg(&mut seed))
                })
                .collect();
            let hull = StarShape::radial_hull(c, &discs).unwrap();
            for &(x, rho) in &discs {
                for j in 0..2000 {
                    let a = TAU * j as f64 / 2000.0;
                    let p = x + rho * Vector2::new(a.cos(), a.sin());
                    let v = p - c;
                    let (r, _) = hull.radius(v.y.atan2(v.x));
                    assert!(
                        v.norm() <= r * (1.0 + 1e-9),
                        "trial {trial}: {} > {r}",
                        v.norm()
                    );
                }
            }
        }
    }

    /// The hull is tight: for one disc about its own centre it is that disc to within the
    /// rounding lift, and for a disc seen from outside its table follows eq. exit to within
    /// two cells' turn (the largest `R` is `t + ρ`, reached).
    #[test]
    fn the_hull_of_one_disc_is_that_disc() {
        let c = Vector2::new(0.3, -0.2);
        let hull = StarShape::radial_hull(c, &[(c, 0.7)]).unwrap();
        let (lo, hi) = hull.radius_bounds();
        assert!(
            (lo - 0.7).abs() < 1e-9 && (hi - 0.7).abs() < 1e-9,
            "{lo} {hi}"
        );
        let x = c + Vector2::new(2.0, 0.0);
        let hull = StarShape::radial_hull(c, &[(x, 0.5), (c, 0.1)]).unwrap();
        assert!((hull.radius(0.0).0 - 2.5).abs() < 1e-9);
        // Across the disc the radial function is eq. exit to within the grid's turn.
        for j in 1..20 {
            let alpha = (0.5f64 / 2.0).asin() * j as f64 / 20.0;
            let exact = exit(2.0, 0.5, alpha);
            let r = hull.radius(alpha).0;
            let near = exit(2.0, 0.5, (alpha - 2.0 * TAU / HULL_CELLS as f64).max(0.0));
            assert!(
                r >= exact - 1e-9 && r <= near + 1e-9,
                "{alpha}: {r} {exact} {near}"
            );
        }
    }

    /// The dilated hull holds the true dilation and stays close to it: a circle of radius 1
    /// dilated by 0.3 is within `δ + h/2` (+ rounding) of the circle of radius 1.3, and a
    /// bow tie whose offset folds dilates without error, holding its boundary pushed out by r.
    #[test]
    fn the_dilated_hull_holds_the_dilation_and_never_folds() {
        let disc = StarShape::circle(Vector2::zeros(), 1.0).unwrap();
        let grown = disc.dilated_hull(0.3, 0.01).unwrap();
        let (lo, hi) = grown.radius_bounds();
        assert!(lo >= 1.3 && hi <= 1.3 + 0.006 + 1e-4, "{lo} {hi}");
        let tie = StarShape::fourier_star(Vector2::zeros(), 0.3, &[(2, 0.25, 0.0)]).unwrap();
        assert!(tie.offset(0.2).is_err());
        let grown = tie.dilated_hull(0.2, 0.01).unwrap();
        for j in 0..4000 {
            let th = TAU * j as f64 / 4000.0;
            let p = tie.boundary_point(th);
            for k in 0..16 {
                let a = TAU * k as f64 / 16.0;
                let q = p + 0.2 * Vector2::new(a.cos(), a.sin());
                assert!(grown.contains(q) || grown.signed_distance(q) < 1e-9);
            }
        }
        // Tighter than the disc the navigator fell back to before (radius max R + r).
        assert!(grown.area() < std::f64::consts::PI * 0.75f64.powi(2) * 0.8);
    }

    /// Bad input is a typed error, never a panic or a NaN star.
    #[test]
    fn bad_discs_are_refused() {
        let c = Vector2::zeros();
        assert!(StarShape::radial_hull(c, &[]).is_err());
        assert!(StarShape::radial_hull(c, &[(Vector2::new(1.0, 0.0), 0.0)]).is_err());
        assert!(StarShape::radial_hull(c, &[(Vector2::new(f64::NAN, 0.0), 0.1)]).is_err());
        assert!(StarShape::radial_hull(Vector2::new(f64::INFINITY, 0.0), &[(c, 0.1)]).is_err());
        let disc = StarShape::circle(c, 1.0).unwrap();
        assert!(disc.dilated_hull(-0.1, 0.01).is_err());
        assert!(disc.dilated_hull(0.1, 0.0).is_err());
    }
}
