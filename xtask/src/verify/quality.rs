//! The motion-quality benchmark's targets (`docs/benchmarks.md`), one check per `k` policy, on
//! the kinematic law: every run arrives with every guarantee held; under the default policy
//! the path is near-shortest (median ≤ 1.05, p90 ≤ 1.15 of the shortest path, per obstacle count
//! and sensing) and the margin cells keep their clearance.

use harmonav_field::KPolicy;
use harmonav_sim::quality::{CellStats, run_plan};
use harmonav_sim::run::MARGIN_TOLERANCE;
use harmonav_sim::scenario::Model;

use super::{Check, Outcome, outcome};
use crate::quality::{WORLDS, plan};

/// Path / shortest targets of the default policy: median and 90th percentile.
const MEDIAN: f64 = 1.05;
const P90: f64 = 1.15;

pub fn checks() -> Vec<Check> {
    KPolicy::ALL
        .into_iter()
        .map(|policy| {
            Check::new(format!("quality.kinematic.{policy}"), move || {
                quality(policy)
            })
            .early()
        })
        .collect()
}

fn quality(policy: KPolicy) -> Outcome {
    let stats = run_plan(&plan(&[Model::Kinematic], &[policy], WORLDS), 1)?;
    let mut failures = Vec::new();
    for s in &stats {
        let key = s.cell.key();
        if s.reached < s.runs || s.guarantees_held < s.runs || s.collisions > 0 {
            failures.push(format!(
                "{key}: {}/{} arrived, {}/{} held every guarantee, {} collisions",
                s.reached, s.runs, s.guarantees_held, s.runs, s.collisions
            ));
        }
        if s.min_clearance < s.cell.margin - MARGIN_TOLERANCE {
            failures.push(format!(
                "{key}: clearance {:.4} m below the margin",
                s.min_clearance
            ));
        }
        let near_shortest = s.ratio[0] <= MEDIAN && s.ratio[1] <= P90;
        if policy == KPolicy::default() && !near_shortest {
            failures.push(format!(
                "{key}: path/shortest median {:.3}, p90 {:.3} (targets {MEDIAN}, {P90})",
                s.ratio[0], s.ratio[1]
            ));
        }
    }
    let worst = |f: fn(&CellStats) -> f64| stats.iter().map(f).fold(0.0, f64::max);
    outcome(
        failures.is_empty(),
        format!(
            "{} cells × {WORLDS} worlds: path/shortest median ≤ {:.3}, p90 ≤ {:.3}, max {:.3}; \
             min clearance {:.4} m{}",
            stats.len(),
            worst(|s| s.ratio[0]),
            worst(|s| s.ratio[1]),
            worst(|s| s.ratio[2]),
            stats
                .iter()
                .map(|s| s.min_clearance)
                .fold(f64::INFINITY, f64::min),
            if failures.is_empty() {
                String::new()
            } else {
                format!("; FAILED {}", failures.join("; "))
            }
        ),
    )
}
