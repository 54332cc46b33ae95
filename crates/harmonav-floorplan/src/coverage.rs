//! [`CertifiedArea`]: how much of the robot's reachable free space the certified level `c_δ`
//! covers (issue 52), estimated on a grid.
//!
//! The *reachable free space* is the set of centres the robot of clearance `r` (radius +
//! margin) can take, joined to its start: the points inside the true walls at least `r` from
//! every wall and more than `r` from every true obstacle (the rule a file's starts obey), in
//! the component of the start. It is sampled at the centres of a square grid over the walls'
//! bounding box ([`area_cell`]); the component is the start's 4-connected component of the
//! free samples (the crate's one labelling of a mask, as for a map's pixels).
//!
//! A sample is *certified* when it lies in `W_δ` and `Θ < c_δ` or `Θ < c_s` there (compared
//! in `phi_k`, [`LayerLevel::holds`]): the continuous law's sublevel set through it stays
//! inside `W_δ`, where `H` is certified (docs/maths.md §13.5), or its slide along `∂W_δ`
//! cannot rest there (§13.9, when the level was found by `FloorField::certify_level`), so
//! convergence from it is proven. The
//! fraction is the certified samples over the reachable ones, an area fraction to the grid's
//! resolution (each sample stands for one cell). What is not certified is reported in two
//! parts: the layer between `r` and `δ` from the walls (where `Θ` is not defined, only when
//! `δ > r`), and the part of `W_δ` above the level.

use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::level::LayerLevel;
use crate::ros_map::grid::{NONE, components};
use crate::theta::FloorField;

/// The finest grid cell [`area_cell`] takes, m.
pub const MIN_AREA_CELL: f64 = 0.05;

/// The samples [`area_cell`] aims at, at most: about 3 s of `Θ` evaluations on one core at
/// 2 000 boundary elements, bounded on any map.
pub const MAX_AREA_SAMPLES: usize = 200_000;

/// The grid cell for a plan whose walls span `size` (m) and a robot of clearance `inflation`:
/// the finest of [`MIN_AREA_CELL`]`·2ⁿ` whose grid has at most `max_samples` samples, but no
/// larger than `inflation`, so that two neighbouring samples, both at least `inflation` from
/// every wall, cannot have a wall between them (a wall crossing their segment would be within
/// half a cell of one of them). For a robot much smaller than the plan's cell that bound would
/// exceed `16·max_samples`: the cell then stays at `√(area/(16·max_samples))`, and a wall
/// thinner than `cell − 2·inflation` may join two samples on the grid (the count is then an
/// estimate of the free space, not of the robot's component of it).
#[must_use]
pub fn area_cell(size: Vector2<f64>, inflation: f64, max_samples: usize) -> f64 {
    let area = size.x.max(0.0) * size.y.max(0.0);
    let most = max_samples.max(1) as f64;
    let mut cell = MIN_AREA_CELL;
    while area / (cell * cell) > most && cell < 1e9 {
        cell *= 2.0;
    }
    let cell = if inflation > 0.0 {
        cell.min(inflation)
    } else {
        cell
    };
    cell.max((area / (16.0 * most)).sqrt())
}

/// What [`FloorField::certified_area`] counted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CertifiedArea {
    /// The grid's cell, m (each sample stands for `cell²` of area).
    pub cell: f64,
    /// Samples in the robot's reachable free space (the start's component); 0 when no free
    /// sample lies within two cells of the start.
    pub reachable: usize,
    /// Of those, the samples in `W_δ` (at least `δ` from the walls shrunk by `s`), where `Θ`
    /// is defined.
    pub in_region: usize,
    /// Of those, the samples where [`LayerLevel::holds`]: convergence certified.
    pub certified: usize,
    /// Samples in `W_δ` where `Θ` could not be evaluated (counted as not certified).
    pub skipped: usize,
}

impl CertifiedArea {
    /// `certified / reachable`, in `[0, 1]` (0 with no reachable sample).
    #[must_use]
    pub fn fraction(&self) -> f64 {
        ratio(self.certified, self.reachable)
    }

    /// `in_region / reachable`: the part of the reachable free space in `W_δ` (below 1 only
    /// when `δ` exceeds radius + margin, or where `W_s`'s offset corners cut it).
    #[must_use]
    pub fn region_fraction(&self) -> f64 {
        ratio(self.in_region, self.reachable)
    }

    /// `(reachable − in_region) / reachable`: the uncertified part in the layer, where `Θ` is
    /// not defined.
    #[must_use]
    pub fn layer_fraction(&self) -> f64 {
        ratio(self.reachable - self.in_region, self.reachable)
    }

    /// `(in_region − certified) / reachable`: the uncertified part in `W_δ`, at or above the
    /// level (or not evaluated).
    #[must_use]
    pub fn above_level_fraction(&self) -> f64 {
        ratio(self.in_region - self.certified, self.reachable)
    }

    /// The reachable free area, m² (`reachable · cell²`).
    #[must_use]
    pub fn reachable_area(&self) -> f64 {
        self.reachable as f64 * self.cell * self.cell
    }
}

fn ratio(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        part as f64 / whole as f64
    }
}

/// The free sample nearest to `start` within two cells of it, if any.
fn nearest_free(
    free: &[bool],
    nx: usize,
    ny: usize,
    at: impl Fn(usize, usize) -> Vector2<f64>,
    start: Vector2<f64>,
    origin: Vector2<f64>,
    cell: f64,
) -> Option<usize> {
    let g = (start - origin) / cell;
    if !(g.x.is_finite() && g.y.is_finite()) {
        return None;
    }
    let (ci, cj) = (g.x.floor() as i64, g.y.floor() as i64);
    let mut best: Option<(f64, usize)> = None;
    for j in cj - 2..=cj + 2 {
        for i in ci - 2..=ci + 2 {
            if i < 0 || j < 0 || i as usize >= nx || j as usize >= ny {
                continue;
            }
            let n = j as usize * nx + i as usize;
            let d = (at(i as usize, j as usize) - start).norm();
            if free[n] && best.is_none_or(|(b, _)| d < b) {
                best = Some((d, n));
            }
        }
    }
    best.map(|(_, n)| n)
}

/// The robot's reachable free space sampled on a grid ([`FloorField::reachable_region`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// The grid's cell, m (each sample stands for `cell²` of area).
    pub cell: f64,
    /// Samples in the robot's reachable free space (the start's component); 0 when no free
    /// sample lies within two cells of the start.
    pub reachable: usize,
    /// Of those, the samples in `W_δ`, where `Θ` is defined, in grid order.
    pub samples: Vec<Vector2<f64>>,
    /// The grid's corner, its columns and rows, and the index in `samples` of each grid cell
    /// (`usize::MAX` where it holds none), row-major.
    grid: (Vector2<f64>, usize, usize, Vec<usize>),
}

impl Region {
    /// The index in [`Region::samples`] of the sample of `p`'s grid cell, if it has one.
    #[must_use]
    pub fn sample_at(&self, p: Vector2<f64>) -> Option<usize> {
        let (lo, nx, ny, index) = &self.grid;
        let g = (p - lo) / self.cell;
        if !(g.x >= 0.0 && g.y >= 0.0 && g.x < *nx as f64 && g.y < *ny as f64) {
            return None;
        }
        let n = index[g.y as usize * nx + g.x as usize];
        (n != usize::MAX).then_some(n)
    }
}

/// `judge` on each of `items`, split among `threads` threads (at least one), the results in
/// the items' order; an item whose thread failed gets `failed`. Deterministic: the results do
/// not depend on `threads`.
pub(crate) fn on_threads<T: Sync, R: Send + Clone>(
    items: &[T],
    threads: usize,
    failed: R,
    judge: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let chunk = items.len().div_ceil(threads.max(1)).max(1);
    let judge = &judge;
    std::thread::scope(|scope| {
        let handles: Vec<_> = items
            .chunks(chunk)
            .map(|part| {
                (
                    part.len(),
                    scope.spawn(move || part.iter().map(judge).collect::<Vec<R>>()),
                )
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|(n, h)| h.join().unwrap_or_else(|_| vec![failed.clone(); n]))
            .collect()
    })
}

impl FloorField {
    /// The robot's reachable free space (module docs): the free space of clearance
    /// `inflation` (radius + margin) about the true walls and `obstacles` (as given, not
    /// grown), the component of `start`, sampled at the centres of a grid of cell
    /// [`area_cell`]`(·, inflation, max_samples)`; its samples in `W_δ` are kept.
    #[must_use]
    pub fn reachable_region(
        &self,
        start: Vector2<f64>,
        inflation: f64,
        obstacles: &[StarShape],
        max_samples: usize,
    ) -> Region {
        let floor = self.floor();
        let (lo, hi) = floor.walls().bounding_box();
        let cell = area_cell(hi - lo, inflation, max_samples);
        let nx = ((hi.x - lo.x) / cell).ceil().max(1.0) as usize;
        let ny = ((hi.y - lo.y) / cell).ceil().max(1.0) as usize;
        let at = |i: usize, j: usize| lo + Vector2::new(i as f64 + 0.5, j as f64 + 0.5) * cell;
        let free: Vec<bool> = (0..nx * ny)
            .map(|n| {
                let p = at(n % nx, n / nx);
                floor.wall_distance(p) >= inflation
                    && floor.walls().contains(p)
                    && obstacles.iter().all(|o| o.signed_distance(p) > inflation)
            })
            .collect();
        let mut out = Region {
            cell,
            reachable: 0,
            samples: Vec::new(),
            grid: (lo, nx, ny, vec![usize::MAX; nx * ny]),
        };
        let Some(seed) = nearest_free(&free, nx, ny, at, start, lo, cell) else {
            return out;
        };
        let (label, _) = components(&free, nx, ny, false);
        let mine = label[seed];
        for n in (0..nx * ny).filter(|&n| mine != NONE && label[n] == mine) {
            out.reachable += 1;
            let p = at(n % nx, n / nx);
            if floor.clearance(p) >= 0.0 {
                out.grid.3[n] = out.samples.len();
                out.samples.push(p);
            }
        }
        out
    }

    /// The certified fraction of the robot's reachable free space (module docs): each sample
    /// of [`FloorField::reachable_region`] in `W_δ` is evaluated (`Θ` of this field) against
    /// `level`. The evaluations run on `threads` threads (at least one). Deterministic: the
    /// counts do not depend on `threads`.
    #[must_use]
    pub fn certified_area(
        &self,
        level: &LayerLevel,
        start: Vector2<f64>,
        inflation: f64,
        obstacles: &[StarShape],
        max_samples: usize,
        threads: usize,
    ) -> CertifiedArea {
        let region = self.reachable_region(start, inflation, obstacles, max_samples);
        // Θ at each sample of W_δ: Some(certified) or None (not evaluated).
        let judged = on_threads(&region.samples, threads, None, |&p| {
            self.eval(p).ok().map(|e| level.holds(e.phi))
        });
        CertifiedArea {
            cell: region.cell,
            reachable: region.reachable,
            in_region: region.samples.len(),
            certified: judged.iter().filter(|j| **j == Some(true)).count(),
            skipped: judged.iter().filter(|j| j.is_none()).count(),
        }
    }
}
