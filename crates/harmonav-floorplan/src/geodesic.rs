//! [`Geodesic`]: the length `T(x)` of the shortest path from `x` to the goal inside the certified
//! region `W_δ` of a floor plan, on a grid, by fast marching (Sethian 1996): the eikonal equation
//!
//! ```text
//! |∇T| = 1 in W_δ,    T(x_d) = 0,
//! ```
//!
//! whose viscosity solution is the geodesic distance. Its unit descent `−∇T/|∇T|` points along
//! a shortest path: the *nominal heading* that the kinematic law's `HeadingPolicy::Auto`
//! follows within a cone about `−∇Θ` (`docs/maths.md` §13.3). It is a heading, not a
//! certificate: safety and convergence still come from `Θ` alone, so the grid's first-order
//! error (`O(cell)` in `T`, larger in its direction next to the goal and along the cut locus)
//! costs path length, never a guarantee.
//!
//! Only the walls are in it (the obstacles sensed later are not: `Θ` keeps the robot off them).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use nalgebra::Vector2;

use crate::plan::FloorMap;

/// The grid nodes [`Geodesic::new`] aims at: the cell grows beyond `δ/2` when the plan's
/// bounding box would need more (a 100 m × 100 m plan: 0.2 m cells), but never beyond half the
/// clearance `s + δ` that `W_δ` keeps from the walls, so a large plan for a small robot can
/// take more, up to 16 times as many (4 million nodes, about 40 MB while marching). 250 000 nodes take about 0.09 s (one parry distance query per node, then the
/// march).
pub const MAX_NODES: usize = 250_000;

/// The geodesic distance to the goal on a grid over `W_δ` (module docs).
#[derive(Clone, Debug)]
pub struct Geodesic {
    /// The grid node `(0, 0)`.
    origin: Vector2<f64>,
    /// The grid's spacing, m.
    cell: f64,
    nx: usize,
    ny: usize,
    /// `T` at the nodes, row-major (`j·nx + i`); `+∞` outside `W_δ` and where the goal cannot
    /// be reached.
    time: Vec<f64>,
    goal: Vector2<f64>,
}

/// A trial node of the march, ordered by its tentative `T` (smallest first).
#[derive(PartialEq)]
struct Trial(f64, usize);

impl Eq for Trial {}

impl PartialOrd for Trial {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Trial {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl Geodesic {
    /// `T` on `floor`'s `W_δ` (`FloorMap::clearance ≥ 0` at the node) towards `goal`, with the
    /// cell `min(max(δ/2, √(box area/`[`MAX_NODES`]`)), (s + δ)/2)`, but at least
    /// `√(box area/(16·`[`MAX_NODES`]`))`. The nodes within two cells
    /// of the goal start at their straight distance to it; the rest is marched. A node that no
    /// path of free nodes joins to them keeps `+∞`: a door narrower than a cell closes on the
    /// grid, and beyond it [`Geodesic::heading`] points along another route if there is one,
    /// and is `None` otherwise (the law then follows `−∇Θ`). If no node near the goal is free,
    /// `T` is `+∞` everywhere and the heading is `None` everywhere.
    #[must_use]
    pub fn new(floor: &FloorMap, goal: Vector2<f64>) -> Self {
        let (lo, hi) = floor.domain().bounding_box();
        let size = hi - lo;
        // A cell larger than half the clearance r = s + δ that W_δ keeps from the walls could
        // join nodes across a thin wall (the march links free neighbours, the seeds take the
        // straight distance): the cell never exceeds r/2, above MAX_NODES if need be, but
        // within 16·MAX_NODES (memory: a huge plan for a tiny robot gets the coarser cell, and
        // its heading may then cut a thin wall on the grid; Θ still keeps the robot out).
        let reach = floor.shrink() + floor.delta();
        let area = size.x * size.y;
        let cell = (0.5 * floor.delta())
            .max((area / MAX_NODES as f64).sqrt())
            .min(0.5 * reach)
            .max((area / (16 * MAX_NODES) as f64).sqrt());
        let nx = (size.x / cell).ceil() as usize + 1;
        let ny = (size.y / cell).ceil() as usize + 1;
        let origin = lo;
        let node = |i: usize, j: usize| origin + Vector2::new(i as f64, j as f64) * cell;
        let free: Vec<bool> = (0..nx * ny)
            .map(|n| floor.clearance(node(n % nx, n / nx)) >= 0.0)
            .collect();
        let mut time = vec![f64::INFINITY; nx * ny];
        let mut done = vec![false; nx * ny];
        let mut heap = BinaryHeap::new();
        let g = (goal - origin) / cell;
        let (gi, gj) = (g.x.floor() as i64, g.y.floor() as i64);
        for j in gj - 1..=gj + 2 {
            for i in gi - 1..=gi + 2 {
                if i < 0 || j < 0 || i as usize >= nx || j as usize >= ny {
                    continue;
                }
                let n = j as usize * nx + i as usize;
                if free[n] {
                    time[n] = (node(i as usize, j as usize) - goal).norm();
                    heap.push(Trial(time[n], n));
                }
            }
        }
        while let Some(Trial(t, n)) = heap.pop() {
            if done[n] || t > time[n] {
                continue;
            }
            done[n] = true;
            let (i, j) = (n % nx, n / nx);
            for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if a < 0 || b < 0 || a as usize >= nx || b as usize >= ny {
                    continue;
                }
                let m = b as usize * nx + a as usize;
                if done[m] || !free[m] {
                    continue;
                }
                let update = eikonal(&time, &done, nx, ny, m, cell);
                if update < time[m] {
                    time[m] = update;
                    heap.push(Trial(update, m));
                }
            }
        }
        Self {
            origin,
            cell,
            nx,
            ny,
            time,
            goal,
        }
    }

    /// The grid's spacing, m.
    #[must_use]
    pub fn cell(&self) -> f64 {
        self.cell
    }

    /// `T(x)`, bilinear between the four nodes of `x`'s cell; `None` when one of them is not
    /// reached (outside `W_δ`, within a cell of its edge, or cut off from the goal).
    #[must_use]
    pub fn distance(&self, x: Vector2<f64>) -> Option<f64> {
        let (t, fx, fy) = self.corners(x)?;
        Some((1.0 - fy) * ((1.0 - fx) * t[0] + fx * t[1]) + fy * ((1.0 - fx) * t[2] + fx * t[3]))
    }

    /// The nominal heading at `x`: `−∇T/|∇T|` of the bilinear `T` of [`Geodesic::distance`],
    /// or the straight unit vector to the goal within two cells of it (where the grid's `T` is
    /// the straight distance, and its bilinear gradient would be coarser). `None` where
    /// [`Geodesic::distance`] is, at the goal, and where the gradient vanishes.
    #[must_use]
    pub fn heading(&self, x: Vector2<f64>) -> Option<Vector2<f64>> {
        let to_goal = self.goal - x;
        let r = to_goal.norm();
        if r < 2.0 * self.cell {
            return (r > 0.0).then(|| to_goal / r);
        }
        let (t, fx, fy) = self.corners(x)?;
        let gx = (1.0 - fy) * (t[1] - t[0]) + fy * (t[3] - t[2]);
        let gy = (1.0 - fx) * (t[2] - t[0]) + fx * (t[3] - t[1]);
        let g = -Vector2::new(gx, gy);
        let norm = g.norm();
        (norm > 0.0 && norm.is_finite()).then(|| g / norm)
    }

    /// The nominal heading at `x` also within a cell of the edge of `W_δ`, where
    /// [`Geodesic::heading`] is `None`: there, the unit vector towards the reached node `q`
    /// between half a cell and two cells from `x` that minimises `|q − x| + T(q)` (a look-ahead
    /// of one segment on the grid's distance: `T(x) ≤ |q − x| + T(q)` for every `q` seen from
    /// `x`). The nearest nodes are left out: each node is a local minimum of
    /// `min_q (|q − x| + T(q))` over all `q`, so a robot that steps towards them comes back.
    /// `None` if no such node is reached.
    #[must_use]
    pub fn heading_near(&self, x: Vector2<f64>) -> Option<Vector2<f64>> {
        if let Some(d) = self.heading(x) {
            return Some(d);
        }
        let g = (x - self.origin) / self.cell;
        if !(g.x.is_finite() && g.y.is_finite()) {
            return None;
        }
        let (ci, cj) = (g.x.round(), g.y.round());
        let mut best: Option<(f64, Vector2<f64>)> = None;
        for dj in -2..=2 {
            for di in -2..=2 {
                let (i, j) = (ci + f64::from(di), cj + f64::from(dj));
                if i < 0.0 || j < 0.0 || i >= self.nx as f64 || j >= self.ny as f64 {
                    continue;
                }
                let t = self.time[j as usize * self.nx + i as usize];
                let to = self.origin + self.cell * Vector2::new(i, j) - x;
                let r = to.norm();
                let cost = r + t;
                if t.is_finite() && r >= 0.5 * self.cell && best.is_none_or(|(c, _)| cost < c) {
                    best = Some((cost, to / r));
                }
            }
        }
        best.map(|(_, d)| d)
    }

    /// The four node values of `x`'s cell (`(i, j)`, `(i+1, j)`, `(i, j+1)`, `(i+1, j+1)`) and
    /// `x`'s fractions in it, if all four are finite.
    fn corners(&self, x: Vector2<f64>) -> Option<([f64; 4], f64, f64)> {
        let g = (x - self.origin) / self.cell;
        // Also refuses NaN, and points beyond the grid before the casts (which saturate).
        let (top_x, top_y) = ((self.nx - 1) as f64, (self.ny - 1) as f64);
        if !((0.0..top_x).contains(&g.x) && (0.0..top_y).contains(&g.y)) {
            return None;
        }
        let (i, j) = (g.x.floor() as usize, g.y.floor() as usize);
        if i + 1 >= self.nx || j + 1 >= self.ny {
            return None;
        }
        let n = j * self.nx + i;
        let t = [
            self.time[n],
            self.time[n + 1],
            self.time[n + self.nx],
            self.time[n + self.nx + 1],
        ];
        t.iter()
            .all(|v| v.is_finite())
            .then(|| (t, g.x - i as f64, g.y - j as f64))
    }
}

/// The upwind update of node `m` from its accepted neighbours (second-order fast marching,
/// Sethian 1999). Along each axis the smaller accepted neighbour `T₁` gives the difference
/// `(t − T₁)/cell`, or, when the next node beyond it is accepted with `T₂ ≤ T₁`, the one-sided
/// second-order `(3t − 4T₁ + T₂)/(2cell)`; both are `√α·(t − β)/cell` with `(α, β) = (1, T₁)`
/// or `(9/4, (4T₁ − T₂)/3)`. The update is the larger root `t` of
///
/// ```text
/// Σ_axes α (t − β)² = cell²,
/// ```
///
/// and, when it has none or it lies below an axis' `T₁` (the upwind condition), the one-sided
/// first-order `min T₁ + cell`.
fn eikonal(time: &[f64], done: &[bool], nx: usize, ny: usize, m: usize, cell: f64) -> f64 {
    let (i, j) = (m % nx, m / nx);
    let accepted = |n: usize| if done[n] { time[n] } else { f64::INFINITY };
    // (T₁, α, β) along one axis from its neighbours at −1 and +1 (`near`) and the next ones
    // at −2 and +2 (`far`), `None` off the grid.
    let axis = |near: [Option<usize>; 2], far: [Option<usize>; 2]| {
        let mut best: Option<(f64, f64, f64)> = None;
        for (n1, n2) in near.into_iter().zip(far) {
            let Some(n1) = n1 else { continue };
            let t1 = accepted(n1);
            if !t1.is_finite() || best.is_some_and(|(b, _, _)| b <= t1) {
                continue;
            }
            let t2 = n2.map_or(f64::INFINITY, accepted);
            best = Some(if t2 <= t1 {
                (t1, 2.25, (4.0 * t1 - t2) / 3.0)
            } else {
                (t1, 1.0, t1)
            });
        }
        best
    };
    let x_axis = axis(
        [(i >= 1).then(|| m - 1), (i + 1 < nx).then(|| m + 1)],
        [(i >= 2).then(|| m - 2), (i + 2 < nx).then(|| m + 2)],
    );
    let y_axis = axis(
        [(j >= 1).then(|| m - nx), (j + 1 < ny).then(|| m + nx)],
        [
            (j >= 2).then(|| m - 2 * nx),
            (j + 2 < ny).then(|| m + 2 * nx),
        ],
    );
    let one_sided = [x_axis, y_axis]
        .iter()
        .flatten()
        .map(|(t1, _, _)| t1 + cell)
        .fold(f64::INFINITY, f64::min);
    let (mut sa, mut sab, mut sabb) = (0.0, 0.0, 0.0);
    for (_, a, b) in [x_axis, y_axis].into_iter().flatten() {
        sa += a;
        sab += a * b;
        sabb += a * b * b;
    }
    let disc = sab * sab - sa * (sabb - cell * cell);
    if sa == 0.0 || disc < 0.0 {
        return one_sided;
    }
    let t = (sab + disc.sqrt()) / sa;
    let upwind = [x_axis, y_axis].iter().flatten().all(|(t1, _, _)| t >= *t1);
    if upwind { t.min(one_sided) } else { one_sided }
}
