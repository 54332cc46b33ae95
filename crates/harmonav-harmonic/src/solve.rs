//! The iterative solve of the boundary-element system (docs/maths/13-harmonic-scaling.md): the
//! same equations as the dense LU of `crate::map`, solved by restarted GMRES with a multipole
//! matrix–vector product and a two-level preconditioner, in `O(N)` memory and `O(N)` work per
//! iteration instead of `8(N + M + 1)²` bytes and `(2/3)(N + M + 1)³` flops.
//!
//! **The product.** `A x` for `x = (k, p, c)`: the single-layer block `G k`,
//! `G_ij = W_j(c_i)`, is split as `G = G_near + G_far`. `G_far k = 2 Re Σ_j k_j G_j(c_i)` over
//! the pieces of the elements outside the 3 × 3 leaves about `c_i` comes from
//! `harmonav_multipole::Operator` (`W_j = 2 Re G_j`); `G_near` holds the rest exactly, as a
//! sparse matrix of the closed form on each near piece (`crate::kernel::interval`), computed
//! once. The puncture columns, the constant column and the charge rows are applied exactly.
//!
//! **The preconditioner** (`M⁻¹ r = P A_c⁻¹ R r + Σ_I E_I S_I⁻¹ [r_I; 0]`, right-applied):
//! the elements are grouped into clusters of at most `b` consecutive elements of one ring.
//! - *Local*, per cluster `I`: `S_I = [[G_II, 1], [ℓ_Iᵀ, 0]]` (its own dense block, exact, with
//!   a constant and a zero-charge row, `ℓ_j = |E_j|/h̄`): the correction it gives has zero
//!   charge on the cluster, so it changes no charge row, and the constant part of `r_I` is left
//!   to the coarse level.
//! - *Coarse*: one unknown per cluster (a density constant on it) plus the `M` punctures and
//!   the constant: `A_c` is `A` restricted to that space (`R` averages each cluster's rows, the
//!   charge rows are kept), with `Σ_{j∈J} G_ij` exact between near clusters and
//!   `L_J ln|c̄_I − c̄_J|²` between far ones. The charge rows and the puncture and constant
//!   columns are exact in it, so the constraints are solved at the coarse level.
//!
//! The single layer is a first-kind operator (its condition grows like `N`); block Jacobi
//! alone leaves the smooth modes, which the coarse level takes.
//!
//! **Relaxation** (inexact Krylov; Bouras & Frayssé, SIAM J. Matrix Anal. Appl. 26, 2005;
//! Simoncini & Szyld, SIAM J. Sci. Comput. 25, 2003): once GMRES's residual estimate has
//! fallen to `‖r_k‖`, an error in the next product of up to about `ε‖b‖/‖r_k‖` moves the
//! attainable residual by about `ε‖b‖`, so the multipole part of the Arnoldi products is taken
//! within `PRODUCT_TOLERANCE·‖b‖/‖r_k‖`, at most `RELAXED_TOLERANCE` (`Operator::apply_order`:
//! a lower expansion order, `p` = 49 down to 26). Each cycle's true residual `b − A x` is a
//! full-order product, and GMRES stops only when that one is below `rtol‖b‖` (or at
//! `MAX_ITERATIONS`, when the map then accepts up to `MAX_SOLVE_RESIDUAL` or refuses): the
//! relaxed products can cost restarts, which bring that cap nearer, but not the accuracy of a
//! solve that converges.

use std::ops::Range;

use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, Solve};
use harmonav_multipole::{C64, FmmError, Operator, Options as FmmOptions, Piece, Source};

use crate::kernel::{self, Panel};

mod gmres;
mod near;

use gmres::Gmres;
use near::NearMatrix;

/// The tolerance of the multipole product: `|Δ(G_far k)_i| ≤ tol·Σ_j 2|k_j||E_j|`.
pub(crate) const PRODUCT_TOLERANCE: f64 = 1e-12;

/// The loosest tolerance of a relaxed product (module docs, "Relaxation").
const RELAXED_TOLERANCE: f64 = 1e-6;

/// GMRES stops at `‖b − A x‖₂ ≤ rtol·‖b‖₂` (its recursive estimate; the true residual is
/// measured after).
pub(crate) const GMRES_TOLERANCE: f64 = 1e-12;

/// Pieces per occupied leaf the multipole tree aims at.
const LEAF_SIZE: usize = 64;

/// What the iterative solve reports.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Stats {
    /// GMRES iterations, both components.
    pub iterations: usize,
    /// `‖b − A x‖₂/‖b‖₂`, the worse component, from a last product.
    pub residual: f64,
    /// The multipole tree, the near matrix and the preconditioner.
    pub assembly: std::time::Duration,
}

/// The assembled operator: the multipole tree, the near matrix (rows by collocation point).
struct System<'a> {
    panels: &'a [Panel],
    ring_of: Vec<usize>,
    holes: usize,
    mean: f64,
    far: Operator,
    near: NearMatrix,
}

impl System<'_> {
    fn size(&self) -> usize {
        self.panels.len() + self.holes + 1
    }

    /// `G_far (2k)` at every collocation point into `far`, from the densities `k` of `x`,
    /// within `relaxation` times [`PRODUCT_TOLERANCE`], at most `loosest`.
    fn far_part(&self, x: &[f64], (relaxation, loosest): (f64, f64), (weights, far): &mut Scratch) {
        let n = self.panels.len();
        weights.clear();
        weights.extend(x[..n].iter().map(|k| 2.0 * k));
        far.resize(n, 0.0);
        let tolerance = (PRODUCT_TOLERANCE * relaxation).min(loosest);
        self.far
            .apply_order(weights, far, self.far.order_for(tolerance));
    }

    /// Row `i < N` of `A x` from its single-layer part `s` (far and near): minus the ring's
    /// puncture, plus the constant.
    fn collocation_row(&self, i: usize, x: &[f64], mut s: f64) -> f64 {
        let n = self.panels.len();
        let r = self.ring_of[i];
        if r > 0 {
            s -= x[n + r - 1];
        }
        s + x[n + self.holes]
    }

    /// The charge rows `y[N..]` of `A x`.
    fn charge_rows(&self, x: &[f64], y: &mut [f64]) {
        let n = self.panels.len();
        for v in &mut y[n..] {
            *v = 0.0;
        }
        for (j, p) in self.panels.iter().enumerate() {
            let r = self.ring_of[j];
            let row = if r == 0 { n + self.holes } else { n + r - 1 };
            y[row] += 2.0 * p.half / self.mean * x[j];
        }
    }

    /// `y = A x` (module docs) on one thread.
    #[cfg(test)]
    fn apply(&self, x: &[f64], y: &mut [f64], scratch: &mut Scratch) {
        self.far_part(x, (1.0, PRODUCT_TOLERANCE), scratch);
        for (i, yi) in y[..self.panels.len()].iter_mut().enumerate() {
            *yi = self.collocation_row(i, x, self.near.add_row(i, x, scratch.1[i]));
        }
        self.charge_rows(x, y);
    }

    /// `y_c = A x_c` for one or two products `(x_c, y_c, relaxation_c)`, on two threads: the
    /// far parts one per thread (each within its relaxation times [`PRODUCT_TOLERANCE`], at
    /// most `loosest`), then the collocation rows halved between them, the near block read
    /// once for both vectors ([`NearMatrix::add_row2`]). Unrelaxed (1), each `y_c` is
    /// [`System::apply`]'s bit for bit (the same sums in the same order).
    fn apply_pair(&self, products: &mut [Product<'_>], loosest: f64, scratch: &mut [Scratch; 2]) {
        let n = self.panels.len();
        let [s0, s1] = scratch;
        match products {
            [(x0, _, r0)] => self.far_part(x0, (*r0, loosest), s0),
            [(x0, _, r0), (x1, _, r1)] => std::thread::scope(|scope| {
                let handle = scope.spawn(|| self.far_part(x1, (*r1, loosest), s1));
                self.far_part(x0, (*r0, loosest), s0);
                join(handle);
            }),
            _ => unreachable!("one or two products"),
        }
        let (f0, f1) = (&s0.1, &s1.1);
        let half = n / 2;
        let rows = |start: usize, ys: &mut [&mut [f64]], xs: &[&[f64]]| match (ys, xs) {
            ([y0], [x0]) => {
                for (k, y) in y0.iter_mut().enumerate() {
                    let i = start + k;
                    *y = self.collocation_row(i, x0, self.near.add_row(i, x0, f0[i]));
                }
            }
            ([y0, y1], [x0, x1]) => {
                for (k, (a, b)) in y0.iter_mut().zip(y1.iter_mut()).enumerate() {
                    let i = start + k;
                    let [p, q] = self.near.add_row2(i, [x0, x1], [f0[i], f1[i]]);
                    *a = self.collocation_row(i, x0, p);
                    *b = self.collocation_row(i, x1, q);
                }
            }
            _ => unreachable!("one or two products"),
        };
        let xs: Vec<&[f64]> = products.iter().map(|(x, _, _)| *x).collect();
        let (mut low, mut high): (Vec<&mut [f64]>, Vec<&mut [f64]>) = products
            .iter_mut()
            .map(|(_, y, _)| y[..n].split_at_mut(half))
            .unzip();
        std::thread::scope(|scope| {
            let handle = scope.spawn(|| rows(half, &mut high, &xs));
            rows(0, &mut low, &xs);
            join(handle);
        });
        for (x, y, _) in products.iter_mut() {
            self.charge_rows(x, y);
        }
    }
}

/// One product `y = A x` of [`System::apply_pair`]: `(x, y, relaxation)`, the far part within
/// `relaxation` times [`PRODUCT_TOLERANCE`] ([`Gmres::relaxation`]).
type Product<'a> = (&'a [f64], &'a mut [f64], f64);

/// A product's buffers: the far field's weights and its values at the collocation points.
type Scratch = (Vec<f64>, Vec<f64>);

/// `f` of the two halves of `0..n`, the second on another thread: `[f(0..n/2), f(n/2..n)]`.
fn halves<T: Send>(n: usize, f: impl Fn(Range<usize>) -> T + Sync) -> [T; 2] {
    std::thread::scope(|scope| {
        let handle = scope.spawn(|| f(n / 2..n));
        let first = f(0..n / 2);
        [first, join(handle)]
    })
}

/// Joins a scoped thread, re-raising its panic here.
fn join<T>(handle: std::thread::ScopedJoinHandle<'_, T>) -> T {
    handle
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e))
}

/// `W_j(c_i)` of the dense matrix (`crate::map`'s entry, bit for bit).
fn entry(panels: &[Panel], i: usize, j: usize) -> f64 {
    let (p, q) = (&panels[i], &panels[j]);
    let dx = p.centre[0] - q.centre[0];
    let dy = p.centre[1] - q.centre[1];
    let xo = dx * q.tangent[0] + dy * q.tangent[1];
    let yo = -dx * q.tangent[1] + dy * q.tangent[0];
    let yo = if i == j { 0.0 } else { yo };
    kernel::element(xo, yo, q.half).w
}

/// The closed form on one near piece of element `piece.source` at normalised point `z`
/// (`crate::map`'s near pieces, the same snapping of the ends).
pub(crate) fn piece_value(panels: &[Panel], z: [f64; 2], piece: &Piece) -> f64 {
    let Some(p) = panels.get(piece.source) else {
        return 0.0;
    };
    let Source::Segment(s0, s1) = piece.shape else {
        return 0.0;
    };
    let (tx, ty) = (p.tangent[0], p.tangent[1]);
    let dx = z[0] - p.centre[0];
    let dy = z[1] - p.centre[1];
    let xo = dx * tx + dy * ty;
    let yo = -dx * ty + dy * tx;
    let snap = 16.0 * f64::EPSILON;
    let along = |s: C64| {
        let t = (s.re - p.centre[0]) * tx + (s.im - p.centre[1]) * ty;
        if (t + p.half).abs() <= snap {
            -p.half
        } else if (t - p.half).abs() <= snap {
            p.half
        } else {
            t
        }
    };
    let (t0, t1) = (along(s0), along(s1));
    if t1 <= t0 {
        return 0.0;
    }
    kernel::interval(xo, yo, t0, t1).0.w
}

fn assemble<'a>(
    panels: &'a [Panel],
    ranges: &[Range<usize>],
    mean: f64,
) -> Result<System<'a>, FmmError> {
    let n = panels.len();
    let ring_of: Vec<usize> = ranges
        .iter()
        .enumerate()
        .flat_map(|(r, range)| std::iter::repeat_n(r, range.len()))
        .collect();
    let sources: Vec<Source> = panels
        .iter()
        .map(|p| {
            let c = C64::new(p.centre[0], p.centre[1]);
            let t = C64::new(p.tangent[0], p.tangent[1]);
            Source::Segment(c - t * p.half, c + t * p.half)
        })
        .collect();
    let targets: Vec<C64> = panels
        .iter()
        .map(|p| C64::new(p.centre[0], p.centre[1]))
        .collect();
    let options = FmmOptions {
        tolerance: PRODUCT_TOLERANCE,
        leaf_size: LEAF_SIZE,
        max_level: 8,
        region: None,
    };
    let far = Operator::new(&sources, &targets, &options)?;
    // The near matrix, rows by collocation point: each half of the rows on its own thread
    // (each row is computed alone, so the matrix is the one-thread matrix bit for bit).
    let rows = |range: Range<usize>| -> NearMatrix {
        let mut block = NearMatrix::new();
        let mut cols = Vec::new();
        let mut vals = Vec::new();
        let mut acc = vec![0.0; n];
        let mut mark = vec![usize::MAX; n];
        let mut touched: Vec<usize> = Vec::new();
        for i in range {
            let p = &panels[i];
            far.near(i, |piece| {
                let j = piece.source;
                if mark[j] != i {
                    mark[j] = i;
                    touched.push(j);
                }
                acc[j] += piece_value(panels, p.centre, piece);
            });
            touched.sort_unstable();
            cols.clear();
            vals.clear();
            for &j in &touched {
                cols.push(j as u32);
                vals.push(acc[j]);
                acc[j] = 0.0;
            }
            block.push_row(&cols, &vals);
            touched.clear();
        }
        block
    };
    let [mut near, second] = halves(n, rows);
    near.append(second);
    Ok(System {
        panels,
        ring_of,
        holes: ranges.len() - 1,
        mean,
        far,
        near,
    })
}

/// The two-level preconditioner of the module docs.
struct Preconditioner {
    n: usize,
    holes: usize,
    clusters: Vec<Range<usize>>,
    local: Vec<PartialPivLu<f64>>,
    coarse: PartialPivLu<f64>,
}

impl Preconditioner {
    fn new(system: &System<'_>, ranges: &[Range<usize>]) -> Self {
        let panels = system.panels;
        let n = panels.len();
        let holes = system.holes;
        let mean = system.mean;
        // Clusters of at most b consecutive elements of one ring, b chosen so that the coarse
        // matrix stays near 1 500 unknowns.
        let b = (n.div_ceil(1500)).max(32);
        let mut clusters = Vec::new();
        let mut cluster_ring = Vec::new();
        for (r, range) in ranges.iter().enumerate() {
            let m = range.len();
            let parts = m.div_ceil(b).max(1);
            for k in 0..parts {
                let s = range.start + k * m / parts;
                let e = range.start + (k + 1) * m / parts;
                if e > s {
                    clusters.push(s..e);
                    cluster_ring.push(r);
                }
            }
        }
        let ell = |j: usize| 2.0 * panels[j].half / mean;
        let factor = |c: &Range<usize>| {
            let s = c.len();
            let m = Mat::<f64>::from_fn(s + 1, s + 1, |row, col| match (row < s, col < s) {
                (true, true) => entry(panels, c.start + row, c.start + col),
                (true, false) => 1.0,
                (false, true) => ell(c.start + col),
                (false, false) => 0.0,
            });
            m.partial_piv_lu()
        };
        // Each block alone, the halves on two threads: the one-thread blocks bit for bit.
        let local: Vec<PartialPivLu<f64>> = halves(clusters.len(), |range| {
            clusters[range].iter().map(factor).collect::<Vec<_>>()
        })
        .into_iter()
        .flatten()
        .collect();
        // Cluster centroids (length-weighted), lengths and radii.
        let nc = clusters.len();
        let mut centroid = Vec::with_capacity(nc);
        let mut length = Vec::with_capacity(nc);
        let mut radius = Vec::with_capacity(nc);
        for c in &clusters {
            let (mut sx, mut sy, mut l) = (0.0, 0.0, 0.0);
            for p in &panels[c.clone()] {
                let w = 2.0 * p.half;
                sx += w * p.centre[0];
                sy += w * p.centre[1];
                l += w;
            }
            let (cx, cy) = (sx / l, sy / l);
            let r = panels[c.clone()]
                .iter()
                .map(|p| (p.centre[0] - cx).hypot(p.centre[1] - cy) + p.half)
                .fold(0.0, f64::max);
            centroid.push([cx, cy]);
            length.push(l);
            radius.push(r);
        }
        let size = nc + holes + 1;
        let coarse_entry = |i: usize, j: usize| {
            let d = (centroid[i][0] - centroid[j][0]).hypot(centroid[i][1] - centroid[j][1]);
            if d > 3.0 * (radius[i] + radius[j]) {
                length[j] * (d * d).ln()
            } else {
                // Exact on the diagonal; between near clusters the mean over at most
                // eight evenly spaced rows of I (a preconditioner needs no more).
                let ci = clusters[i].clone();
                let rows = if i == j { ci.len() } else { ci.len().min(8) };
                let mut s = 0.0;
                for k in 0..rows {
                    let ii = ci.start + k * ci.len() / rows;
                    for jj in clusters[j].clone() {
                        s += entry(panels, ii, jj);
                    }
                }
                s / rows as f64
            }
        };
        // The cluster rows of A_c, the halves on two threads (each entry alone).
        let rows: Vec<f64> = halves(nc, |range| {
            range
                .flat_map(|i| (0..nc).map(move |j| (i, j)))
                .map(|(i, j)| coarse_entry(i, j))
                .collect::<Vec<_>>()
        })
        .concat();
        let mut ac = Mat::<f64>::zeros(size, size);
        for i in 0..nc {
            for j in 0..nc {
                ac[(i, j)] = rows[i * nc + j];
            }
            let r = cluster_ring[i];
            if r > 0 {
                ac[(i, nc + r - 1)] = -1.0;
            }
            ac[(i, size - 1)] = 1.0;
            let row = if r == 0 { size - 1 } else { nc + r - 1 };
            ac[(row, i)] = clusters[i].clone().map(ell).sum::<f64>();
        }
        Self {
            n,
            holes,
            clusters,
            local,
            coarse: ac.partial_piv_lu(),
        }
    }

    /// `z = M⁻¹ r`.
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        let n = self.n;
        let nc = self.clusters.len();
        let mut rc = Mat::<f64>::zeros(nc + self.holes + 1, 1);
        for (i, c) in self.clusters.iter().enumerate() {
            rc[(i, 0)] = r[c.clone()].iter().sum::<f64>() / c.len() as f64;
        }
        for k in 0..=self.holes {
            rc[(nc + k, 0)] = r[n + k];
        }
        let yc = self.coarse.solve(&rc);
        for (i, c) in self.clusters.iter().enumerate() {
            let s = c.len();
            let mut rl = Mat::<f64>::zeros(s + 1, 1);
            for (k, j) in c.clone().enumerate() {
                rl[(k, 0)] = r[j];
            }
            let x = self.local[i].solve(&rl);
            for (k, j) in c.clone().enumerate() {
                z[j] = yc[(i, 0)] + x[(k, 0)];
            }
        }
        for k in 0..=self.holes {
            z[n + k] = yc[(nc + k, 0)];
        }
    }
}

/// Solves the system of `crate::map` for both right-hand sides (`rhs[c][i]`, rows as the
/// dense matrix's) iteratively; returns the solutions (unknowns as the dense solve's columns)
/// and the statistics.
pub(crate) fn solve(
    panels: &[Panel],
    ranges: &[Range<usize>],
    mean: f64,
    rhs: [&[f64]; 2],
) -> Result<([Vec<f64>; 2], Stats), FmmError> {
    solve_relaxed(panels, ranges, mean, rhs, RELAXED_TOLERANCE)
}

/// [`solve`] with the loosest product tolerance `loosest` ([`PRODUCT_TOLERANCE`]: no
/// relaxation).
fn solve_relaxed(
    panels: &[Panel],
    ranges: &[Range<usize>],
    mean: f64,
    rhs: [&[f64]; 2],
    loosest: f64,
) -> Result<([Vec<f64>; 2], Stats), FmmError> {
    let clock = std::time::Instant::now();
    let system = assemble(panels, ranges, mean)?;
    let pre = Preconditioner::new(&system, ranges);
    let assembly = clock.elapsed();
    let size = system.size();
    let mut stats = Stats {
        assembly,
        ..Stats::default()
    };
    // The two components side by side: each solver's preconditioner and Arnoldi step on its
    // own thread, then both products in one pass over the near block (`System::apply_pair`).
    let mut solvers = rhs.map(|b| Gmres::new(b, GMRES_TOLERANCE));
    let mut scratch: [Scratch; 2] = Default::default();
    loop {
        let [a, b] = &mut solvers;
        let asked = std::thread::scope(|scope| {
            let handle = scope.spawn(|| b.advance(|r, z| pre.apply(r, z)));
            let first = a.advance(|r, z| pre.apply(r, z));
            [first, join(handle)]
        });
        let mut products: Vec<Product<'_>> = Vec::with_capacity(2);
        for (solver, asked) in solvers.iter_mut().zip(asked) {
            if asked {
                let relaxation = solver.relaxation();
                let (x, y) = solver.input_output();
                products.push((x, y, relaxation));
            }
        }
        if products.is_empty() {
            break;
        }
        system.apply_pair(&mut products, loosest, &mut scratch);
    }
    let [(xu, iu), (xv, iv)] = solvers.map(Gmres::finish);
    // The true residuals, from a last product of each solution.
    let (mut yu, mut yv) = (vec![0.0; size], vec![0.0; size]);
    system.apply_pair(
        &mut [(&xu, &mut yu, 1.0), (&xv, &mut yv, 1.0)],
        loosest,
        &mut scratch,
    );
    let relative = |y: &[f64], b: &[f64]| {
        let num: f64 = y.iter().zip(b).map(|(a, b)| (a - b) * (a - b)).sum();
        let den: f64 = b.iter().map(|b| b * b).sum();
        let rel = if den > 0.0 {
            (num / den).sqrt()
        } else {
            num.sqrt()
        };
        if rel.is_finite() { rel } else { f64::INFINITY }
    };
    let u = (xu, iu, relative(&yu, rhs[0]));
    let v = (xv, iv, relative(&yv, rhs[1]));
    stats.iterations = u.1 + v.1;
    stats.residual = u.2.max(v.2);
    let out = [u.0, v.0];
    Ok((out, stats))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Panels along a polygon's edges, `per_edge` a side, in the order of its vertices.
    fn ring(vertices: &[[f64; 2]], per_edge: usize) -> Vec<Panel> {
        let mut panels = Vec::new();
        for (e, a) in vertices.iter().enumerate() {
            let b = vertices[(e + 1) % vertices.len()];
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let length = dx.hypot(dy);
            for k in 0..per_edge {
                let t = (k as f64 + 0.5) / per_edge as f64;
                panels.push(Panel {
                    centre: [a[0] + t * dx, a[1] + t * dy],
                    tangent: [dx / length, dy / length],
                    half: 0.5 * length / per_edge as f64,
                    ku: 0.0,
                    kv: 0.0,
                });
            }
        }
        panels
    }

    /// A room of 1 200 elements with two pillars: its panels, rings and mean length.
    fn pillared_room() -> (Vec<Panel>, [Range<usize>; 3], f64) {
        let mut panels = ring(&[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]], 250);
        let outer = panels.len();
        panels.extend(ring(
            &[[-0.5, -0.5], [-0.5, -0.2], [-0.2, -0.2], [-0.2, -0.5]],
            25,
        ));
        let first = panels.len();
        panels.extend(ring(&[[0.3, 0.3], [0.3, 0.6], [0.6, 0.6], [0.6, 0.3]], 25));
        let ranges = [0..outer, outer..first, first..panels.len()];
        let mean = panels.iter().map(|p| 2.0 * p.half).sum::<f64>() / panels.len() as f64;
        (panels, ranges, mean)
    }

    /// The two-thread product of one or two vectors is the one-thread product, bit for bit,
    /// on the pillared room (a far field of several levels).
    #[test]
    fn the_paired_product_is_the_single_one() {
        let (panels, ranges, mean) = pillared_room();
        let system = assemble(&panels, &ranges, mean).unwrap();
        assert!(system.far.levels() >= 3, "{} levels", system.far.levels());
        let size = system.size();
        let x0: Vec<f64> = (0..size).map(|i| (i as f64 * 0.731).sin()).collect();
        let x1: Vec<f64> = (0..size).map(|i| (i as f64 * 0.217).cos() - 0.3).collect();
        let mut scratch: [Scratch; 2] = Default::default();
        let single = |x: &[f64], scratch: &mut [Scratch; 2]| {
            let mut y = vec![0.0; size];
            system.apply(x, &mut y, &mut scratch[0]);
            y
        };
        let (r0, r1) = (single(&x0, &mut scratch), single(&x1, &mut scratch));
        let (mut y0, mut y1) = (vec![f64::NAN; size], vec![f64::NAN; size]);
        system.apply_pair(
            &mut [(&x0, &mut y0, 1.0), (&x1, &mut y1, 1.0)],
            RELAXED_TOLERANCE,
            &mut scratch,
        );
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&y0), bits(&r0));
        assert_eq!(bits(&y1), bits(&r1));
        let mut y = vec![f64::NAN; size];
        system.apply_pair(&mut [(&x1, &mut y, 1.0)], RELAXED_TOLERANCE, &mut scratch);
        assert_eq!(bits(&y), bits(&r1));
    }

    /// The relaxed solve (products down to 1e-6 as the residual falls) reaches the same true
    /// residual as the unrelaxed one, in as many iterations, and its solution is the
    /// unrelaxed one's to within the system's conditioning; it is not the same bits (the
    /// negative control that the lower orders are taken).
    #[test]
    fn the_relaxed_solve_keeps_the_residual() {
        let (panels, ranges, mean) = pillared_room();
        let outer = ranges[0].end;
        let size = panels.len() + ranges.len();
        let rhs = |f: fn(f64) -> f64| -> Vec<f64> {
            (0..size)
                .map(|i| {
                    if i < outer {
                        f(std::f64::consts::TAU * i as f64 / outer as f64)
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let (bu, bv) = (rhs(f64::cos), rhs(f64::sin));
        let (exact, plain) =
            solve_relaxed(&panels, &ranges, mean, [&bu, &bv], PRODUCT_TOLERANCE).unwrap();
        let (relaxed, stats) = solve_relaxed(&panels, &ranges, mean, [&bu, &bv], 1e-6).unwrap();
        assert!(
            plain.residual <= 1e-12 && stats.residual <= 1e-12,
            "{plain:?} {stats:?}"
        );
        assert!(
            stats.iterations <= plain.iterations + 2,
            "{stats:?} against {plain:?}"
        );
        let mut worst = 0.0_f64;
        for (a, b) in exact.iter().zip(&relaxed) {
            let scale = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for (x, y) in a.iter().zip(b) {
                worst = worst.max((x - y).abs() / scale);
            }
        }
        assert!(worst > 0.0 && worst <= 1e-8, "{worst:e}");
    }
}
