//! The 2-D program of the mover filter (`docs/movers.md` §2): the velocity closest to a nominal
//! one subject to half-planes `n_i·u ≥ a_i` and a disc `|u| ≤ r`, and, when no velocity meets
//! them all, the one that minimises the largest shortfall of the soft rows.
//!
//! ```text
//! project:   argmin |u − p|²   s.t.  n_i·u ≥ a_i − s·[i soft]  (all i),   |u| ≤ r
//! minimax:   s* = min { s ≥ 0 : the set above is not empty }
//! ```
//!
//! `project` is the incremental algorithm for a strictly convex objective over a 2-D polygon
//! (de Berg et al., *Computational Geometry*, ch. 4): the rows are taken in order; when the
//! optimum so far violates row `i`, the new optimum lies on row `i`'s line, a 1-D problem over
//! the rows before it and the disc. `O(n²)` in the worst case, no allocation. `minimax`
//! bisects on `s` (the set grows with `s`, and `s = max(0, max a_soft)` is feasible whenever the
//! hard rows admit `u = 0`, which the filter guarantees by building them with `a ≤ 0`).

use nalgebra::Vector2;

/// One half-plane `n·u ≥ a` on the held velocity, from mover `mover`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Row {
    /// The unit normal, from the mover's reported centre towards the robot (tilted by up to
    /// `atan(η/(1 − η))`, `η < 1`, for a reciprocal mover with a position error, eq. robust).
    pub n: Vector2<f64>,
    /// The bound.
    pub a: f64,
    /// Hard rows (a reciprocal robot's) are kept whatever happens; soft rows (a
    /// non-cooperative mover's) may be violated, by the least shortfall, when nothing meets them
    /// all.
    pub hard: bool,
    /// The mover's index.
    pub mover: usize,
    /// `d_j ≤ 0`: the robot is already within the mover's margin (a late report, or a period
    /// that could not be certified): the row leads out, but no command is certified.
    pub inside: bool,
}

impl Row {
    /// The bound with the soft rows relaxed by `s`.
    fn bound(&self, s: f64) -> f64 {
        if self.hard { self.a } else { self.a - s }
    }

    /// `n·u − a`, the slack of `u` (negative: violated).
    pub(crate) fn slack(&self, u: Vector2<f64>) -> f64 {
        self.n.dot(&u) - self.a
    }
}

/// Tolerance of the 1-D interval, relative to the disc's radius: an interval empty by less is
/// a single point to rounding.
const POINT: f64 = 1e-12;

/// `argmin |u − p|²` over the rows (soft ones relaxed by `s`) and `|u| ≤ r`; `Err(i)` when the
/// set is empty, `i` the row at which that was found.
pub(crate) fn project(
    rows: &[Row],
    r: f64,
    p: Vector2<f64>,
    s: f64,
) -> Result<Vector2<f64>, usize> {
    let norm = p.norm();
    let mut u = if norm > r { p * (r / norm) } else { p };
    for (i, row) in rows.iter().enumerate() {
        if row.n.dot(&u) >= row.bound(s) {
            continue;
        }
        u = on_line(&rows[..i], row, r, p, s).ok_or(i)?;
    }
    Ok(u)
}

/// The point of `line`'s boundary `n·u = a` closest to `p` within the disc and the rows
/// `before`; `None` if there is none.
fn on_line(before: &[Row], line: &Row, r: f64, p: Vector2<f64>, s: f64) -> Option<Vector2<f64>> {
    let a = line.bound(s);
    let half = r * r - a * a;
    if half < -(POINT * r).powi(2).max(f64::MIN_POSITIVE) {
        return None;
    }
    let root = half.max(0.0).sqrt();
    let origin = a * line.n;
    let dir = Vector2::new(-line.n.y, line.n.x);
    let (mut lo, mut hi) = (-root, root);
    for row in before {
        // row.n·(origin + t·dir) ≥ b  ⇔  c·t ≥ b − row.n·origin.
        let c = row.n.dot(&dir);
        let b = row.bound(s) - row.n.dot(&origin);
        if c.abs() <= f64::EPSILON {
            // Parallel: the whole line is in or out of the row.
            if b > POINT * (1.0 + r) {
                return None;
            }
        } else if c > 0.0 {
            lo = lo.max(b / c);
        } else {
            hi = hi.min(b / c);
        }
    }
    if lo > hi {
        if lo - hi > POINT * (1.0 + r) {
            return None;
        }
        let mid = 0.5 * (lo + hi);
        return Some(origin + mid * dir);
    }
    let t = dir.dot(&(p - origin)).clamp(lo, hi);
    Some(origin + t * dir)
}

/// The least largest shortfall `s*` of the soft rows over the hard rows and `|u| ≤ r`, and the
/// velocity closest to `p` that attains it (to a relative `1e-12`); `None` when the hard rows
/// and the disc alone are empty (not expected: the filter builds them so that `u = 0` meets
/// them).
pub(crate) fn minimax(rows: &[Row], r: f64, p: Vector2<f64>) -> Option<(Vector2<f64>, f64)> {
    let mut hi = rows
        .iter()
        .filter(|row| !row.hard)
        .fold(0.0_f64, |m, row| m.max(row.a));
    project(rows, r, p, hi).ok()?;
    let mut lo = 0.0;
    // Bisection: the feasible set grows with `s`.
    for _ in 0..128 {
        if hi - lo <= 1e-12 * (1.0 + hi) {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if project(rows, r, p, mid).is_ok() {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    project(rows, r, p, hi).ok().map(|u| (u, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonav_transform::random::Rng;

    fn row(angle: f64, a: f64, hard: bool) -> Row {
        Row {
            n: Vector2::new(angle.cos(), angle.sin()),
            a,
            hard,
            mover: 0,
            inside: false,
        }
    }

    /// The independent reference: every KKT candidate of the program (the unconstrained point,
    /// its projections on each line and on the circle, every line–line and line–circle
    /// vertex), the feasible one closest to `p`.
    fn oracle(rows: &[Row], r: f64, p: Vector2<f64>) -> Option<Vector2<f64>> {
        let mut candidates = vec![
            p,
            if p.norm() > 0.0 {
                p * (r / p.norm())
            } else {
                p
            },
        ];
        for (i, a) in rows.iter().enumerate() {
            let origin = a.a * a.n;
            let dir = Vector2::new(-a.n.y, a.n.x);
            candidates.push(origin + dir.dot(&(p - origin)) * dir);
            let half = r * r - a.a * a.a;
            if half >= 0.0 {
                candidates.push(origin + half.sqrt() * dir);
                candidates.push(origin - half.sqrt() * dir);
            }
            for b in &rows[i + 1..] {
                let det = a.n.x * b.n.y - a.n.y * b.n.x;
                if det.abs() > 1e-12 {
                    let x = (a.a * b.n.y - a.n.y * b.a) / det;
                    let y = (a.n.x * b.a - a.a * b.n.x) / det;
                    candidates.push(Vector2::new(x, y));
                }
            }
        }
        let ok = |u: &Vector2<f64>| {
            u.norm() <= r * (1.0 + 1e-9) && rows.iter().all(|w| w.slack(*u) >= -1e-9)
        };
        candidates
            .into_iter()
            .filter(ok)
            .min_by(|a, b| (a - p).norm().total_cmp(&(b - p).norm()))
    }

    /// `project` agrees with the exhaustive KKT enumeration on 2 000 seeded programs of 1 to 8
    /// rows, in value and in feasibility.
    #[test]
    fn the_projection_is_the_kkt_oracle() {
        let mut rng = Rng::new(7);
        let mut unit = || rng.uniform(0.0, 1.0);
        let (mut feasible, mut empty) = (0, 0);
        for _ in 0..2000 {
            let n = 1 + (unit() * 8.0) as usize;
            let r = 0.2 + 2.0 * unit();
            let rows: Vec<Row> = (0..n)
                .map(|_| {
                    row(
                        unit() * std::f64::consts::TAU,
                        2.0 * r * (unit() - 0.6),
                        false,
                    )
                })
                .collect();
            let p = Vector2::new(4.0 * unit() - 2.0, 4.0 * unit() - 2.0);
            match (project(&rows, r, p, 0.0), oracle(&rows, r, p)) {
                (Ok(u), Some(o)) => {
                    feasible += 1;
                    assert!(
                        (u - o).norm() < 1e-7 * (1.0 + r),
                        "{u:?} vs {o:?} for {rows:?}"
                    );
                }
                (Err(_), None) => empty += 1,
                (got, want) => panic!("{got:?} vs {want:?} for {rows:?}, r = {r}, p = {p:?}"),
            }
        }
        assert!(
            feasible > 200 && empty > 200,
            "{feasible} feasible, {empty} empty"
        );
    }

    /// Two movers closing from opposite sides: no velocity meets both rows; the least shortfall
    /// is shared between them and the hard row holds.
    #[test]
    fn the_least_shortfall_of_a_pincer_is_shared() {
        let rows = [
            row(0.0, 0.5, false),
            row(std::f64::consts::PI, 0.5, false),
            row(0.5 * std::f64::consts::PI, -0.1, true),
        ];
        assert!(project(&rows, 1.0, Vector2::zeros(), 0.0).is_err());
        let (u, s) = minimax(&rows, 1.0, Vector2::zeros()).unwrap();
        assert!((s - 0.5).abs() < 1e-9, "{s}");
        assert!(
            rows[2].slack(u) >= -1e-12 && u.norm() <= 1.0 + 1e-12,
            "{u:?}"
        );
    }
}
