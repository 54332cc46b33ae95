//! `cargo xtask bench --only many`: the cost of many obstacles (issue 27, item 3), direct
//! loops and the spatial index side by side in one run (docs/benchmarks.md, "Many obstacles").
//!
//! Worlds: [`random::scattered`], a disc of radius 50 m (100 m across) with M = 100, 300 and
//! 1 000 obstacles of the four shapes, every obstacle known (global sensing). Figures, each the
//! median of repeated batches:
//!
//! - `many_theta_ns_m{M}_{direct,indexed}`: one `Field::eval` (`Θ`, `∇Θ`) at a free point;
//!   `..._direct_sum`: the same without the point world's multipole tree (docs/maths.md §15);
//! - `many_command_ns_m{M}`: one `Navigator::command` (kinematic law, the default hold) at a
//!   free point (the navigator's workspace is always indexed: its API has no lookup);
//! - `many_workspace_us_m{M}_{direct,indexed}`: `Workspace::new` over the M shapes;
//! - `many_field_us_m{M}_{direct,indexed}`: `Field::all_known` on that workspace;
//! - `many_add_obstacle_us_m{M}`: one `Navigator::add_obstacle` with M − 1 obstacles known
//!   (navigators of their own); `..._clone`: the same in clones of one navigator (the first
//!   discovery of a clone copies the shared workspace and multipole tree);
//!   `many_add_obstacle_mean_us_m{M}`: the mean of the M − 1 discoveries from none (amortised);
//! - `many_census_ms_m{M}_{direct,indexed}`: one `Field::census` (one run); and
//!   `many_census_ms_m2000[_paper]` (indexed; default `k` and `k = M + 1`), issue 27's
//!   census target, with the number of true saddles found.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use harmonav::{Law, Navigator, Options};
use harmonav_field::{Field, KPolicy};
use harmonav_transform::random::{self, Kind, Rng, Scattered};
use harmonav_transform::{Lookup, Workspace};

use crate::bench::median_ns;

/// The world radius of the many-obstacle benchmark, m.
const RADIUS: f64 = 50.0;

/// The obstacle counts of the per-call figures.
const COUNTS: [usize; 3] = [100, 300, 1000];

/// The world of `m` obstacles (seed `m`).
fn world(m: usize) -> Scattered {
    let kinds = [Kind::Circle, Kind::Ellipse, Kind::Polygon, Kind::Star];
    random::scattered(&mut Rng::new(m as u64), RADIUS, m, &kinds, 0.3)
        .expect("the benchmark world has room for its obstacles")
}

/// 1024 seeded free points of `ws`.
fn free_points(ws: &Workspace) -> Vec<harmonav_potential::Vector2<f64>> {
    let mut rng = Rng::new(7);
    (0..1024)
        .map(|_| random::free_point(&mut rng, ws, 1e-3))
        .collect()
}

/// The median of `samples` runs of `f`, µs.
fn median_us(samples: usize, mut f: impl FnMut()) -> f64 {
    median_ns(samples, 1e3, &mut f)
}

/// The obstacle count of issue 27's census target (≤ 2 s).
const CENSUS_COUNT: usize = 2000;

/// Every figure of this module, through `put(name, value)`.
pub fn figures(put: &mut dyn FnMut(&str, f64)) {
    census_figure(put);
    for m in COUNTS {
        let w = world(m);
        let samples = if m >= 1000 { 5 } else { 11 };
        for (name, lookup) in [("direct", Lookup::Direct), ("indexed", Lookup::Indexed)] {
            let build =
                || Workspace::with_lookup(w.boundary.clone(), w.obstacles.clone(), w.goal, lookup);
            put(
                &format!("many_workspace_us_m{m}_{name}"),
                median_us(samples, || {
                    black_box(build()).ok();
                }),
            );
            let ws = Arc::new(build().expect("valid benchmark world"));
            put(
                &format!("many_field_us_m{m}_{name}"),
                median_us(samples, || {
                    black_box(Field::all_known(ws.clone())).ok();
                }),
            );
            let field = Field::all_known(ws.clone()).expect("valid benchmark field");
            let pts = free_points(&ws);
            let reps = (20_000 / m).max(2);
            put(
                &format!("many_theta_ns_m{m}_{name}"),
                median_ns(11, (reps * pts.len()) as f64, || {
                    for _ in 0..reps {
                        for &x in &pts {
                            let _ = black_box(field.eval(black_box(x)));
                        }
                    }
                }),
            );
            // The point world's sum without its multipole tree, side by side (§15).
            let direct_sum = field.clone().without_far_field();
            put(
                &format!("many_theta_ns_m{m}_{name}_direct_sum"),
                median_ns(11, (reps * pts.len()) as f64, || {
                    for _ in 0..reps {
                        for &x in &pts {
                            let _ = black_box(direct_sum.eval(black_box(x)));
                        }
                    }
                }),
            );
            let t = Instant::now();
            let census = black_box(field.census());
            put(
                &format!("many_census_ms_m{m}_{name}"),
                t.elapsed().as_secs_f64() * 1e3,
            );
            put(&format!("many_census_saddles_m{m}"), census.saddles as f64);
        }
        // The navigator builds its workspace itself (always indexed: its API has no lookup).
        let ws = Workspace::new(w.boundary.clone(), w.obstacles.clone(), w.goal)
            .expect("valid benchmark world");
        let pts = free_points(&ws);
        let navigator = || {
            Navigator::new(
                w.boundary.clone(),
                w.goal,
                Law::kinematic(1.0),
                Options::default(),
            )
            .expect("valid benchmark navigator")
        };
        // Every discovery from none to M in one navigator: their mean is the amortised cost
        // (with the multipole tree's rebuilds at 128, 256, 512, … points).
        let mut nav = navigator();
        let t = Instant::now();
        for o in &w.obstacles[..m - 1] {
            nav.add_obstacle(o.clone())
                .expect("valid benchmark obstacle");
        }
        put(
            &format!("many_add_obstacle_mean_us_m{m}"),
            t.elapsed().as_secs_f64() * 1e6 / (m - 1) as f64,
        );
        let last = w.obstacles[m - 1].clone();
        let timed = |n: &mut Navigator| {
            let t = Instant::now();
            black_box(n.add_obstacle(last.clone())).ok();
            t.elapsed().as_nanos() as f64 / 1e3
        };
        let median = |mut times: Vec<f64>| {
            times.sort_by(f64::total_cmp);
            times[times.len() / 2]
        };
        // The M-th discovery in navigators of their own (as a robot's navigator is).
        let mut own: Vec<Navigator> = (0..samples)
            .map(|_| {
                let mut n = navigator();
                for o in &w.obstacles[..m - 1] {
                    n.add_obstacle(o.clone()).expect("valid benchmark obstacle");
                }
                n
            })
            .collect();
        put(
            &format!("many_add_obstacle_us_m{m}"),
            median(own.iter_mut().map(timed).collect()),
        );
        // The same in clones of one navigator: a clone shares the workspace and the multipole
        // tree, and its first discovery copies them (copy on write).
        let mut copies: Vec<Navigator> = (0..samples).map(|_| nav.clone()).collect();
        put(
            &format!("many_add_obstacle_us_m{m}_clone"),
            median(copies.iter_mut().map(timed).collect()),
        );
        let mut nav = copies.swap_remove(0);
        let reps = (2_000 / m).max(1);
        put(
            &format!("many_command_ns_m{m}"),
            median_ns(11, (reps * pts.len()) as f64, || {
                for _ in 0..reps {
                    for &x in &pts {
                        let v = harmonav_potential::Vector2::zeros();
                        let _ = black_box(nav.command(black_box(x), v));
                    }
                }
            }),
        );
    }
}

/// `many_census_ms_m2000[_paper]`: one `Field::census` of a world of [`CENSUS_COUNT`]
/// obstacles (issue 27's target: at most 2 s) under the default `k` policy and the paper's
/// `k = M + 1`, and `many_census_saddles_m2000[_paper]`: how many of its points are saddles
/// with finite eigenvalues of opposite signs (the count alone would be `M` whatever the roots).
fn census_figure(put: &mut dyn FnMut(&str, f64)) {
    let w = world(CENSUS_COUNT);
    let ws = Arc::new(
        Workspace::new(w.boundary.clone(), w.obstacles.clone(), w.goal)
            .expect("valid benchmark world"),
    );
    for (suffix, policy) in [("", KPolicy::Auto), ("_paper", KPolicy::Paper)] {
        let field = Field::all_known_with(ws.clone(), policy).expect("valid benchmark field");
        let t = Instant::now();
        let census = black_box(field.census());
        put(
            &format!("many_census_ms_m{CENSUS_COUNT}{suffix}"),
            t.elapsed().as_secs_f64() * 1e3,
        );
        let saddles = census
            .points
            .iter()
            .filter(|p| matches!(p.eigenvalues, Some([lo, hi]) if lo < 0.0 && hi > 0.0))
            .count();
        put(
            &format!("many_census_saddles_m{CENSUS_COUNT}{suffix}"),
            saddles as f64,
        );
    }
}
