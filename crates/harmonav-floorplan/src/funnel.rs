//! [`Funnels`]: sequential composition (Burridge, Rizzi & Koditschek, IJRR 1999) of the
//! certified sublevel sets of one floor plan's `Θ` towards several goals (issue 52,
//! docs/maths.md §13.10).
//!
//! `H` does not depend on the goal, so `Θ_g` towards any goal `g` of `W_δ` is a new
//! [`FloorField`] over the same solve. Funnel `i` is
//!
//! ```text
//! F_i = { x ∈ W_δ : phi_i(x) < ĉ_i },     ĉ_i = max(phi(c_δ), phi(c_s)) of Θ_i      (eq. funnel)
//! ```
//!
//! ([`LayerLevel::holds`]): from every point of `F_i` the continuous law on `Θ_i` converges to
//! `g_i` (§13.5, §13.9). The chain's rule: funnel 0 is the file's goal, and every other goal
//! lies inside an earlier funnel, its *parent*, with a margin:
//!
//! ```text
//! phi_{p(i)}(g_i) < ĉ_{p(i)} − FUNNEL_MARGIN,     p(i) < i                     (eq. chain)
//! ```
//!
//! The navigator runs `Θ_i` while in funnel `i` and switches to `p(i)` once the robot is in
//! `F_{p(i)}`. From a point of `F_i` the law converges to `g_i`, an interior point of the open
//! set `F_{p(i)}`, so it enters `F_{p(i)}` in finite time; each switch lowers the index, so
//! there are at most as many switches as the chain is deep, and convergence to the file's goal
//! is certified from every point of `∪ F_i` (no chatter: a switch never goes back).
//!
//! [`FloorField::funnels`] builds the chain greedily on the grid of
//! [`FloorField::reachable_region`]: the uncovered sample nearest the goal along the shortest
//! path ([`Geodesic`]) is walked towards the goal until it enters a funnel; the goal of the
//! next funnel is that point, on the frontier of the covered part (so the new funnel reaches
//! out from it), or with [`FunnelOptions::inward`] > 0 the point of largest clearance on the
//! next `inward` m of the walk inside that funnel.

use std::sync::Arc;

use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::coverage::{Region, on_threads};
use crate::geodesic::Geodesic;
use crate::level::{LayerLevel, LevelOptions};
use crate::theta::FloorField;

/// How far below its funnel's level `ĉ` (in `phi_k`) a goal of the chain lies (eq. chain),
/// and a robot must lie before it switches: a switch decided within rounding of the level
/// would not be one the certificate makes.
pub const FUNNEL_MARGIN: f64 = 1e-3;

/// Options of [`FloorField::funnels`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FunnelOptions {
    /// The most funnels, the file's goal's included (default 96: the office needs 62).
    pub max_funnels: usize,
    /// Stop once this fraction of the reachable samples is covered (default 0.99).
    pub target: f64,
    /// How far, m, past its entry into the funnels the walk looks for the next goal (the point
    /// of largest clearance; default 0: the entry itself, which measured best, docs/maths.md
    /// §13.10).
    pub inward: f64,
    /// The certificate of each funnel ([`FloorField::certify_level`]).
    pub level: LevelOptions,
    /// The samples of the reachable region, at most ([`crate::area_cell`]).
    pub max_samples: usize,
    /// Threads for the evaluations of the samples (at least one).
    pub threads: usize,
}

impl Default for FunnelOptions {
    fn default() -> Self {
        Self {
            max_funnels: 96,
            target: 0.99,
            inward: 0.0,
            level: LevelOptions {
                max_evaluations: 100_000,
                ..LevelOptions::default()
            },
            max_samples: crate::MAX_AREA_SAMPLES,
            threads: 1,
        }
    }
}

impl FunnelOptions {
    /// The default options with [`FunnelOptions::threads`] this machine's available
    /// parallelism, at most four (what a file's chain and Python's `funnels=True` use).
    #[must_use]
    pub fn on_this_machine() -> Self {
        Self {
            threads: std::thread::available_parallelism().map_or(1, |n| n.get().min(4)),
            ..Self::default()
        }
    }
}

/// One funnel of the chain: its goal, its field and its certified level.
#[derive(Clone, Debug)]
pub struct Funnel {
    /// `g_i`.
    pub goal: Vector2<f64>,
    /// The earlier funnel that holds `g_i` (eq. chain); `None` for the file's goal.
    pub parent: Option<usize>,
    /// `Θ_i` over the walls.
    pub field: FloorField,
    /// `c_δ` and `c_s` of `Θ_i`.
    pub level: LayerLevel,
    /// Reachable samples this funnel was the first to cover.
    pub covered: usize,
}

impl Funnel {
    /// `ĉ_i` of eq. funnel, in `phi_k`.
    #[must_use]
    pub fn phi_level(&self) -> f64 {
        self.level.phi_certified.max(self.level.phi_slide)
    }

    /// Whether `x` lies in the funnel at least [`FUNNEL_MARGIN`] below its level, `phi_i(x) <
    /// ĉ_i − FUNNEL_MARGIN` (false where `Θ_i` is not defined).
    #[must_use]
    pub fn holds(&self, x: Vector2<f64>) -> bool {
        self.field
            .eval(x)
            .is_ok_and(|e| e.phi < self.phi_level() - FUNNEL_MARGIN)
    }

    /// Whether `phi` (of `Θ_i`, or under the dynamic law of its energy) lies below the
    /// funnel's level less [`FUNNEL_MARGIN`].
    #[must_use]
    pub fn holds_phi(&self, phi: f64) -> bool {
        phi < self.phi_level() - FUNNEL_MARGIN
    }
}

/// The chain of [`FloorField::funnels`] and the part of the reachable region it covers.
#[derive(Clone, Debug)]
pub struct Funnels {
    /// Funnel 0 is the file's goal; every other one's parent comes before it.
    pub funnels: Vec<Arc<Funnel>>,
    /// The grid's cell, m.
    pub cell: f64,
    /// Samples in the reachable free space.
    pub reachable: usize,
    /// Of those, the samples in `W_δ`.
    pub in_region: usize,
    /// Of those, the samples in some funnel.
    pub certified: usize,
    /// The samples in `W_δ` that no funnel holds (`in_region − certified` of them): where
    /// convergence is not certified (with the reachable part of the layer, `reachable −
    /// in_region` samples, which the chain cannot hold).
    pub uncovered: Vec<Vector2<f64>>,
}

impl Funnels {
    /// `certified / reachable`, in `[0, 1]` (0 with no reachable sample).
    #[must_use]
    pub fn fraction(&self) -> f64 {
        if self.reachable == 0 {
            0.0
        } else {
            self.certified as f64 / self.reachable as f64
        }
    }

    /// The funnel of least index that holds `x` (`None` if none does).
    #[must_use]
    pub fn entry(&self, x: Vector2<f64>) -> Option<usize> {
        self.funnels.iter().position(|f| f.holds(x))
    }

    /// The most switches from a funnel to the file's goal ([`Funnels::depth`]; 0 for a chain
    /// of one).
    #[must_use]
    pub fn deepest(&self) -> usize {
        (0..self.funnels.len())
            .map(|i| self.depth(i))
            .max()
            .unwrap_or(0)
    }

    /// The depth of funnel `i`: the switches from it to the file's goal.
    #[must_use]
    pub fn depth(&self, mut i: usize) -> usize {
        let mut depth = 0;
        while let Some(p) = self.funnels.get(i).and_then(|f| f.parent) {
            i = p;
            depth += 1;
        }
        depth
    }
}

impl FloorField {
    /// The chain of funnels towards this field's goal over its walls (module docs): funnel 0
    /// is this field with `root` (its level, computed here when `None`), then greedily one
    /// more while fewer than `options.target` of the reachable samples are covered and fewer
    /// than `options.max_funnels` are built. Each new goal satisfies eq. chain (checked with
    /// [`Funnel::holds`]); a candidate whose field cannot be built or that covers no new sample
    /// is dropped. Deterministic: the chain does not depend on `options.threads`. The sensed
    /// obstacles are not in it: build it on the walls' field.
    #[must_use]
    pub fn funnels(
        &self,
        root: Option<LayerLevel>,
        start: Vector2<f64>,
        inflation: f64,
        obstacles: &[StarShape],
        options: &FunnelOptions,
    ) -> Funnels {
        let region: Region =
            self.reachable_region(start, inflation, obstacles, options.max_samples);
        let samples = &region.samples;
        let _memo = self.floor().remember_enclosures();
        let level = root.unwrap_or_else(|| self.certify_level(&options.level));
        let mut covered = vec![false; samples.len()];
        let mut chain: Vec<Arc<Funnel>> = Vec::new();
        let mut root = Funnel {
            goal: self.transform().goal(),
            parent: None,
            field: self.clone(),
            level,
            covered: 0,
        };
        root.covered = cover(&root, samples, &mut covered, options.threads);
        let mut count = root.covered;
        chain.push(Arc::new(root));
        let owned;
        let geodesic = match self.geodesic() {
            Some(g) => g,
            None => {
                owned = Geodesic::new(self.floor(), self.transform().goal());
                &owned
            }
        };
        // The samples by their distance to the goal along the shortest path (unreached last).
        let distance: Vec<f64> = samples
            .iter()
            .map(|&p| geodesic.distance(p).unwrap_or(f64::INFINITY))
            .collect();
        let mut order: Vec<usize> = (0..samples.len()).collect();
        order.sort_by(|&a, &b| distance[a].total_cmp(&distance[b]).then(a.cmp(&b)));
        let mut tried = vec![false; samples.len()];
        // The goals tried so far (the funnels' included).
        let mut goals: Vec<Vector2<f64>> = vec![self.transform().goal()];
        let wanted = (options.target.clamp(0.0, 1.0) * region.reachable as f64).ceil() as usize;
        // Every sample before `order[next]` is covered, tried or unreached.
        let mut next = 0;
        while chain.len() < options.max_funnels.max(1) && count < wanted {
            let Some(at) = order[next..]
                .iter()
                .position(|&s| !covered[s] && !tried[s] && distance[s].is_finite())
            else {
                break;
            };
            next += at;
            let s = order[next];
            tried[s] = true;
            let Some((goal, parent)) =
                self.next_goal(samples[s], &chain, geodesic, &region, &covered, options)
            else {
                continue;
            };
            // A goal within two cells of one already tried would give about its funnel.
            if goals.iter().any(|g| (g - goal).norm() < 2.0 * region.cell) {
                continue;
            }
            goals.push(goal);
            let Ok(field) = FloorField::new(self.floor().clone(), goal, self.k_policy()) else {
                continue;
            };
            let level = field.certify_level(&options.level);
            let mut funnel = Funnel {
                goal,
                parent: Some(parent),
                field,
                level,
                covered: 0,
            };
            // `cover` marks only what the funnel newly holds: with nothing, nothing changed.
            funnel.covered = cover(&funnel, samples, &mut covered, options.threads);
            if funnel.covered > 0 {
                count += funnel.covered;
                chain.push(Arc::new(funnel));
            }
        }
        Funnels {
            funnels: chain,
            cell: region.cell,
            reachable: region.reachable,
            in_region: samples.len(),
            certified: count,
            uncovered: samples
                .iter()
                .zip(&covered)
                .filter(|&(_, &c)| !c)
                .map(|(&p, _)| p)
                .collect(),
        }
    }

    /// The goal of the next funnel for the uncovered point `x`, and the funnel it lies in: the
    /// walk from `x` along the shortest path ([`Geodesic::heading_near`], steps of half a cell)
    /// to the first point whose grid sample is covered (or within two cells of a goal) and that
    /// a funnel holds
    /// ([`Funnel::holds`], the least such funnel), then on for `options.inward` m while that
    /// funnel holds it; of the points of the walk in the funnel, the one of largest clearance
    /// (the first on a tie). `None` if the walk never enters one.
    fn next_goal(
        &self,
        x: Vector2<f64>,
        chain: &[Arc<Funnel>],
        geodesic: &Geodesic,
        region: &Region,
        covered: &[bool],
        options: &FunnelOptions,
    ) -> Option<(Vector2<f64>, usize)> {
        let step = 0.5 * region.cell;
        let length = geodesic.distance(x)?;
        let steps = (2.0 * length / step).ceil() as usize + 16;
        let floor = self.floor();
        let mut p = x;
        let mut entered: Option<(Vector2<f64>, usize, f64)> = None;
        let mut walked_in = 0.0;
        for _ in 0..steps {
            match entered {
                None => {
                    // A covered sample, or near a goal (a funnel smaller than a cell may
                    // hold no sample).
                    let near = region.sample_at(p).is_some_and(|s| covered[s])
                        || chain
                            .iter()
                            .any(|f| (p - f.goal).norm() < 2.0 * region.cell);
                    if let Some(i) = near
                        .then(|| chain.iter().position(|f| f.holds(p)))
                        .flatten()
                    {
                        entered = Some((p, i, floor.clearance(p)));
                    }
                }
                Some((_, i, best)) => {
                    walked_in += step;
                    if walked_in > options.inward || !chain[i].holds(p) {
                        break;
                    }
                    let c = floor.clearance(p);
                    if c > best {
                        entered = Some((p, i, c));
                    }
                }
            }
            if entered.is_some() && options.inward <= 0.0 {
                break;
            }
            let Some(d) = geodesic.heading_near(p) else {
                break;
            };
            p += step * d;
        }
        entered.map(|(p, i, _)| (p, i))
    }
}

/// Marks the samples `funnel` holds ([`Funnel::holds_phi`], the rule by which a navigator
/// enters it) that no earlier funnel did; returns how many.
fn cover(funnel: &Funnel, samples: &[Vector2<f64>], covered: &mut [bool], threads: usize) -> usize {
    let open: Vec<usize> = (0..samples.len()).filter(|&s| !covered[s]).collect();
    let held = on_threads(&open, threads, false, |&s| {
        funnel
            .field
            .eval(samples[s])
            .is_ok_and(|e| funnel.holds_phi(e.phi))
    });
    let mut n = 0;
    for (&s, h) in open.iter().zip(held) {
        if h {
            covered[s] = true;
            n += 1;
        }
    }
    n
}
